#!/usr/bin/env python3
"""Normal error of `facetool eval` on synthetic samples, broken down by light and by head pose.

    python3 scripts/eval-synthetic-breakdown.py EVAL/per_image.csv SAMPLES_DIR > breakdown.md

Reads each sample's light and pose (roll, pitch, yaw) from the folder's synth manifests
(manifest-*.tsv) and prints Markdown tables: per light, per |yaw| and per |pitch| bin, the images
and their mean per-image normal error, plus the eight worst samples with their light and pose.
"""
import csv
import glob
import os
import sys


def read_manifests(samples):
    found = {}
    for path in sorted(glob.glob(os.path.join(samples, "manifest-*.tsv"))):
        with open(path, newline="") as f:
            lines = [line for line in f if not line.startswith("#")]
        for row in csv.DictReader(lines, delimiter="\t"):
            found[row["file"]] = row
    return found


def table(title, rows, key_order=None):
    groups = {}
    for key, error in rows:
        groups.setdefault(key, []).append(error)
    print(f"| {title} | images | mean normal error (deg) |\n| --- | --- | --- |")
    for key in key_order or sorted(groups):
        if key in groups:
            values = groups[key]
            print(f"| {key} | {len(values)} | {sum(values) / len(values):.2f} |")
    print()


def bin_of(angle, edges):
    for low, high in zip(edges, edges[1:]):
        if low <= angle < high:
            return f"{low}-{high}"
    return f">= {edges[-1]}"


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    per_image, samples = sys.argv[1], sys.argv[2]
    manifest = read_manifests(samples)
    if not manifest:
        sys.exit(f"eval-synthetic-breakdown: no manifest-*.tsv in {samples} (written by facetool synth)")
    rows = []
    with open(per_image, newline="") as f:
        for row in csv.DictReader(f):
            info = manifest.get(row["file"])
            if row["ground_truth"] != "1" or info is None:
                continue
            roll, pitch, yaw = (abs(float(info[k])) for k in ("roll_deg", "pitch_deg", "yaw_deg"))
            rows.append((row["file"], float(row["normal_error_mean_deg"]), info["light_source"],
                         pitch, yaw, roll))
    if not rows:
        sys.exit(f"eval-synthetic-breakdown: no synthetic rows in {per_image}")
    table("light", [(r[2], r[1]) for r in rows])
    edges = [0, 10, 20, 30]
    order = ["0-10", "10-20", "20-30"]
    table("abs(yaw) deg", [(bin_of(r[4], edges), r[1]) for r in rows], order)
    table("abs(pitch) deg", [(bin_of(r[3], edges), r[1]) for r in rows], order)
    print("| worst samples | normal error (deg) | light | roll, pitch, yaw (abs, deg) |\n"
          "| --- | --- | --- | --- |")
    for r in sorted(rows, key=lambda r: -r[1])[:8]:
        print(f"| {r[0]} | {r[1]:.2f} | {r[2]} | {r[5]:.0f}, {r[3]:.0f}, {r[4]:.0f} |")


if __name__ == "__main__":
    main()
