#!/usr/bin/env bash
# The table of bad-input and full-disk cases over every facetool command, and its runner.
#
# usage: bad_input_cases.sh FACETOOL [--group REGEX] [--report] [--work DIR]
#
# Each case runs the real binary with one bad input (a missing, empty, damaged or hostile file,
# an out-of-range or malformed option, a full or read-only disk) and checks that
#   - it exits non-zero and is not killed by a signal (crash) nor by the time limit (hang),
#   - its message names the file or option given as the case's "named thing" and contains none
#     of the raw library phrases below (unclear message),
#   - no file in its output folder changed, appeared or was truncated (data loss): the folder is
#     filled with the outputs of good runs first and hashed before and after.
# Cases are named GROUP/NAME; --group keeps those whose name matches REGEX.
# --report prints the figures of issue #10's probe (cases, crashes, hangs, data losses, unclear
# messages). Exit status: 0 when every case passed.
set -u
FACETOOL=$(realpath "$1")
shift
GROUP='.'
REPORT=0
WORK=''
while [ $# -gt 0 ]; do
  case "$1" in
    --group) GROUP=$2; shift 2 ;;
    --report) REPORT=1; shift ;;
    --work) WORK=$2; shift 2 ;;
    *) echo "bad_input_cases.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
[ -x "$FACETOOL" ] || { echo "bad_input_cases.sh: '$FACETOOL' is not an executable" >&2; exit 2; }
[ -n "$WORK" ] || WORK=$(mktemp -d "${TMPDIR:-/tmp}/facetool-cli-cases.XXXXXX")
mkdir -p "$WORK"
WORK=$(realpath "$WORK")
FX=$WORK/fixtures
TIME_LIMIT=${FACETOOL_CASE_TIMEOUT:-30}
# Only facetool's own plugins, found beside the executable.
export FACETOOL_PLUGIN_PATH=
# Raw phrases that must never reach a user: library internals, temporary names.
RAW_PHRASES='bad_alloc|basic_filebuf|basic_ios|terminate called|what\(\)|std::|stoi|stod|vector::|out_of_range|\.tmp-[0-9]+-[0-9]+'

tried=0 crashes=0 hangs=0 losses=0 unclear=0 wrong_exit=0 failed=0 skipped=0
failures=()

