#!/usr/bin/env bash
# Reproduces facetool-v1, the model shipped until facetool-v2 (docs/model-card-v1.md): data, width trials, stage 1, pseudo labels, stage 2, evaluation.
#
#   bash scripts/train-model-v1.sh [STEP...]      # no STEP: all of them, in order
#
# Steps: lights synth real width-trials stage1 pseudo stage2 eval figures ship. Every step is resumable:
# synth and prepare-real keep the samples already written, training continues from its
# checkpoint (--resume), and a finished step is skipped (its marker is $WORK/done/STEP). Stop
# it at any time (Ctrl-C: training writes its checkpoint first) and run the same command again,
# in this sitting or another one. Each step's wall time on this machine lands in
# $WORK/timings.tsv; docs/model-card-v1.md quotes them.
#
# Measured here for facetool-v1 (2026-12-02, a 2-core AMD EPYC VM shared with builds and
# tests): lights 0 s, synth 53 min, real 8 min, width-trials 17 min, stage1 36 min (3,675 steps),
# pseudo 3 min, stage2 20 min (978 steps), eval + figures + ship 1 min: 2 h 18 min in all.
#
# Environment: FACETOOL (the program, default build/bin/facetool), SHARED (default ../shared:
# the ICT-FaceKit model, the HDRIs and the UTKFace photos), WORK (default data/train-model,
# where everything but the shipped weights goes: about 2.5 GB), SITTING_MINUTES (a time limit
# for each training step in this sitting; unset: train to the end).
set -euo pipefail
cd "$(dirname "$0")/.."

FACETOOL=${FACETOOL:-build/bin/facetool}
SHARED=${SHARED:-../shared}
WORK=${WORK:-data/train-model}

# The data and the schedule (docs/model-card-v1.md explains each choice).
SIZE=64                  # network input and sample size: measured choice, see the model card
SYNTH_TRAIN=20000        # synthetic training samples (seed 1, training lights)
SYNTH_HELDOUT=500        # held-out synthetic samples (seed 2: new identities; held-out lights)
TRIAL_WIDTHS="16 32 64"  # widths compared for the same wall time
TRIAL_MINUTES=15         # wall time of the width trials (side by side, one thread each)
TRIAL_SAMPLES=8000       # the trials train on the samples 0..TRIAL_SAMPLES-1 (more than they reach)
HELDOUT_LIGHTS="quarry_01_1k.hdr sunrise.exr sunset.exr"  # never seen in training

ALL_STEPS="lights synth real width-trials stage1 pseudo stage2 eval figures ship"

# shellcheck source=scripts/lib/train-steps.sh
source scripts/lib/train-steps.sh
check_inputs


# Training lights: the HDRIs of SHARED and blender-data except the held-out ones.
step_lights() { split_lights; }

# Synthetic samples. Every sample draws a new identity from the face model, so the held-out
# seed's identities are unseen; its lights are the held-out ones.
step_synth() {
  "$FACETOOL" synth --face-model "$FACE_MODEL" --lights "$WORK/lights/heldout" --size "$SIZE" \
    --count "$SYNTH_HELDOUT" --seed 2 -o "$WORK/synthetic-heldout"
  "$FACETOOL" synth --face-model "$FACE_MODEL" --lights "$WORK/lights/train" --size "$SIZE" \
    --count "$SYNTH_TRAIN" --seed 1 -o "$WORK/synthetic" --contact-sheet "$WORK/synthetic-sheet.png"
}

# Real photos: aligned crops with masks (prepare-real), split by the documented rule.
step_real() {
  split_utkface
  "$FACETOOL" prepare-real "$WORK/utkface/train" --size "$SIZE" -o "$WORK/real"
  "$FACETOOL" prepare-real "$WORK/utkface/heldout" --size "$SIZE" -o "$WORK/real-heldout"
}

# A stage-1 configuration for `width` on the data folder `data`, written into the work folder.
write_stage1_config() {
  local path=$1 width=$2 steps=$3 data=$4
  sed -e "s/\"width\": [0-9]*/\"width\": $width/" -e "s/\"steps\": [0-9]*/\"steps\": $steps/" \
    -e "s#\"directory\": \"[^\"]*\"#\"directory\": \"$(realpath "$data")\"#" \
    configs/facetool-v1-stage1.json > "$path"
}


