#!/usr/bin/env bash
# facetool eval --shard i/n on three shards, merged with eval --merge, equals one unsharded eval;
# infer and pseudo-label --shard 0/2 and 1/2 into one folder write what one unsharded run writes
# (infer's contact sheets one per shard; photos named over the whole list);
# with MPIRUN, `mpirun -np 2 facetool train` logs the one-process run's losses (1e-5 relative).
# Usage: eval_shards_test.sh FACETOOL SHARED_DIR [MPIRUN]. Exits 77 (skip) without ../shared's
# face model.
set -euo pipefail
facetool=$1
shared=$2
mpirun=${3:-}
face="$shared/assets/ict-facekit/FaceXModel"
if [ ! -d "$face" ] || [ ! -d "$shared/assets/hdri" ]; then
  echo "skip: needs the ICT face model and HDRIs under $shared/assets"; exit 77
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
"$facetool" synth --face-model "$face" --lights "$shared/assets/hdri" --count 10 --size 32 \
  --directions 100 --threads 1 --out data >/dev/null 2>&1
cat > smoke.json <<'JSON'
{"name": "shards", "network": {"width": 4, "input_size": 32}, "steps": 2,
 "validation": {"holdout_every": 0}, "seed": 3, "sources": [{"name": "synthetic",
 "directory": "data", "batch": 4, "terms": {"albedo": 1, "normal": 0.2, "recon_albedo": 1}}]}
JSON
"$facetool" train --config smoke.json --out run 2>/dev/null
model=run/weights.safetensors
"$facetool" eval --model $model --data data -o whole --batch 3 >/dev/null 2>&1
for i in 0 1 2; do
  "$facetool" eval --model $model --data data -o shard$i --shard $i/3 --batch 3 >/dev/null 2>&1
done
[ "$(wc -l < shard1/per_image.csv)" -eq 4 ] || { echo "FAIL: shard 1/3 of 10 should hold 3 rows"; exit 1; }
"$facetool" eval --merge shard0 shard1 shard2 -o merged >/dev/null 2>&1
# Per-image rows: identical text (same network, same images; numbers printed exactly).
diff whole/per_image.csv merged/per_image.csv || { echo "FAIL: merged per_image.csv differs"; exit 1; }
# Summary: counts and per-image means equal; the pixel-level normal error mean and std, summed
# per image then over images instead of pixel by pixel, within 1e-12 relative.
python3 - whole/summary.json merged/summary.json <<'PY'
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
def walk(x, y, path):
    if isinstance(x, dict):
        assert set(x) == set(y), f"{path}: keys {sorted(x)} vs {sorted(y)}"
        for k in x: walk(x[k], y[k], f"{path}/{k}")
    elif isinstance(x, float) or isinstance(y, float):
        assert abs(x - y) <= 1e-12 * max(abs(x), abs(y), 1e-300), f"{path}: {x} vs {y}"
    else:
        assert x == y, f"{path}: {x} vs {y}"
walk(a, b, "summary")
assert "normal_error" in a, "no normal error in the summary"
PY
# A shard folder merged twice is refused.
if "$facetool" eval --merge shard0 shard0 -o twice 2>err.txt; then echo "FAIL: merged twice"; exit 1; fi
grep -q "is in two shards" err.txt || { cat err.txt; exit 1; }
echo "merged shards equal the unsharded eval"
# infer and pseudo-label: two shards into one folder equal one run (same names, same bytes);
# plain crops (infer's input.png) are named by their index in the whole list.
"$facetool" infer --aligned --model $model data/sample_*.exr -o inf --no-contact-sheet >/dev/null 2>&1
for i in 0 1; do
  "$facetool" infer --aligned --model $model data/sample_*.exr -o inf2 --no-contact-sheet --shard $i/2 >/dev/null 2>&1
done
diff -r inf inf2 || { echo "FAIL: sharded infer differs"; exit 1; }
for inputs in "data/sample_*.exr" "inf/*/input.png"; do
  rm -rf pl pl2
  "$facetool" pseudo-label --model $model $inputs -o pl >/dev/null 2>&1
  for i in 0 1; do
    "$facetool" pseudo-label --model $model $inputs -o pl2 --shard $i/2 >/dev/null 2>&1
  done
  [ "$(ls pl | wc -l)" -eq 10 ] || { echo "FAIL: pseudo-label wrote $(ls pl | wc -l) files"; exit 1; }
  diff -r pl pl2 || { echo "FAIL: sharded pseudo-label of $inputs differs"; exit 1; }
done
# With their contact sheets: each shard writes its own sheet, none overwrites contact_sheet.png.
for i in 0 1; do
  "$facetool" infer --aligned --model $model data/sample_*.exr -o inf3 --shard $i/2 >/dev/null 2>&1
done
[ -s inf3/contact_sheet-0-of-2.png ] && [ -s inf3/contact_sheet-1-of-2.png ] && [ ! -e inf3/contact_sheet.png ] ||
  { ls inf3; echo "FAIL: sharded infer's contact sheets"; exit 1; }
diff -r -x 'contact_sheet*' inf inf3 || { echo "FAIL: sharded infer with sheets differs"; exit 1; }
# Photos: two files named alike in two folders keep the whole list's names (x, x_2) in any shard.
examples=$(cd "$(dirname "$0")/../../examples/photos" && pwd)
if [ -e /usr/share/dlib/shape_predictor_68_face_landmarks.dat ] && [ -e "$examples/astronaut.png" ]; then
  mkdir -p p1 p2
  cp "$examples/astronaut.png" p1/x.png
  cp "$examples/astronaut.png" p2/x.png
  for i in 0 1; do
    "$facetool" infer --model $model p1/x.png p2/x.png -o photos --shard $i/2 --no-contact-sheet >/dev/null 2>&1
  done
  [ -s photos/x/photo.exr ] && [ -s photos/x_2/photo.exr ] ||
    { ls photos; echo "FAIL: sharded photo names"; exit 1; }
  "$facetool" infer --model $model p1/x.png p2/x.png -o photos1 --no-contact-sheet >/dev/null 2>&1
  diff -r photos photos1 || { echo "FAIL: sharded photos differ from one run"; exit 1; }
fi
echo "sharded infer and pseudo-label equal unsharded runs"
[ -n "$mpirun" ] || { echo "no mpirun: the 2-rank command-line run is not checked"; exit 0; }
"$mpirun" --allow-run-as-root --oversubscribe -np 2 "$facetool" train --config smoke.json \
  --out run2 2>/dev/null
for f in checkpoint.safetensors weights.safetensors log.jsonl loss.png; do
  [ -s "run2/$f" ] || { echo "FAIL: run2/$f missing"; exit 1; }
done
python3 - run/log.jsonl run2/log.jsonl <<'PY'
import json, sys
one, two = ([json.loads(l) for l in open(p) if '"total"' in l] for p in sys.argv[1:3])
assert len(one) == len(two) == 2, (len(one), len(two))
for a, b in zip(one, two):
    assert a["images"] == b["images"], (a["images"], b["images"])
    assert abs(a["total"] - b["total"]) <= 1e-5 * abs(a["total"]), (a["total"], b["total"])
PY
echo "mpirun -np 2 facetool train logs the one-process losses"