# --- fixtures: good files made by facetool itself, and bad ones --------------------------------
make_fixtures() {
  rm -rf "$FX" && mkdir -p "$FX/folder" "$FX/empty_dir" || return 1
  cat > "$FX/light.json" <<'EOF'
{"format": "facetool-light", "version": 1,
 "coefficients": {"r": [2.5, 0.3, 0.8, 0.2, 0, 0, 0, 0, 0],
                  "g": [2.5, 0.3, 0.8, 0.2, 0, 0, 0, 0, 0],
                  "b": [2.5, 0.3, 0.8, 0.2, 0, 0, 0, 0, 0]}}
EOF
  "$FACETOOL" light show "$FX/light.json" -o "$FX/picture.png" --size 32 > /dev/null &&
    "$FACETOOL" infer --aligned --init random --input-size 32 --width 8 "$FX/picture.png" \
      -o "$FX/infer" --raw-output "$FX/raw.safetensors" > /dev/null 2>&1 || return 1
  cp "$FX/infer/picture/input.png" "$FX/face.png"
  cp "$FX/infer/picture/albedo.exr" "$FX/albedo.exr"
  cp "$FX/infer/picture/normal.exr" "$FX/normal.exr"
  cp "$FX/infer/picture/visibility.exr" "$FX/visibility.exr"
  "$FACETOOL" light convert "$FX/light.json" "$FX/light_sfsnet.txt" --to sfsnet > /dev/null &&
    "$FACETOOL" light convert "$FX/light.json" "$FX/light_dpr.txt" --to dpr > /dev/null || return 1
  printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > "$FX/triangle.obj"
  # Bad files, one per kind of damage.
  : > "$FX/empty.png"
  printf 'hello, this is not what you think\n' > "$FX/garbage.png"
  head -c 120 "$FX/face.png" > "$FX/truncated.png"
  head -c 300 "$FX/albedo.exr" > "$FX/truncated.exr"
  # A valid PNG header claiming 100000 x 100000 pixels (CRCs correct).
  local hex=89504e470d0a1a0a0000000d49484452000186a0000186a0080200000027309c9f0000000c49444154789c6360a00c000000400001b7347cef0000000049454e44ae426082
  # shellcheck disable=SC2059
  printf "$(sed 's/../\\x&/g' <<< "$hex")" > "$FX/huge.png"
  printf '{"format": "facetool-light", "version": 1, "coefficients": {"r": [1e999, 0, 0, 0, 0, 0, 0, 0, 0], "g": [1, 0, 0, 0, 0, 0, 0, 0, 0], "b": [1, 0, 0, 0, 0, 0, 0, 0, 0]}}' > "$FX/infinite.json"
  printf '{"format": "facetool-light", "version": 1}' > "$FX/nocoeffs.json"
  printf '{"format": "facetool-light", "version": 1, "coefficients": ' > "$FX/truncated.json"
  { for i in $(seq 27); do printf 'nan '; done; echo; } > "$FX/nan_sfsnet.txt"
  printf '1 2 3\n' > "$FX/short_dpr.txt"
  printf 'v 0 0 0\nv 1 0 0\nf 1 2 7\n' > "$FX/bad_index.obj"
  head -c 3000 "$(dirname "$FACETOOL")/sh_renderer.ftplugin.so" > "$FX/truncated.ftplugin.so"
  printf 'not a shared library' > "$FX/text.ftplugin.so"
  head -c 40 "$FX/raw.safetensors" > "$FX/truncated.safetensors"
  # An EXR with NaN pixels (oiiotool, when installed; otherwise a damaged EXR of that name).
  if command -v oiiotool > /dev/null; then
    oiiotool --create 8x8 3 --fill:color=nan,0,0 0,0,8,8 -o "$FX/nan.exr" > /dev/null 2>&1 || true
  fi
  [ -f "$FX/nan.exr" ] || cp "$FX/truncated.exr" "$FX/nan.exr"
  return 0
}

# The output folder a case writes into, filled with good outputs of earlier runs.
seed_output() {
  local out=$1
  mkdir -p "$out"
  cp -r "$FX/infer" "$out/infer"
  cp "$FX/face.png" "$out/out.png"
  cp "$FX/face.png" "$out/out_shading.png"
  cp "$FX/albedo.exr" "$out/out.exr"
  cp "$FX/albedo.exr" "$out/out_shading.exr"
  cp "$FX/light.json" "$out/light.json"
  cp "$FX/light_sfsnet.txt" "$out/light.txt"
  cp "$FX/face.png" "$out/preview.png"
  cp "$FX/raw.safetensors" "$out/raw.safetensors"
}

folder_hash() { (cd "$1" && find . -type f -print0 | sort -z | xargs -0 -r md5sum) | md5sum; }

