#!/usr/bin/env bash
# Reproduces the shipped model (models/facetool-v2.safetensors) from a fresh clone: data, fit labels, stage 1, six stage-2 runs, the landmark normal head, evaluation, figures.
#
#   bash scripts/train-model.sh [STEP...]      # no STEP: the shipped model's steps, in order
#
# The shipped model's steps: lights synth-heldout synth real fit-labels textures synth-textured
# stage1 tex-stage2 tex-grey-stage2 tex-normal-stage2 tex-normal3-stage2 tex-grey50-stage2
# tex-relit-stage2 hard-stage2 landmark-normals eval figures ship. The others train the networks the model card compares it with (docs/model-card.md),
# by name: stage2 (the paper's network on the procedural set), prior-data prior-stage1 prior-stage2
# prior-fov14 tex-prior-stage1 tex-prior-stage2 shading-stage2 (the same network with the fit's
# normals as a second input, issue 25 item 4; docs/fit.md, "The fit as the network's input"). The
# tex-* steps train on synthetic faces painted with albedo textures unwrapped from the training
# photos (issue 25 item 3; docs/synthetic-data.md, "Photo-textured albedo"); shading-stage2 is
# tex-prior-stage2 with the real photos' normal label at a tenth of its weight. Every step is
# resumable: synth and prepare-real keep what they wrote, training resumes its checkpoint, a
# finished step is skipped ($WORK/done/STEP), so the model trains over several sittings: set
# SITTING_MINUTES and run the same command in each. Wall times land in $WORK/timings.tsv for the
# model card. The trainings' step counts are those the shipped weights got (configs/facetool-v2-
# {stage1,tex-stage2,tex-grey-stage2,tex-normal-stage2,tex-normal3-stage2,tex-grey50-stage2,
# tex-relit-stage2,hard-stage2}.json; hard-stage2's shipped run read smaller sets, UTK_LIMIT=1800 and
# SYNTH_TEXTURED=1500, as its sitting remade them: docs/model-card.md, "Hard-lit inputs";
# the learning rate is constant, so a run cut there is the run).
# scripts/train-model-v1.sh reproduces the model shipped before (docs/model-card-v1.md).
#
# What differs from v1 (each a starting choice, to be measured against the alternatives):
# - the v2 framing (the inner face fills 71 % of the crop; the outside of the photo filled with
#   the mean of its border, the mask cut there) at 96 x 96 (the issue: "at least 96x96");
# - synthetic samples crossed by a simulated photo edge in 30 % of them (`synth --photo-edges`);
# - the real photos' normals, visibility and mask from the landmark fit (`pseudo-label --from
#   fit`), light and albedo by least squares from them, instead of stage 1's predictions;
# - faces cut by the photo's edge kept up to 20 % of their mask (v1: 5 %), as the fill and the
#   cut mask handle the outside.
#
# On a fresh machine the shortest way to the textured prior network's runs is `lights real
# fit-labels textures synth-textured synth-heldout prior-fov14` and then the run (tex-prior-stage1,
# or shading-stage2): the procedural set (`synth`) is needed only by the paper network's stage 1.
#
# Environment: FACETOOL (the program, default build/bin/facetool), SHARED (default ../shared: the
# ICT-FaceKit model, the HDRIs and the UTKFace photos), WORK (default data/train-model-v2, about
# 3 GB), SITTING_MINUTES (a time limit for each training step in this sitting; unset: train to
# the end); the data's sizes SYNTH_TRAIN (procedural set), SYNTH_TEXTURED, SYNTH_HELDOUT and
# UTK_LIMIT (about N UTKFace photos spread over the list; the defaults are the shipped model's),
# LABEL_SMOOTH and LABEL_MASK (the fit labels' --smooth-normals and --label-mask, below); for a trial at small scale STEPS (every
# run) and BATCH (every source's batch).
set -euo pipefail
cd "$(dirname "$0")/.."

FACETOOL=${FACETOOL:-build/bin/facetool}
SHARED=${SHARED:-../shared}
WORK=${WORK:-data/train-model-v2}

