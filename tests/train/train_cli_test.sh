#!/usr/bin/env bash
# facetool train, pseudo-label and eval from the command line: a run, a stopped run resumed
# (its log must equal the uninterrupted one's, bit for bit on cpu), config errors, the outputs.
# Usage: train_cli_test.sh FACETOOL SHARED_DIR. Exits 77 (skip) without ../shared's face model.
set -euo pipefail
facetool=$1
shared=$2
face="$shared/assets/ict-facekit/FaceXModel"
if [ ! -d "$face" ] || [ ! -d "$shared/assets/hdri" ]; then
  echo "skip: needs the ICT face model and HDRIs under $shared/assets"; exit 77
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
"$facetool" synth --face-model "$face" --lights "$shared/assets/hdri" --count 24 --size 32 \
  --directions 100 --threads 1 --out data >/dev/null 2>&1
cat > smoke.json <<'JSON'
{"name": "cli", "network": {"width": 4, "input_size": 32}, "optimizer": {"learning_rate": 1e-3},
 "steps": 8, "checkpoint_every": 3, "validation": {"every": 4, "holdout_every": 6, "batches": 1},
 "seed": 5, "sources": [{"name": "synthetic", "directory": "data", "batch": 4,
   "terms": {"recon_albedo": 1, "recon_normal": 0.2, "recon_visibility": 0.2, "recon_light": 0.01,
             "albedo": 1, "normal": 0.2, "visibility": 0.2, "light": 0.01}}]}
JSON
"$facetool" train --config smoke.json --out straight 2>/dev/null
"$facetool" train --config smoke.json --out stopped --steps 5 2>/dev/null
"$facetool" train --config smoke.json --out stopped --resume 2>/dev/null
for f in checkpoint.safetensors weights.safetensors log.jsonl loss.png; do
  [ -s "straight/$f" ] || { echo "FAIL: straight/$f missing"; exit 1; }
done
grep -q '"validation"' straight/log.jsonl || { echo "FAIL: no validation line"; exit 1; }
# Training lines only (a run that stops validates at its last step), without the timings.
strip() { grep '"total"' "$1" | sed -E 's/"seconds(_data)?":[-0-9.e+]+,?//g'; }
if ! diff <(strip straight/log.jsonl) <(strip stopped/log.jsonl); then
  echo "FAIL: the resumed run's log differs from the uninterrupted run's"; exit 1
fi
# --time-limit stops early with exit 0 and a checkpoint; --resume then continues the same losses.
"$facetool" train --config smoke.json --out timed --steps 1000000 --time-limit 0.01 2>timed.txt
grep -q "time limit of 0.01 min reached at step" timed.txt || { cat timed.txt; exit 1; }
timed_steps=$(grep -c '"total"' timed/log.jsonl)
[ "$timed_steps" -ge 1 ] && [ "$timed_steps" -lt 1000000 ] || { echo "FAIL: timed run took $timed_steps steps"; exit 1; }
[ -s timed/checkpoint.safetensors ] && [ -s timed/weights.safetensors ] || { echo "FAIL: timed run wrote no checkpoint"; exit 1; }
n=$((timed_steps < 8 ? timed_steps : 8))
if ! diff <(strip straight/log.jsonl | head -n "$n") <(strip timed/log.jsonl | head -n "$n"); then
  echo "FAIL: the --time-limit run's losses differ from the uninterrupted run's"; exit 1
fi
if [ "$timed_steps" -lt 8 ]; then
  "$facetool" train --config smoke.json --out timed --resume 2>/dev/null
  if ! diff <(strip straight/log.jsonl) <(strip timed/log.jsonl); then
    echo "FAIL: the run resumed after --time-limit differs from the uninterrupted run"; exit 1
  fi
fi
# A second start into the same folder without --resume is refused.
if "$facetool" train --config smoke.json --out straight 2>err.txt; then echo "FAIL: reused run"; exit 1; fi
grep -q "already holds a run" err.txt || { cat err.txt; exit 1; }
# An unknown term is an error before any step.
sed 's/"light": 0.01}/"light": 0.01, "sharpness": 1}/' smoke.json > bad.json
if "$facetool" train --config bad.json --out bad 2>err.txt; then echo "FAIL: unknown term accepted"; exit 1; fi
grep -q "unknown loss term 'sharpness'" err.txt || { cat err.txt; exit 1; }
[ ! -e bad/log.jsonl ] || { echo "FAIL: bad run wrote a log"; exit 1; }
# Pseudo labels, then eval with and without ground truth.
"$facetool" pseudo-label --model straight/weights.safetensors data/sample_00000001.exr \
  data/sample_00000002.exr -o pseudo 2>/dev/null
[ -s pseudo/sample_00000001.exr ] || { echo "FAIL: no pseudo-labelled sample"; exit 1; }
"$facetool" eval --model straight/weights.safetensors --data data -o eval --contact-sheet >eval.txt 2>/dev/null
grep -q "< 20 deg" eval.txt || { cat eval.txt; exit 1; }
for f in per_image.csv summary.json summary.md contact_sheet.png; do
  [ -s "eval/$f" ] || { echo "FAIL: eval/$f missing"; exit 1; }
done
[ "$(wc -l < eval/per_image.csv)" -eq 25 ] || { echo "FAIL: per_image.csv rows"; exit 1; }
"$facetool" eval --model straight/weights.safetensors --data pseudo -o eval-real >eval-real.txt 2>/dev/null
if grep -q "normal_error" eval-real/summary.json; then echo "FAIL: real data got a normal error"; exit 1; fi
# The blurred-input baseline: a wider blur loses more, so its PSNR against the input falls.
"$facetool" eval --model straight/weights.safetensors --data data -o eval-blur2 --blur-sigma 2 >/dev/null 2>&1
blurred() { grep -o '"blurred_psnr_db_mean": [0-9.]*' "$1/summary.json" | grep -o '[0-9.]*$'; }
[ -n "$(blurred eval)" ] && [ -n "$(blurred eval-blur2)" ] || { echo "FAIL: no blurred_psnr_db_mean"; exit 1; }
awk -v a="$(blurred eval)" -v b="$(blurred eval-blur2)" 'BEGIN { exit !(a > b + 1) }' ||
  { echo "FAIL: blurred PSNR at sigma 1 ($(blurred eval)) not above sigma 2 ($(blurred eval-blur2))"; exit 1; }
echo "train CLI: ok"