# run_case_in NAME NAMED_THING OUT COMMAND...: runs COMMAND (facetool's arguments) with output
# folder OUT already seeded, and records the outcome.
run_case_in() {
  local name=$1 needle=$2 out=$3
  shift 3
  [[ "$name" =~ $GROUP ]] || return 0
  tried=$((tried + 1))
  local before after rc message problems=''
  before=$(folder_hash "$out")
  message=$(cd "$WORK" && timeout -k 5 "$TIME_LIMIT" "$FACETOOL" "$@" 2>&1 < /dev/null)
  rc=$?
  after=$(folder_hash "$out")
  if [ "$rc" -eq 124 ] || [ "$rc" -eq 137 ]; then
    hangs=$((hangs + 1)); problems+=" hang(${TIME_LIMIT}s)"
  elif [ "$rc" -gt 128 ]; then
    crashes=$((crashes + 1)); problems+=" crash(signal $((rc - 128)))"
  elif [ "$rc" -eq 0 ]; then
    wrong_exit=$((wrong_exit + 1)); problems+=" exit-0"
  fi
  if [ "$before" != "$after" ]; then
    losses=$((losses + 1)); problems+=" output-folder-changed"
  fi
  if [ "$rc" -ne 124 ] && [ "$rc" -ne 137 ] && [ "$rc" -le 128 ] && [ "$rc" -ne 0 ]; then
    if ! grep -qF -- "$needle" <<< "$message" || grep -qE -- "$RAW_PHRASES" <<< "$message"; then
      unclear=$((unclear + 1)); problems+=" unclear-message"
    fi
  fi
  if [ -n "$problems" ]; then
    failed=$((failed + 1))
    failures+=("$name")
    echo "FAIL $name:$problems"
    echo "  \$ facetool $*"
    echo "  exit $rc; wanted the message to name: $needle"
    sed 's/^/  | /' <<< "$message" | head -8
  else
    echo "ok   $name"
  fi
}

skip_case() {
  [[ "$1" =~ $GROUP ]] || return 0
  skipped=$((skipped + 1))
  echo "skip $1: $2"
}

# --- the tables -----------------------------------------------------------------------------
# Bad files: KIND|PATH. Each is given to every file-taking option below.
bad_files() {
  cat <<EOF
missing|$FX/does_not_exist.png
folder|$FX/folder
empty|$FX/empty.png
garbage|$FX/garbage.png
truncated-png|$FX/truncated.png
truncated-exr|$FX/truncated.exr
huge-png|$FX/huge.png
device|/dev/zero
EOF
}

# File slots: GROUP|OPTION-NAME|arguments with @ for the bad file and OUT for the output folder.
file_slots() {
  cat <<'EOF'
infer|image|infer --aligned --init random --input-size 32 --width 8 {BAD} -o {OUT}/infer
infer|model|infer --aligned --model {BAD} {FX}/face.png -o {OUT}/infer
render|albedo|render --albedo {BAD} --normal {FX}/normal.exr --light {FX}/light.json -o {OUT}/out.png
render|normal|render --albedo {FX}/albedo.exr --normal {BAD} --light {FX}/light.json -o {OUT}/out.png
render|visibility|render --albedo {FX}/albedo.exr --normal {FX}/normal.exr --visibility {BAD} --light {FX}/light.json -o {OUT}/out.exr
render|mask|render --albedo {FX}/albedo.exr --normal {FX}/normal.exr --mask {BAD} --light {FX}/light.json -o {OUT}/out.png
render|light|render --albedo {FX}/albedo.exr --normal {FX}/normal.exr --light {BAD} -o {OUT}/out.png
light|from-envmap|light from-envmap {BAD} -o {OUT}/light.json
light|convert|light convert {BAD} {OUT}/light.txt --to sfsnet
light|show|light show {BAD} -o {OUT}/preview.png
synth|mesh|synth --mesh {BAD} --lights {FX}/light_sfsnet.txt -o {OUT}/synth --size 16
synth|lights|synth --mesh {FX}/triangle.obj --lights {BAD} -o {OUT}/synth --size 16
synth|backgrounds|synth --mesh {FX}/triangle.obj --lights {FX}/light_sfsnet.txt --backgrounds {BAD} -o {OUT}/synth --size 16
synth|face-model|synth --face-model {BAD} --lights {FX}/light_sfsnet.txt -o {OUT}/synth --size 16
plugins|plugin|--plugin {BAD} plugins
fit|face-model|fit --face-model {BAD} {FX}/face.png -o {OUT}/fit
EOF
}