SIZE=96
FRAMING=v2
PHOTO_EDGES=0.3
MAX_EDGE_CUT=0.2
SYNTH_TRAIN=${SYNTH_TRAIN:-8000}
SYNTH_TEXTURED=${SYNTH_TEXTURED:-6000}
SYNTH_HELDOUT=${SYNTH_HELDOUT:-500}
UTK_LIMIT=${UTK_LIMIT:-4000}
HELDOUT_LIGHTS="quarry_01_1k.hdr sunrise.exr sunset.exr"  # the same held-out lights as v1
# Synthetic samples' landmarks jittered by this x the inter-ocular distance before the prior's
# fit: 0.08 makes the prior as wrong as the fit from dlib's landmarks on renders (docs/fit.md).
LANDMARK_NOISE=${LANDMARK_NOISE:-0.08}
# The fraction of the textured set's faces painted from photos (the rest procedural).
TEXTURE_FRACTION=${TEXTURE_FRACTION:-0.5}
# The tex-* runs' input prior is the fit at 14 degrees over the crop ("fit_normal fov 14" in their
# configurations): the v2 crop's own field of view (synth's 20-25 degrees over v1's crop, zoomed
# 1.6), where the fit's default 22.5 makes faces too flat (model card: prior error 7.6 against 8.3
# degrees on held-out synthetic faces, 14.1 against 14.6 on yaleb-dev).
PRIOR_FOV=14
LABEL_SMOOTH=${LABEL_SMOOTH:-0}
# The labels' mask as the shipped weights' labels had it: the whole fitted region (pseudo-label's
# default is now the trusted pixels; docs/model-card.md, "The labels' mask").
LABEL_MASK=${LABEL_MASK:-fitted}
# The run whose weights ship (figures, ship).
SHIPPED_STAGE=landmark-normals
DEFAULT_STEPS="lights synth-heldout synth real fit-labels textures synth-textured stage1 tex-stage2 tex-grey-stage2 tex-normal-stage2 tex-normal3-stage2 tex-grey50-stage2 tex-relit-stage2 hard-stage2 landmark-normals eval figures ship"
ALL_STEPS="$DEFAULT_STEPS stage2 prior-data prior-stage1 prior-stage2 prior-fov14 tex-prior-stage1 tex-prior-stage2 shading-stage2"

# shellcheck source=scripts/lib/train-steps.sh
source scripts/lib/train-steps.sh
check_inputs

step_lights() { split_lights; }

# The held-out synthetic samples at the v2 framing: seed 2 (new identities), the held-out lights.
step_synth-heldout() {
  "$FACETOOL" synth --face-model "$FACE_MODEL" --lights "$WORK/lights/heldout" --size "$SIZE" \
    --framing "$FRAMING" --photo-edges "$PHOTO_EDGES" --count "$SYNTH_HELDOUT" --seed 2 \
    -o "$WORK/synthetic-heldout"
}

# The training synthetic samples: seed 1, the training lights.
step_synth() {
  "$FACETOOL" synth --face-model "$FACE_MODEL" --lights "$WORK/lights/train" --size "$SIZE" \
    --framing "$FRAMING" --photo-edges "$PHOTO_EDGES" --count "$SYNTH_TRAIN" --seed 1 \
    -o "$WORK/synthetic" --contact-sheet "$WORK/synthetic-sheet.png"
}

# UTKFace photos aligned at the v2 framing, split by v1's held-out rule. Their masks stay the
# landmark hull: the fit labels' light and albedo are solved where the hull and the fit agree, so
# fringes of hair on the forehead stay out of the solve (the training labels' mask is the whole fitted
# region: LABEL_MASK below).
step_real() {
  split_utkface
  local part
  for part in train heldout; do
    "$FACETOOL" prepare-real "$WORK/utkface/$part" --size "$SIZE" --framing "$FRAMING" \
      --face-region hull --max-edge-cut "$MAX_EDGE_CUT" -o "$WORK/real-$part"
  done
}

