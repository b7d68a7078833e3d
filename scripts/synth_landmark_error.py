#!/usr/bin/env python3
"""Landmark error of `facetool detect --report` CSVs on `facetool synth` samples, whose true 68 points are in their metadata.

    facetool synth --face-model DIR --lights HDRI_DIR --size 256 \\
        --framing "zoom 1.0 centre 0.5 0.5 border ring-mean" --directions 16 --count 1000 --seed 11 -o SAMPLES
    facetool detect SAMPLES --report REPORT.csv
    /usr/bin/python3 scripts/synth_landmark_error.py SAMPLES REPORT.csv [REPORT2.csv ...]

Per report: the mean error of the 51 inner points (17-67) over the inter-ocular distance (the
truth's outer eye corners 36 and 45, the 300-W convention) of each sample's first face, over all
samples and by |yaw| range with roll and pitch within 10 degrees (issue 22's goal), the faces the
CNN found apart, and the count of gross failures (over 15 %). Needs numpy and OpenImageIO's
Python module (Debian: python3-numpy, python3-openimageio).
"""
import csv
import os
import sys

import numpy as np
import OpenImageIO as oiio

GROSS = 0.15


def read_truth(folder):
    """{file name: (68 x 2 true points in pixels, (roll, pitch, yaw) degrees)} of the samples."""
    if not os.path.isdir(folder):
        sys.exit(f"{folder}: no such folder of synth samples")
    truth = {}
    for name in sorted(os.listdir(folder)):
        if not name.endswith(".exr"):
            continue
        image = oiio.ImageInput.open(os.path.join(folder, name))
        if image is None:
            sys.exit(f"{name}: cannot read: {oiio.geterror()}")
        spec = image.spec()
        image.close()
        points, pose = spec.getattribute("facetool:landmarks"), spec.getattribute("facetool:pose_deg")
        if points is None or pose is None:
            sys.exit(f"{name}: no facetool:landmarks or facetool:pose_deg: not a sample of today's `facetool synth`")
        truth[name] = (np.array([float(v) for v in points.split()]).reshape(68, 2),
                       tuple(float(v) for v in pose.split()))
    if not truth:
        sys.exit(f"{folder}: no .exr samples")
    return truth


def inner_error(points, truth):
    """Mean distance of the inner points over the inter-ocular distance."""
    iod = np.linalg.norm(truth[36] - truth[45])
    return float(np.linalg.norm(points[17:] - truth[17:], axis=1).mean() / iod)


def summary(errors):
    if not errors:
        return "none"
    e = np.array(errors)
    return (f"{len(e)}: inner {100 * e.mean():.2f} % (median {100 * np.median(e):.2f}), "
            f"over {100 * GROSS:.0f} %: {(e > GROSS).sum()}")


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    truth = read_truth(sys.argv[1])
    for report in sys.argv[2:]:
        try:
            with open(report) as f:
                reader = csv.DictReader(f)
                needed = {"photo", "face", "detector"} | {f"{a}{i}" for a in "xy" for i in range(68)}
                if not needed <= set(reader.fieldnames or []):
                    sys.exit(f"{report}: not a `facetool detect --report` CSV (missing columns)")
                rows = {os.path.basename(r["photo"]): r for r in reader if r["face"] == "0"}
        except OSError as e:
            sys.exit(f"{report}: cannot read: {e.strerror}")
        groups = {"all": [], "all, found by the CNN": [], "|yaw| 0-15, roll and pitch within 10": [],
                  "|yaw| 15-30, roll and pitch within 10": []}
        missed = 0
        for name, (t, (roll, pitch, yaw)) in truth.items():
            if name not in rows:
                missed += 1
                continue
            r = rows[name]
            e = inner_error(np.array([[float(r[f"x{i}"]), float(r[f"y{i}"])] for i in range(68)]), t)
            groups["all"].append(e)
            if r["detector"] == "cnn":
                groups["all, found by the CNN"].append(e)
            if abs(roll) <= 10 and abs(pitch) <= 10 and abs(yaw) <= 30:
                groups["|yaw| 0-15, roll and pitch within 10" if abs(yaw) < 15
                       else "|yaw| 15-30, roll and pitch within 10"].append(e)
        print(f"{report}: {len(truth) - missed} of {len(truth)} samples with a face")
        for label, errors in groups.items():
            print(f"  {label}: {summary(errors)}")


if __name__ == "__main__":
    main()