# Option cases: GROUP/NAME|NAMED THING|arguments ({OUT}, {FX} as above).
option_cases() {
  cat <<'EOF'
global/no-command|no command|
global/unknown-command|nonsense|nonsense
global/unknown-option|--nonsense|--nonsense
global/unknown-backend|nonsense|--backend nonsense backends
global/unknown-backend-infer|nonsense|--backend nonsense infer --aligned --init random {FX}/face.png -o {OUT}/infer
global/unknown-backend-render|nonsense|--backend nonsense render --albedo {FX}/albedo.exr --normal {FX}/normal.exr --light {FX}/light.json -o {OUT}/out.png
global/opencl-bad-index|index 99|--backend opencl:99 backends
backends/unknown-option|--nonsense|backends --nonsense
plugins/unknown-option|--nonsense|plugins --nonsense
plugins/truncated-plugin|truncated.ftplugin.so|--plugin {FX}/truncated.ftplugin.so plugins
plugins/text-plugin|text.ftplugin.so|--plugin {FX}/text.ftplugin.so plugins
plugins/missing-plugin-render|nonsense|render --albedo {FX}/albedo.exr --normal {FX}/normal.exr --light {FX}/light.json --renderer nonsense -o {OUT}/out.png
bench/unknown-target|nonsense|bench nonsense
bench/no-target|bench|bench
bench/batches-letters|--batches|bench ops --batches 1,x
bench/batches-zero|--batches|bench ops --batches 0
bench/batches-negative|--batches|bench ops --batches=-3
bench/repeats-letters|--repeats|bench ops --repeats x
bench/repeats-0|--repeats|bench ops --repeats 0
bench/width-0|--width|bench network --width 0
bench/input-size-0|--input-size|bench render --input-size 0
bench/train-batch-negative|--train-batch|bench network --train-batch=-3
infer/no-images|input images|infer --aligned --init random -o {OUT}/infer
infer/no-output|-o|infer --aligned --init random {FX}/face.png
infer/model-and-init|--model|infer --aligned --init random --model {FX}/raw.safetensors {FX}/face.png -o {OUT}/infer
infer/init-unknown|--init|infer --init zeros {FX}/face.png -o {OUT}/infer
infer/batch-0|--batch|infer --aligned --init random --batch 0 {FX}/face.png -o {OUT}/infer
infer/batch-letters|--batch|infer --aligned --init random --batch x {FX}/face.png -o {OUT}/infer
infer/width-0|--width|infer --aligned --init random --width 0 {FX}/face.png -o {OUT}/infer
infer/input-size-0|--input-size|infer --aligned --init random --input-size 0 {FX}/face.png -o {OUT}/infer
infer/seed-negative|--seed|infer --aligned --init random --seed=-1 {FX}/face.png -o {OUT}/infer
infer/unknown-network|nonsense|infer --aligned --init random --network nonsense {FX}/face.png -o {OUT}/infer
infer/unknown-renderer|nonsense|infer --aligned --init random --renderer nonsense {FX}/face.png -o {OUT}/infer
infer/model-not-weights|raw.safetensors|infer --aligned --model {FX}/raw.safetensors {FX}/face.png -o {OUT}/infer
infer/model-truncated|truncated.safetensors|infer --aligned --model {FX}/truncated.safetensors {FX}/face.png -o {OUT}/infer
infer/image-nan-exr|nan.exr|infer --aligned --init random --input-size 32 --width 8 {FX}/nan.exr -o {OUT}/infer
infer/output-is-a-file|out.png|infer --aligned --init random --input-size 32 --width 8 {FX}/face.png -o {OUT}/out.png
infer/contact-sheet-missing-folder|no_such_folder|infer --aligned --init random --input-size 32 --width 8 {FX}/face.png -o {OUT}/infer --contact-sheet {OUT}/no_such_folder/sheet.png
infer/raw-output-missing-folder|no_such_folder|infer --aligned --init random --input-size 32 --width 8 {FX}/face.png -o {OUT}/infer --raw-output {OUT}/no_such_folder/raw.safetensors
infer/out-and-output|--output|infer --aligned --init random {FX}/face.png -o {OUT}/infer --out {OUT}/infer
render/no-output|-o|render --albedo {FX}/albedo.exr --normal {FX}/normal.exr --light {FX}/light.json
render/output-jpeg|out.jpg|render --albedo {FX}/albedo.exr --normal {FX}/normal.exr --light {FX}/light.json -o {OUT}/out.jpg
render/output-missing-folder|no_such_folder|render --albedo {FX}/albedo.exr --normal {FX}/normal.exr --light {FX}/light.json -o {OUT}/no_such_folder/out.png
render/output-folder|names a folder|render --albedo {FX}/albedo.exr --normal {FX}/normal.exr --light {FX}/light.json -o {OUT}/
render/light-format-unknown|--light-format|render --albedo {FX}/albedo.exr --normal {FX}/normal.exr --light {FX}/light.json --light-format nonsense -o {OUT}/out.png
render/light-format-wrong|light.json|render --albedo {FX}/albedo.exr --normal {FX}/normal.exr --light {FX}/light.json --light-format sfsnet -o {OUT}/out.png
render/light-infinite|infinite.json|render --albedo {FX}/albedo.exr --normal {FX}/normal.exr --light {FX}/infinite.json -o {OUT}/out.png
render/light-no-coefficients|nocoeffs.json|render --albedo {FX}/albedo.exr --normal {FX}/normal.exr --light {FX}/nocoeffs.json -o {OUT}/out.png
render/light-truncated-json|truncated.json|render --albedo {FX}/albedo.exr --normal {FX}/normal.exr --light {FX}/truncated.json -o {OUT}/out.png
render/light-nan-sfsnet|nan_sfsnet.txt|render --albedo {FX}/albedo.exr --normal {FX}/normal.exr --light {FX}/nan_sfsnet.txt -o {OUT}/out.png
render/light-short-dpr|short_dpr.txt|render --albedo {FX}/albedo.exr --normal {FX}/normal.exr --light {FX}/short_dpr.txt -o {OUT}/out.png
render/size-mismatch|picture.png|render --albedo {FX}/picture.png --normal {FX}/normal.exr --light {FX}/light.json -o {OUT}/out.png
render/visibility-three-channels|albedo.exr|render --albedo {FX}/albedo.exr --normal {FX}/normal.exr --visibility {FX}/albedo.exr --light {FX}/light.json -o {OUT}/out.exr
render/albedo-nan|nan.exr|render --albedo {FX}/nan.exr --normal {FX}/nan.exr --light {FX}/light.json -o {OUT}/out.exr
render/missing-albedo|--albedo|render --normal {FX}/normal.exr --light {FX}/light.json -o {OUT}/out.png
light/no-subcommand|light|light
light/unknown-subcommand|nonsense|light nonsense
light/from-envmap-no-output|-o|light from-envmap {FX}/picture.png
light/from-envmap-rotate-letters|--rotate|light from-envmap {FX}/picture.png --rotate a,b,c -o {OUT}/light.json
light/from-envmap-rotate-two|--rotate|light from-envmap {FX}/picture.png --rotate 1,2 -o {OUT}/light.json
light/from-envmap-rotate-nan|--rotate|light from-envmap {FX}/picture.png --rotate nan,0,0 -o {OUT}/light.json
light/from-envmap-missing-folder|no_such_folder|light from-envmap {FX}/picture.png -o {OUT}/no_such_folder/light.json
light/convert-no-output|OUT|light convert {FX}/light.json --to sfsnet
light/convert-to-unknown|nonsense|light convert {FX}/light.json {OUT}/light.txt --to nonsense
light/convert-from-unknown|nonsense|light convert {FX}/light.json {OUT}/light.txt --to sfsnet --from nonsense
light/convert-from-wrong|light_sfsnet.txt|light convert {FX}/light_sfsnet.txt {OUT}/light.txt --to dpr --from dpr
light/convert-infinite|infinite.json|light convert {FX}/infinite.json {OUT}/light.txt --to sfsnet
light/convert-nan|nan_sfsnet.txt|light convert {FX}/nan_sfsnet.txt {OUT}/light.json --to facetool
light/convert-missing-folder|no_such_folder|light convert {FX}/light.json {OUT}/no_such_folder/light.txt --to sfsnet
light/convert-output-is-folder|infer|light convert {FX}/light.json {OUT}/infer --to sfsnet
light/show-size-0|--size|light show {FX}/light.json -o {OUT}/preview.png --size 0
light/show-size-huge|--size|light show {FX}/light.json -o {OUT}/preview.png --size 100000
light/show-size-letters|--size|light show {FX}/light.json -o {OUT}/preview.png --size x
light/show-jpeg|preview.jpg|light show {FX}/light.json -o {OUT}/preview.jpg
light/show-missing-folder|no_such_folder|light show {FX}/light.json -o {OUT}/no_such_folder/p.png
light/show-output-is-folder|infer|light show {FX}/light.json -o {OUT}/infer
light/show-infinite|infinite.json|light show {FX}/infinite.json -o {OUT}/preview.png
synth/no-output|-o|synth --mesh {FX}/triangle.obj --lights {FX}/light_sfsnet.txt
synth/no-source|--face-model|synth --lights {FX}/light_sfsnet.txt -o {OUT}/synth
synth/mesh-and-face-model|--face-model|synth --mesh {FX}/triangle.obj --face-model {FX}/folder --lights {FX}/light_sfsnet.txt -o {OUT}/synth
synth/size-0|--size|synth --mesh {FX}/triangle.obj --lights {FX}/light_sfsnet.txt -o {OUT}/synth --size 0
synth/size-letters|--size|synth --mesh {FX}/triangle.obj --lights {FX}/light_sfsnet.txt -o {OUT}/synth --size x
synth/size-negative|--size|synth --mesh {FX}/triangle.obj --lights {FX}/light_sfsnet.txt -o {OUT}/synth --size=-16
synth/count-negative|--count|synth --mesh {FX}/triangle.obj --lights {FX}/light_sfsnet.txt -o {OUT}/synth --count=-1
synth/seed-negative|--seed|synth --mesh {FX}/triangle.obj --lights {FX}/light_sfsnet.txt -o {OUT}/synth --seed=-1
synth/threads-0|--threads|synth --mesh {FX}/triangle.obj --lights {FX}/light_sfsnet.txt -o {OUT}/synth --threads 0
synth/shard-out-of-range|--shard|synth --mesh {FX}/triangle.obj --lights {FX}/light_sfsnet.txt -o {OUT}/synth --shard 3/2
synth/shard-letters|--shard|synth --mesh {FX}/triangle.obj --lights {FX}/light_sfsnet.txt -o {OUT}/synth --shard x
synth/directions-0|--directions|synth --mesh {FX}/triangle.obj --lights {FX}/light_sfsnet.txt -o {OUT}/synth --directions 0
synth/identity-truncation-nan|--identity-truncation|synth --face-model {FX}/empty_dir --lights {FX}/light_sfsnet.txt -o {OUT}/synth --identity-truncation nan
synth/identity-truncation-tiny|--identity-truncation|synth --face-model {FX}/empty_dir --lights {FX}/light_sfsnet.txt -o {OUT}/synth --identity-truncation 1e-300
synth/max-expressions-negative|--max-expressions|synth --mesh {FX}/triangle.obj --lights {FX}/light_sfsnet.txt -o {OUT}/synth --max-expressions=-1
synth/contact-sheet-rows-negative|--contact-sheet-rows|synth --mesh {FX}/triangle.obj --lights {FX}/light_sfsnet.txt -o {OUT}/synth --contact-sheet-rows=-1
synth/mesh-bad-index|bad_index.obj|synth --mesh {FX}/bad_index.obj --lights {FX}/light_sfsnet.txt -o {OUT}/synth --size 16
synth/face-model-empty|empty_dir|synth --face-model {FX}/empty_dir --lights {FX}/light_sfsnet.txt -o {OUT}/synth --size 16
synth/lights-empty-folder|empty_dir|synth --mesh {FX}/triangle.obj --lights {FX}/empty_dir -o {OUT}/synth --size 16
synth/lights-nan|nan_sfsnet.txt|synth --mesh {FX}/triangle.obj --lights {FX}/nan_sfsnet.txt -o {OUT}/synth --size 16
synth/unknown-renderer|nonsense|synth --mesh {FX}/triangle.obj --lights {FX}/light_sfsnet.txt -o {OUT}/synth --renderer nonsense --size 16
synth/output-is-a-file|out.png|synth --mesh {FX}/triangle.obj --lights {FX}/light_sfsnet.txt -o {OUT}/out.png --size 16
fit/no-images|input photos|fit --face-model {FX}/folder -o {OUT}/fit
fit/no-output|-o|fit --face-model {FX}/folder {FX}/face.png
fit/no-face-model|--face-model|fit {FX}/face.png -o {OUT}/fit
fit/camera-unknown|--camera|fit --face-model {FX}/folder --camera fisheye {FX}/face.png -o {OUT}/fit
fit/jaw-unknown|--jaw|fit --face-model {FX}/folder --jaw nonsense {FX}/face.png -o {OUT}/fit
fit/fov-0|--fov|fit --face-model {FX}/folder --fov 0 {FX}/face.png -o {OUT}/fit
fit/fov-nan|--fov|fit --face-model {FX}/folder --fov nan {FX}/face.png -o {OUT}/fit
fit/directions-0|--directions|fit --face-model {FX}/folder --directions 0 {FX}/face.png -o {OUT}/fit
fit/identity-prior-negative|--identity-prior|fit --face-model {FX}/folder --identity-prior=-1 {FX}/face.png -o {OUT}/fit
fit/shard-out-of-range|--shard|fit --face-model {FX}/folder --shard 3/2 {FX}/face.png -o {OUT}/fit
fit/output-is-a-file|out.png|fit --face-model {FX}/folder {FX}/face.png -o {OUT}/out.png
fit/image-missing|does_not_exist.png|fit --face-model {FX}/folder {FX}/does_not_exist.png -o {OUT}/fit
fit/infer-with-fit-no-face-model|--face-model|infer --with-fit --init random {FX}/face.png -o {OUT}/infer
fit/infer-with-fit-aligned|--with-fit|infer --with-fit --aligned --init random --face-model {FX}/folder {FX}/face.png -o {OUT}/infer
fit/pseudo-label-from-unknown|--from|pseudo-label --from nonsense {FX}/face.png -o {OUT}/pl
fit/pseudo-label-fit-no-face-model|--face-model|pseudo-label --from fit {FX}/face.png -o {OUT}/pl
fit/pseudo-label-fit-and-model|--model|pseudo-label --from fit --face-model {FX}/folder --model {FX}/raw.safetensors {FX}/face.png -o {OUT}/pl
EOF
}