# Labels of the real photos from the ICT-FaceKit fit to their landmarks (docs/fit.md), with the
# mesh's own normals (LABEL_SMOOTH 0) as the shipped model's labels were: they predate the smoothed
# normals that `pseudo-label --from fit` writes by default.
step_fit-labels() {
  local part
  for part in train heldout; do
    "$FACETOOL" pseudo-label --from fit --smooth-normals "$LABEL_SMOOTH" --label-mask "$LABEL_MASK" \
      --face-model "$FACE_MODEL" "$WORK/real-$part"/sample_*.exr -o "$WORK/real-fit-$part"
  done
}

# configs/facetool-v2-STAGE.json with this work folder's data (each source's folder by its name)
# and the trial overrides.
write_config() {
  local stage=$1 path=$2
  local edits=(-E -e "s#\"directory\": \"[^\"]*/([^/\"]+)\"#\"directory\": \"$(realpath "$WORK")/\\1\"#")
  [ -n "${STEPS:-}" ] && edits+=(-e "s/\"steps\": [0-9]*/\"steps\": $STEPS/")
  [ -n "${BATCH:-}" ] && edits+=(-e "s/\"batch\": [0-9]*/\"batch\": $BATCH/")
  sed "${edits[@]}" "configs/facetool-v2-$stage.json" > "$path"
}

# A trial at small scale: STEPS or BATCH set (its runs are not the shipped schedule).
is_trial() { [ -n "${STEPS:-}${BATCH:-}" ]; }

# A run not started in $WORK starts from the checkpoint committed between sittings, if there is
# one (checkpoints/facetool-v2/RUN/: checkpoint.safetensors and log.jsonl, under 20 MB; removed
# when the model ships), so that a fresh machine goes on where the last sitting stopped. Not for
# a trial (STEPS or BATCH set): its schedule is not the checkpoint's.
seed_from_repository() {
  local run=$1 saved=checkpoints/facetool-v2/$1
  ! is_trial || return 0
  [ ! -e "$WORK/$run/checkpoint.safetensors" ] && [ -e "$saved/checkpoint.safetensors" ] || return 0
  mkdir -p "$WORK/$run"
  cp "$saved/checkpoint.safetensors" "$saved/log.jsonl" "$WORK/$run/"
  echo "$run: starting from the committed checkpoint in $saved"
}

# A run RUN (configs/facetool-v2-RUN.json) started from the weights of the run FROM (a fresh
# optimiser state), or resumed from its checkpoint.
run_from() {
  write_config "$1" "$WORK/$1.json"
  seed_from_repository "$1"
  train_run "$WORK/$1.json" "$WORK/$1" --from "$WORK/$2/weights.safetensors"
}

step_stage1() {
  write_config stage1 "$WORK/stage1.json"
  seed_from_repository stage1
  train_run "$WORK/stage1.json" "$WORK/stage1"
}

step_stage2() { run_from stage2 stage1; }

# The fit's normals as the input prior: the synthetic samples' exact landmarks jittered by
# LANDMARK_NOISE (a detector's error) before the fit; the fit-labelled real samples carry the
# prior already (the fit that labels them).
step_prior-data() {
  local part
  for part in synthetic synthetic-heldout; do
    "$FACETOOL" pseudo-label --from fit --prior-only --landmark-noise "$LANDMARK_NOISE" --face-model "$FACE_MODEL" \
      "$WORK/$part"/sample_*.exr -o "$WORK/$part-prior"
  done
}

step_prior-stage1() {
  write_config prior-stage1 "$WORK/prior-stage1.json"
  seed_from_repository prior-stage1
  train_run "$WORK/prior-stage1.json" "$WORK/prior-stage1"
}

step_prior-stage2() { run_from prior-stage2 prior-stage1; }

# Albedo textures from the training photos only (never the held-out ones).
step_textures() {
  "$FACETOOL" unwrap --face-model "$FACE_MODEL" "$WORK/real-fit-train"/sample_*.exr -o "$WORK/textures"
}

