# Shared by scripts/train-model.sh (the shipped v2) and scripts/train-model-v1.sh: resumable steps with
# recorded wall times, training runs that resume their checkpoint, and the held-out rules for
# lights and UTKFace photos. Sourced; expects FACETOOL, WORK, SHARED and HELDOUT_LIGHTS.

STUDIO_LIGHTS=/usr/share/blender/datafiles/studiolights/world
FACE_MODEL=$SHARED/assets/ict-facekit/FaceXModel
UTKFACE=$SHARED/assets/faces/utkface-crop-part1
REAL_HELDOUT_EVERY=10    # the 10th, 20th, ... photo of the sorted UTKFace list is held out

die() { echo "$(basename "$0" .sh): $*" >&2; exit 1; }

check_inputs() {
  [ -x "$FACETOOL" ] || die "$FACETOOL not found: build first (bash scripts/build.sh) or set FACETOOL"
  [ -d "$FACE_MODEL" ] || die "$FACE_MODEL not found: set SHARED to the folder holding assets/"
  [ -d "$UTKFACE" ] || die "$UTKFACE not found: set SHARED to the folder holding assets/"
  [ -d "$STUDIO_LIGHTS" ] || die "$STUDIO_LIGHTS not found: apt-get install blender-data"
  mkdir -p "$WORK/done"
}

# Runs step NAME (the function step_NAME) unless it is done, and records its wall time.
run_step() {
  local name=$1
  if [ -e "$WORK/done/$name" ]; then echo "== $name: done earlier (remove $WORK/done/$name to redo)"; return; fi
  echo "== $name ($(date -u +%H:%M:%S) UTC)"
  local start=$SECONDS
  "step_$name"
  local seconds=$((SECONDS - start))
  printf '%s\t%d\t%s\t%s\n' "$name" "$seconds" "$(date -u +%FT%TZ)" \
    "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | xargs) x $(nproc)" >> "$WORK/timings.tsv"
  touch "$WORK/done/$name"
  echo "== $name: ${seconds} s"
}

# Runs the steps named on the command line (any of ALL_STEPS), or DEFAULT_STEPS (when the script
# sets it, else ALL_STEPS), in order.
run_steps() {
  local steps=("$@") s
  [ ${#steps[@]} -eq 0 ] && read -r -a steps <<< "${DEFAULT_STEPS:-$ALL_STEPS}"
  for s in "${steps[@]}"; do
    declare -F "step_$s" > /dev/null || die "unknown step '$s' ($ALL_STEPS)"
    run_step "$s"
  done
}

# The light folders: links to the HDRIs and Blender's studio worlds, HELDOUT_LIGHTS apart.
split_lights() {
  rm -rf "$WORK/lights" && mkdir -p "$WORK/lights/train" "$WORK/lights/heldout"
  local f name
  for f in "$SHARED"/assets/hdri/*.hdr "$STUDIO_LIGHTS"/*.exr; do
    name=$(basename "$f")
    if [[ " $HELDOUT_LIGHTS " == *" $name "* ]]; then
      ln -s "$(realpath "$f")" "$WORK/lights/heldout/$name"
    else
      ln -s "$(realpath "$f")" "$WORK/lights/train/$name"
    fi
  done
}

# Links to the UTKFace photos in $WORK/utkface/{train,heldout} by the held-out rule. With
# UTK_LIMIT set (trial runs, shorter sittings) about that many, spread evenly over the sorted
# list (which is ordered by the age in the name, so its first N would all be of a few ages),
# each part keeping every k-th of its photos so the held-out rule is unchanged.
split_utkface() {
  rm -rf "$WORK/utkface" && mkdir -p "$WORK/utkface/train" "$WORK/utkface/heldout"
  local names=() k=0 f part stride=1 n_train=0 n_heldout=0
  mapfile -t names < <(ls "$UTKFACE" | LC_ALL=C sort)
  if [ -n "${UTK_LIMIT:-}" ] && [ "$UTK_LIMIT" -lt "${#names[@]}" ]; then
    stride=$(( (${#names[@]} + UTK_LIMIT - 1) / UTK_LIMIT ))
  fi
  for f in "${names[@]}"; do
    k=$((k + 1))
    if [ $((k % REAL_HELDOUT_EVERY)) -eq 0 ]; then
      part=heldout; n_heldout=$((n_heldout + 1)); [ $(((n_heldout - 1) % stride)) -eq 0 ] || continue
    else
      part=train; n_train=$((n_train + 1)); [ $(((n_train - 1) % stride)) -eq 0 ] || continue
    fi
    ln -s "$(realpath "$UTKFACE/$f")" "$WORK/utkface/$part/$f"
  done
}

# Trains RUN with CONFIG (resuming its checkpoint when there is one), within SITTING_MINUTES.
train_run() {
  local config=$1 run=$2; shift 2
  local limit=()
  [ -n "${SITTING_MINUTES:-}" ] && limit=(--time-limit "$SITTING_MINUTES")
  if [ -e "$run/checkpoint.safetensors" ]; then
    "$FACETOOL" train --config "$config" --out "$run" --resume "${limit[@]}"
  else
    "$FACETOOL" train --config "$config" --out "$run" "$@" "${limit[@]}"
  fi
  # The run is complete when its log reaches the configuration's step count.
  local want have
  want=$(grep -o '"steps": *[0-9]*' "$config" | grep -o '[0-9]*$')
  have=$(grep -c '"total"' "$run/log.jsonl" || true)
  [ "$have" -ge "$want" ] || die "$run stopped at step $have of $want; run the same command again to continue"
}

# Held-out figures of one training stage: `eval` on the synthetic and the real held-out data,
# into $WORK/eval/STAGE-synthetic and $WORK/eval/STAGE-real, with contact sheets.
eval_stage() {
  local stage=$1 synthetic=$2 real=$3
  "$FACETOOL" eval --model "$WORK/$stage/weights.safetensors" --data "$synthetic" \
    -o "$WORK/eval/$stage-synthetic" --contact-sheet
  "$FACETOOL" eval --model "$WORK/$stage/weights.safetensors" --data "$real" \
    -o "$WORK/eval/$stage-real" --contact-sheet
}

# Pictures of the weights WEIGHTS in $WORK/figures: the example photos through infer (example/),
# the first 8 held-out synthetic samples and the 8 with the largest normal error in
# $WORK/eval/STAGE-synthetic through eval's contact sheet (first-eval/, worst-eval/).
model_figures() {
  local weights=$1 stage=$2 set f
  mkdir -p "$WORK/figures"
  "$FACETOOL" infer --model "$weights" examples/photos/grace_hopper_512x512.jpg examples/photos/astronaut.png \
    -o "$WORK/figures/example" > /dev/null
  rm -rf "$WORK/figures/first" "$WORK/figures/worst" && mkdir -p "$WORK/figures/first" "$WORK/figures/worst"
  for f in $(ls "$WORK/synthetic-heldout" | grep '^sample_.*\.exr$' | head -8); do
    ln -s "$(realpath "$WORK/synthetic-heldout/$f")" "$WORK/figures/first/$f"
  done
  for f in $(tail -n +2 "$WORK/eval/$stage-synthetic/per_image.csv" | sort -t, -k3,3 -g -r | head -8 | cut -d, -f1); do
    ln -s "$(realpath "$WORK/synthetic-heldout/$f")" "$WORK/figures/worst/$f"
  done
  for set in first worst; do
    "$FACETOOL" eval --model "$weights" --data "$WORK/figures/$set" -o "$WORK/figures/$set-eval" \
      --contact-sheet > /dev/null
  done
}