# Runs a table line's arguments: {OUT}, {FX} and {BAD} replaced, split on blanks (no blanks in paths here).
run_table_case() {
  local name=$1 needle=$2 line=$3 bad=${4:-}
  [[ "$name" =~ $GROUP ]] || return 0
  local out="$WORK/out/${name//\//_}"
  rm -rf "$out"
  seed_output "$out"
  line=${line//\{OUT\}/$out}
  line=${line//\{FX\}/$FX}
  line=${line//\{BAD\}/$bad}
  local -a words
  read -r -a words <<< "$line"
  run_case_in "$name" "$needle" "$out" "${words[@]}"
}

# --- full and read-only disks ---------------------------------------------------------------
# Fills DIR's file system so that not even a small file fits.
fill_up() {
  dd if=/dev/zero of="$1/.filler" bs=4k > /dev/null 2>&1
  dd if=/dev/zero of="$1/.filler2" bs=512 > /dev/null 2>&1
  true
}

full_disk_cases() {
  local disk=$WORK/disk
  mkdir -p "$disk"
  if ! mount -t tmpfs -o size=2m tmpfs "$disk" 2> /dev/null; then
    for n in infer-again render light-show light-convert light-from-envmap raw-output synth \
             read-only-render read-only-infer; do
      skip_case "disk/$n" "cannot mount a tmpfs here (needs root or CAP_SYS_ADMIN)"
    done
    return 0
  fi
  local seeded=$disk/out
  # Good outputs of a first run, then a full disk, then the same commands again.
  mkdir -p "$seeded"
  "$FACETOOL" infer --aligned --init random --input-size 32 --width 8 "$FX/face.png" -o "$seeded/infer" \
    --raw-output "$seeded/raw.safetensors" > /dev/null 2>&1
  cp "$FX/face.png" "$seeded/out.png"; cp "$FX/face.png" "$seeded/out_shading.png"
  cp "$FX/face.png" "$seeded/preview.png"; cp "$FX/light.json" "$seeded/light.json"
  cp "$FX/light_sfsnet.txt" "$seeded/light.txt"
  fill_up "$disk"
  local common="--aligned --init random --input-size 32 --width 8"
  # shellcheck disable=SC2086
  run_case_in disk/infer-again "No space left" "$seeded" infer $common --seed 7 "$FX/face.png" -o "$seeded/infer"
  run_case_in disk/render "No space left" "$seeded" render --albedo "$FX/albedo.exr" --normal "$FX/normal.exr" --light "$FX/light.json" -o "$seeded/out.png"
  run_case_in disk/light-show "No space left" "$seeded" light show "$FX/light.json" -o "$seeded/preview.png"
  run_case_in disk/light-convert "No space left" "$seeded" light convert "$FX/light.json" "$seeded/light.txt" --to sfsnet
  run_case_in disk/light-from-envmap "No space left" "$seeded" light from-envmap "$FX/picture.png" -o "$seeded/light.json"
  # shellcheck disable=SC2086
  run_case_in disk/raw-output "No space left" "$seeded" infer $common --no-contact-sheet "$FX/face.png" -o "$seeded/infer" --raw-output "$seeded/raw.safetensors"
  run_case_in disk/synth "No space left" "$seeded" synth --mesh "$FX/triangle.obj" --lights "$FX/light_sfsnet.txt" -o "$seeded/synth" --size 16
  umount "$disk"
  # A read-only file system: the OS reason must be given, nothing written.
  if mount -t tmpfs -o size=2m tmpfs "$disk" 2> /dev/null; then
    mkdir -p "$seeded" && cp "$FX/face.png" "$seeded/out.png"
    mkdir -p "$seeded/infer"
    mount -o remount,ro "$disk"
    run_case_in disk/read-only-render "Read-only file system" "$seeded" render --albedo "$FX/albedo.exr" --normal "$FX/normal.exr" --light "$FX/light.json" -o "$seeded/out.png"
    # shellcheck disable=SC2086
    run_case_in disk/read-only-infer "Read-only file system" "$seeded" infer $common "$FX/face.png" -o "$seeded/infer"
    umount "$disk"
  fi
}

# --- run ------------------------------------------------------------------------------------
if ! make_fixtures > "$WORK/fixtures.log" 2>&1; then
  echo "bad_input_cases.sh: could not make the fixtures with $FACETOOL:" >&2
  cat "$WORK/fixtures.log" >&2
  exit 1
fi

while IFS='|' read -r kind path; do
  while IFS='|' read -r group option line; do
    run_table_case "$group/$option-$kind" "$(basename "$path")" "$line" "$path"
  done < <(file_slots)
done < <(bad_files)
while IFS='|' read -r name needle line; do
  run_table_case "$name" "$needle" "$line"
done < <(option_cases)
if [[ "disk/" =~ $GROUP ]] || [[ "disk/x" =~ $GROUP ]]; then full_disk_cases; fi

echo
echo "$tried cases: $failed failed, $skipped skipped"
[ ${#failures[@]} -eq 0 ] || printf '  failed: %s\n' "${failures[@]}"
if [ "$REPORT" -eq 1 ]; then
  echo "probe figures: cases tried $tried, crashes $crashes, hangs $hangs," \
       "data losses $losses, unclear messages $unclear, exit 0 on bad input $wrong_exit"
fi
[ "$failed" -eq 0 ]