# The training synthetic set again (same seed: the same faces, poses and lights), a fraction of the
# faces painted with the textures, and the fit prior added as for the procedural set.
step_synth-textured() {
  "$FACETOOL" synth --face-model "$FACE_MODEL" --lights "$WORK/lights/train" --size "$SIZE" \
    --framing "$FRAMING" --photo-edges "$PHOTO_EDGES" --count "$SYNTH_TEXTURED" --seed 1 \
    --albedo-textures "$WORK/textures" --albedo-texture-fraction "$TEXTURE_FRACTION" \
    -o "$WORK/synthetic-textured" --contact-sheet "$WORK/synthetic-textured-sheet.png"
  "$FACETOOL" pseudo-label --from fit --prior-only --landmark-noise "$LANDMARK_NOISE" --fov "$PRIOR_FOV" \
    --face-model "$FACE_MODEL" "$WORK/synthetic-textured"/sample_*.exr -o "$WORK/synthetic-textured-prior"
}

# The other sets the tex-* runs read, with the prior at PRIOR_FOV (labels kept): the held-out
# synthetic faces, and the fit-labelled real photos (their landmarks are a detector's: no noise).
step_prior-fov14() {
  "$FACETOOL" pseudo-label --from fit --prior-only --landmark-noise "$LANDMARK_NOISE" --fov "$PRIOR_FOV" \
    --face-model "$FACE_MODEL" "$WORK/synthetic-heldout"/sample_*.exr -o "$WORK/synthetic-heldout-prior14"
  local part
  for part in train heldout; do
    "$FACETOOL" pseudo-label --from fit --prior-only --fov "$PRIOR_FOV" --face-model "$FACE_MODEL" \
      "$WORK/real-fit-$part"/sample_*.exr -o "$WORK/real-fit-$part-prior14"
  done
}

# Starts from the prior network's stage 1 (the same network, its prior at 22.5 degrees): a shorter
# schedule at half the learning rate teaches it the textured faces and the prior at PRIOR_FOV.
step_tex-prior-stage1() {
  write_config tex-prior-stage1 "$WORK/tex-prior-stage1.json"
  seed_from_repository tex-prior-stage1
  train_run "$WORK/tex-prior-stage1.json" "$WORK/tex-prior-stage1" --from "$(prior_stage1_weights)"
}

# The prior run's stage 1 as it stands: its weights if this work folder finished it, else the
# checkpoint committed between sittings (step 4,107).
prior_stage1_weights() {
  if [ -e "$WORK/prior-stage1/weights.safetensors" ]; then echo "$WORK/prior-stage1/weights.safetensors"
  else echo checkpoints/facetool-v2/prior-stage1/checkpoint.safetensors; fi
}

step_tex-prior-stage2() { run_from tex-prior-stage2 tex-prior-stage1; }

# From the textured stage 1 where this work folder has it, else from the prior run's stage 1 (the
# textured set is the synthetic source of both runs, so stage 2 also teaches what tex-prior-stage1
# would have).
step_shading-stage2() {
  write_config shading-stage2 "$WORK/shading-stage2.json"
  seed_from_repository shading-stage2
  local from=$WORK/tex-prior-stage1/weights.safetensors
  [ -e "$from" ] || from=$(prior_stage1_weights)
  train_run "$WORK/shading-stage2.json" "$WORK/shading-stage2" --from "$from"
}

# The paper's network (no input prior) on the data of tex-prior-stage2, with its terms, from the
# paper network's stage 1: the other column of the table (issue 25 item 4). Its normals on real
# photos come from the image alone, so it needs no face model at run time.
step_tex-stage2() { run_from tex-stage2 stage1; }

# tex-stage2 with a quarter of each source's photos shown to the network in grey (the config's
# grey_fraction; docs/training.md), from tex-stage2's weights (a fresh optimiser state): an
# image-only network that leans on colour answers grey photos (yaleb-dev's, old prints) with
# other normals.
step_tex-grey-stage2() { run_from tex-grey-stage2 tex-stage2; }

# tex-grey-stage2 with the real photos' normal label (the fit's) weighed 1 instead of 0.2, from
# its weights (a fresh optimiser state): the image-only network moves towards the fit's shapes,
# which are better than its own on real faces (docs/model-card.md).
step_tex-normal-stage2() { run_from tex-normal-stage2 tex-grey-stage2; }

