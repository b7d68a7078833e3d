#!/usr/bin/env python3
"""Per-group figures of `facetool eval` on prepared UTKFace photos: PSNR and SSIM by race label, age and gender.

    python3 scripts/eval-groups.py EVAL/per_image.csv REAL/manifest.tsv > groups.md

per_image.csv is what `facetool eval` writes for a folder of real samples; manifest.tsv is what
`facetool prepare-real` wrote for that folder (sample file -> source photo). UTKFace names a photo
AGE_GENDER_RACE_DATE.jpg.chip.jpg (gender 0 male, 1 female; race 0 White, 1 Black, 2 Asian,
3 Indian, 4 other). The race label is the only skin-tone proxy the set carries. Prints Markdown:
one table per grouping with images, mean PSNR, its difference to the overall mean, mean SSIM and
the mean PSNR of the blurred photo (eval's --blur-sigma baseline; "-" from an older eval).
"""
import csv
import math
import os
import sys

RACES = ["White", "Black", "Asian", "Indian", "Other"]
GENDERS = ["male", "female"]
AGES = [(0, 9), (10, 19), (20, 39), (40, 59), (60, 200)]


def age_group(age):
    for low, high in AGES:
        if low <= age <= high:
            return f"{low}+" if high >= 200 else f"{low}-{high}"
    return "unknown"


def read_sources(manifest_path):
    sources = {}
    with open(manifest_path, newline="") as f:
        for line in f:
            if line.startswith("#") or line.startswith("file\t"):
                continue
            parts = line.rstrip("\n").split("\t")
            if len(parts) >= 3 and parts[2] in ("written", "kept"):
                sources[parts[0]] = os.path.basename(parts[1])
    return sources


def labels(photo_name):
    fields = photo_name.split("_")
    try:
        age, gender, race = int(fields[0]), int(fields[1]), int(fields[2])
    except (IndexError, ValueError):
        return None
    if not (0 <= gender < len(GENDERS) and 0 <= race < len(RACES)):
        return None
    return {"race label": RACES[race], "age": age_group(age), "gender": GENDERS[gender]}


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    per_image, manifest = sys.argv[1], sys.argv[2]
    sources = read_sources(manifest)
    rows = []
    with open(per_image, newline="") as f:
        for row in csv.DictReader(f):
            photo = sources.get(row["file"])
            psnr, ssim = float(row["psnr_db"]), float(row["ssim"])
            blurred = float(row.get("blurred_psnr_db") or "nan")
            if photo is None or not (math.isfinite(psnr) and math.isfinite(ssim)):
                continue
            group = labels(photo)
            if group is not None:
                rows.append((group, psnr, ssim, blurred))
    if not rows:
        sys.exit(f"eval-groups: no row of {per_image} matches a labelled photo of {manifest}")
    overall = sum(r[1] for r in rows) / len(rows)
    blurred = sum(r[3] for r in rows) / len(rows)
    print(f"Held-out real photos: {len(rows)}, mean PSNR {overall:.2f} dB, "
          f"mean SSIM {sum(r[2] for r in rows) / len(rows):.4f}"
          + (f", blurred photo's mean PSNR {blurred:.2f} dB" if math.isfinite(blurred) else "") + "\n")
    for grouping in ("race label", "age", "gender"):
        groups = {}
        for group, psnr, ssim, blurred in rows:
            groups.setdefault(group[grouping], []).append((psnr, ssim, blurred))
        print(f"| {grouping} | images | PSNR (dB) | vs mean | SSIM | blurred photo's PSNR (dB) |\n"
              "| --- | --- | --- | --- | --- | --- |")
        order = {"race label": RACES, "gender": GENDERS}.get(grouping)
        names = order if order else sorted(groups, key=lambda g: int(g.split("-")[0].rstrip("+")))
        for name in names:
            if name not in groups:
                continue
            values = groups[name]
            psnr = sum(v[0] for v in values) / len(values)
            ssim = sum(v[1] for v in values) / len(values)
            blurred = sum(v[2] for v in values) / len(values)
            blurred_text = f"{blurred:.2f}" if math.isfinite(blurred) else "-"
            print(f"| {name} | {len(values)} | {psnr:.2f} | {psnr - overall:+.2f} | {ssim:.4f} | {blurred_text} |")
        print()


if __name__ == "__main__":
    main()