# Width trials: the widths train side by side, one thread each, for the same wall time (so that
# whatever else the machine does slows them alike); the held-out normal error decides.
step_width-trials() {
  mkdir -p "$WORK/width-trials"
  rm -rf "$WORK/trial-synthetic" && mkdir -p "$WORK/trial-synthetic"
  local i name
  for ((i = 0; i < TRIAL_SAMPLES; i++)); do
    name=$(printf 'sample_%08d.exr' "$i")
    [ -e "$WORK/synthetic/$name" ] || die "$WORK/synthetic/$name missing: run the synth step"
    ln -s "$(realpath "$WORK/synthetic/$name")" "$WORK/trial-synthetic/$name"
  done
  local w pids=()
  for w in $TRIAL_WIDTHS; do
    local run=$WORK/width-trials/w$w
    write_stage1_config "$WORK/width-trials/w$w.json" "$w" 1000000 "$WORK/trial-synthetic"
    rm -rf "$run"
    FACETOOL_NUM_THREADS=1 "$FACETOOL" train --config "$WORK/width-trials/w$w.json" --out "$run" \
      --time-limit "$TRIAL_MINUTES" 2> "$WORK/width-trials/w$w.log" &
    pids+=($!)
  done
  for pid in "${pids[@]}"; do wait "$pid" || die "a width trial failed (logs in $WORK/width-trials)"; done
  for w in $TRIAL_WIDTHS; do
    "$FACETOOL" eval --model "$WORK/width-trials/w$w/weights.safetensors" \
      --data "$WORK/synthetic-heldout" -o "$WORK/width-trials/w$w/eval" > /dev/null
  done
  {
    printf 'width\tsteps\tweights_bytes\tnormal_error_mean_deg\n'
    for w in $TRIAL_WIDTHS; do
      local run=$WORK/width-trials/w$w
      printf '%s\t%s\t%s\t%s\n' "$w" "$(grep -c '"total"' "$run/log.jsonl")" \
        "$(stat -c %s "$run/weights.safetensors")" \
        "$(grep -o '"mean_deg": *[0-9.]*' "$run/eval/summary.json" | head -1 | grep -o '[0-9.]*$')"
    done
  } > "$WORK/width-trials/summary.tsv"
  cat "$WORK/width-trials/summary.tsv"
}

step_stage1() {
  local config=$WORK/stage1.json
  sed -e "s#\"directory\": \"[^\"]*\"#\"directory\": \"$(realpath "$WORK")/synthetic\"#" \
    configs/facetool-v1-stage1.json > "$config"
  train_run "$config" "$WORK/stage1"
}

step_pseudo() {
  "$FACETOOL" pseudo-label --model "$WORK/stage1/weights.safetensors" "$WORK"/real/sample_*.exr \
    -o "$WORK/real-pseudo"
}

step_stage2() {
  local config=$WORK/stage2.json
  sed -e "s#\"directory\": \"[^\"]*synthetic\"#\"directory\": \"$(realpath "$WORK")/synthetic\"#" \
    -e "s#\"directory\": \"[^\"]*real-pseudo\"#\"directory\": \"$(realpath "$WORK")/real-pseudo\"#" \
    configs/facetool-v1-stage2.json > "$config"
  train_run "$config" "$WORK/stage2" --from "$WORK/stage1/weights.safetensors"
}

# Held-out figures of stage 1 and stage 2: synthetic (Table 1 form) and real (PSNR, SSIM, per group).
step_eval() {
  local stage
  for stage in stage1 stage2; do
    eval_stage "$stage" "$WORK/synthetic-heldout" "$WORK/real-heldout"
    python3 scripts/eval-groups.py "$WORK/eval/$stage-real/per_image.csv" \
      "$WORK/real-heldout/manifest.tsv" > "$WORK/eval/$stage-real/groups.md"
    cat "$WORK/eval/$stage-real/groups.md"
  done
}

# Pictures of v1's outputs in $WORK/figures (docs/model-card-v1.md shows those of 2026-12-02):
# the example photos' contact sheets, held-out synthetic rows, the worst ones.
step_figures() { model_figures "$WORK/stage2/weights.safetensors" stage2; }

# The weights as v1 shipped them (no longer in models/: facetool-v2 replaced them).
step_ship() {
  local bytes
  bytes=$(stat -c %s "$WORK/stage2/weights.safetensors")
  [ "$bytes" -le 20000000 ] || die "stage 2 weights are $bytes bytes, over the 20 MB limit"
  cp "$WORK/stage2/weights.safetensors" "$WORK/facetool-v1.safetensors.tmp"
  mv "$WORK/facetool-v1.safetensors.tmp" "$WORK/facetool-v1.safetensors"
  sha256sum "$WORK/facetool-v1.safetensors"
}

run_steps "$@"