# The same with that label weighed 3, from tex-normal-stage2's weights (a fresh optimiser state):
# a stronger pull towards the fit's shapes helps again (docs/model-card.md).
step_tex-normal3-stage2() { run_from tex-normal3-stage2 tex-normal-stage2; }

# The same with half of each source's photos shown in grey instead of a quarter, from
# tex-normal3-stage2's weights (a fresh optimiser state): grey, hard-lit photos (yaleb-dev's) gain
# at every light (docs/model-card.md). Its weights are the shipped model.
step_tex-grey50-stage2() { run_from tex-grey50-stage2 tex-normal3-stage2; }
# Half of the real photos relit by a random one-sided light through their labels (docs/training.md).
step_tex-relit-stage2() { run_from tex-relit-stage2 tex-grey50-stage2; }
# Issue 53 item 3: the relit run's weights trained on with half of both sources' photos lit by a
# hard light (relight_light "hard", docs/training.md).
step_hard-stage2() { run_from hard-stage2 tex-relit-stage2; }

# The landmark normal head (docs/model-card.md, "The landmark normal head"): a ridge regression
# from each face's landmarks to its normals (the training photos' fit labels and the textured
# synthetic faces' true normals), added to tex-relit-stage2's weights. Its weights are the
# shipped model.
step_landmark-normals() {
  mkdir -p "$WORK/landmark-normals"
  "$FACETOOL" landmark-normals --data "$WORK/real-fit-train" "$WORK/synthetic-textured" \
    --model "$WORK/hard-stage2/weights.safetensors" -o "$WORK/landmark-normals/weights.safetensors"
}

# Held-out figures of every trained stage of both networks (one not trained yet is skipped):
# synthetic (Table 1 form), real (PSNR and SSIM beside the blurred photo's, by group; the normals
# against the fit's labels), a contact sheet of 24 held-out UTKFace photos (every k-th of the
# sorted list, so the same 24 each time) and, where ../shared has yaleb-dev, the
# photometric-stereo benchmark and relighting with v1 and the fit beside them.
step_eval() {
  local stage
  for stage in stage1 stage2 prior-stage1 prior-stage2 tex-prior-stage1 tex-prior-stage2 shading-stage2 tex-stage2 tex-grey-stage2 tex-normal-stage2 tex-normal3-stage2 tex-grey50-stage2 tex-relit-stage2 hard-stage2 landmark-normals; do
    [ -e "$WORK/$stage/weights.safetensors" ] || { echo "eval: no $stage model yet, skipped"; continue; }
    local synthetic=$WORK/synthetic-heldout real=$WORK/real-fit-heldout
    [[ $stage == prior-* ]] && synthetic=$WORK/synthetic-heldout-prior  # the fit prior added
    [[ $stage == tex-prior-* || $stage == shading-* ]] && synthetic=$WORK/synthetic-heldout-prior14 real=$WORK/real-fit-heldout-prior14
    eval_stage "$stage" "$synthetic" "$real"
    /usr/bin/python3 scripts/eval-groups.py "$WORK/eval/$stage-real/per_image.csv" \
      "$WORK/real-heldout/manifest.tsv" > "$WORK/eval/$stage-real/groups.md"
    local photos=() k=0 f
    local all=("$WORK"/utkface/heldout/*)
    local every=$(( ${#all[@]} / 24 > 0 ? ${#all[@]} / 24 : 1 ))
    for f in "${all[@]}"; do
      if [ $((k++ % every)) -eq 0 ] && [ ${#photos[@]} -lt 24 ]; then photos+=("$f"); fi
    done
    # --face-model: used by the prior network only (the fit of each crop's landmarks).
    "$FACETOOL" infer --model "$WORK/$stage/weights.safetensors" --face-model "$FACE_MODEL" --aligned "${photos[@]}" \
      -o "$WORK/eval/$stage-utkface24" > /dev/null || [ $? -eq 1 ]  # 1: a photo without a face
    if [ -d "$SHARED/assets/faces/yaleb-dev" ]; then
      [ -d "$WORK/yaleb/ps" ] || /usr/bin/python3 scripts/yaleb_benchmark.py --cache "$WORK/yaleb" ps > /dev/null
      /usr/bin/python3 scripts/yaleb_benchmark.py --cache "$WORK/yaleb" infer --facetool "$FACETOOL" \
        --model "$WORK/$stage/weights.safetensors" --name "v2-$stage" > /dev/null
      /usr/bin/python3 scripts/yaleb_benchmark.py --cache "$WORK/yaleb" relight --facetool "$FACETOOL" \
        --model "$WORK/$stage/weights.safetensors" --name "v2-$stage" --markdown "$WORK/eval/$stage-relight.md" > /dev/null
    fi
  done
  local v1
  if [ -d "$SHARED/assets/faces/yaleb-dev" ]; then
    [ -d "$WORK/yaleb/pred/fit" ] || /usr/bin/python3 scripts/yaleb_benchmark.py --cache "$WORK/yaleb" \
      fit --fit-bin "$FACETOOL" > /dev/null
    if v1=$(v1_weights); then
      /usr/bin/python3 scripts/yaleb_benchmark.py --cache "$WORK/yaleb" infer --facetool "$FACETOOL" \
        --model "$v1" --name v1 > /dev/null
      /usr/bin/python3 scripts/yaleb_benchmark.py --cache "$WORK/yaleb" relight --facetool "$FACETOOL" \
        --model "$v1" --name v1 --markdown "$WORK/eval/v1-relight.md" > /dev/null
    else
      echo "eval: facetool-v1 not in this clone's history (a shallow clone?): its column is skipped"
    fi
    /usr/bin/python3 scripts/yaleb_benchmark.py --cache "$WORK/yaleb" score \
      --markdown "$WORK/eval/yaleb.md"
  fi
}

# The model shipped before (facetool-v1) for the figures beside v2's, from the commit that last held
# it in models/; prints its path, fails in a clone without that history.
V1_COMMIT=80f0b2a
v1_weights() {
  local f=$WORK/facetool-v1.safetensors
  if [ ! -e "$f" ]; then
    git show "$V1_COMMIT:models/facetool-v1.safetensors" > "$f.tmp" 2> /dev/null || { rm -f "$f.tmp"; return 1; }
    mv "$f.tmp" "$f"
  fi
  echo "$f"
}

# Pictures for docs/ (public-domain photos and synthetic samples only; UTKFace and Yale B stay out
# of the repository): the example photos' contact sheets (README), the first 8 held-out synthetic
# samples and the 8 with the largest normal error (docs/model-card.md).
step_figures() {
  if is_trial; then echo "figures: not in a trial (STEPS or BATCH set): docs/images kept"; return 0; fi
  model_figures "$WORK/$SHIPPED_STAGE/weights.safetensors" "$SHIPPED_STAGE"
  mkdir -p docs/images
  cp "$WORK/figures/example/grace_hopper_512x512/contact_sheet.png" docs/images/example-contact-sheet.png
  cp "$WORK/figures/example/astronaut/contact_sheet.png" docs/images/example-contact-sheet-astronaut.png
  local set
  for set in first worst; do
    cp "$WORK/figures/$set-eval/contact_sheet.png" "docs/images/model-card-v2-heldout-$set.png"
  done
}

# The shipped run's weights into models/ (written under a temporary name, then renamed).
step_ship() {
  local weights=$WORK/$SHIPPED_STAGE/weights.safetensors bytes
  if is_trial; then echo "ship: not in a trial (STEPS or BATCH set): models/ kept"; return 0; fi
  bytes=$(stat -c %s "$weights")
  [ "$bytes" -le 20000000 ] || die "$weights is $bytes bytes, over the 20 MB limit"
  cp "$weights" models/facetool-v2.safetensors.tmp
  mv models/facetool-v2.safetensors.tmp models/facetool-v2.safetensors
  sha256sum models/facetool-v2.safetensors
}

run_steps "$@"
