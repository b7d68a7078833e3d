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
# Round two (issue 21) adds every other command (train, eval, pseudo-label, prepare-real, relight,
# bench photo), non-regular files (pipes, dangling links, link loops), outputs over inputs and over
# other runs, two runs into one folder, signals, the file-size and memory limits (ulimit -f/-v),
# and silently wrong inputs (duplicate JSON keys, damaged checkpoint steps, missing shards, escape
# sequences in files). A message must also never carry a raw escape byte from a file.
# Cases are named GROUP/NAME; --group keeps those whose name matches REGEX.
# --report prints the figures of issue #10's probe (cases, crashes, hangs, data losses, unclear
# messages). Exit status: 0 when every case passed.
set -u
FACETOOL=$(realpath "$1")
shift
EXAMPLE_PHOTOS=$(realpath "$(dirname "${BASH_SOURCE[0]}")/../../examples/photos")
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
# Shell commands run before facetool in a case (ulimit ...); empty for most.
LIMITS=''
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
  cp "$FX/face.png" "$FX/face_copy.png"
  cp "$EXAMPLE_PHOTOS/grace_hopper_512x512.jpg" "$FX/photo.jpg"  # a real face, for detection
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
  printf '1e308 0 0 0 0 0 0 0 0\n' > "$FX/huge_dpr.txt"
  printf 'v 0 0 0\nv 1 0 0\nf 1 2 7\n' > "$FX/bad_index.obj"
  head -c 3000 "$(dirname "$FACETOOL")/sh_renderer.ftplugin.so" > "$FX/truncated.ftplugin.so"
  printf 'not a shared library' > "$FX/text.ftplugin.so"
  head -c 40 "$FX/raw.safetensors" > "$FX/truncated.safetensors"
  # An EXR with NaN pixels (oiiotool, when installed; otherwise a damaged EXR of that name).
  if command -v oiiotool > /dev/null; then
    oiiotool --create 8x8 3 --fill:color=nan,0,0 0,0,8,8 -o "$FX/nan.exr" > /dev/null 2>&1 || true
  fi
  [ -f "$FX/nan.exr" ] || cp "$FX/truncated.exr" "$FX/nan.exr"
  make_round_two_fixtures
}

# Issue 21's fixtures: non-regular files, a small dataset, a trained run and its damaged
# checkpoints, eval shards, configurations and light files with hidden faults.
make_round_two_fixtures() {
  mkfifo "$FX/pipe.png" || return 1
  ln -s "$FX/nothing_here.png" "$FX/dangling.png"
  ln -s "$FX/loop_b.png" "$FX/loop_a.png" && ln -s "$FX/loop_a.png" "$FX/loop_b.png"
  "$FACETOOL" synth --mesh "$FX/triangle.obj" --lights "$FX/light_sfsnet.txt" -o "$FX/data" \
    --size 32 --count 8 --threads 1 > /dev/null 2>&1 || return 1
  mkdir -p "$FX/data2" "$FX/synth_out" "$FX/dangling_data" "$FX/loopdir" "$FX/fifo_shard"
  cp "$FX/data/sample_00000000.exr" "$FX/data2/"
  cp "$FX/data/sample_00000000.exr" "$FX/data/sample_00000001.exr" "$FX/synth_out/"
  cp "$FX/data"/sample_0000000[0-3].exr "$FX/dangling_data/"
  ln -s "$FX/dangling_data/gone.exr" "$FX/dangling_data/sample_00000004.exr"
  ln -s "$FX/loopdir/b.png" "$FX/loopdir/a.png" && ln -s "$FX/loopdir/a.png" "$FX/loopdir/b.png"
  mkfifo "$FX/fifo_shard/per_image.csv"
  cat > "$FX/cfg.json" <<'JSON'
{"name": "t", "network": {"width": 4, "input_size": 32}, "optimizer": {"learning_rate": 1e-3},
 "steps": 20, "checkpoint_every": 100, "validation": {"every": 100, "holdout_every": 0}, "seed": 1,
 "sources": [{"name": "s", "directory": "data", "batch": 2,
              "terms": {"albedo": 1, "normal": 0.2, "light": 0.01}}]}
JSON
  sed 's/"steps": 20,/"steps": 20, "steps": 2,/' "$FX/cfg.json" > "$FX/dup.json"
  sed 's/"learning_rate": 1e-3/"learning_rate": 1e-3, "epsilon": 0/' "$FX/cfg.json" > "$FX/eps0.json"
  sed 's/"albedo": 1,/"albedo": 1e308,/' "$FX/cfg.json" > "$FX/bigweight.json"
  sed 's/"directory": "data"/"directory": "dangling_data"/' "$FX/cfg.json" > "$FX/dangling_cfg.json"
  sed 's/"width": 4/"width": 256/; s/"batch": 2/"batch": 8/' "$FX/cfg.json" > "$FX/wide_cfg.json"
  "$FACETOOL" train --config "$FX/cfg.json" --out "$FX/run" --steps 10 > /dev/null 2>&1 || return 1
  # Damaged step counts of the same length as "10", so that the header stays valid.
  cp -r "$FX/run" "$FX/negative" &&
    LC_ALL=C sed -i 's/"step":"10"/"step":"-5"/' "$FX/negative/checkpoint.safetensors"
  cp -r "$FX/run" "$FX/past" &&
    LC_ALL=C sed -i 's/"step":"10"/"step":"99"/' "$FX/past/checkpoint.safetensors"
  cp -r "$FX/run" "$FX/finished" && rm "$FX/finished/checkpoint.safetensors"
  for i in 0 1 2; do
    "$FACETOOL" eval --model "$FX/run/weights.safetensors" --data "$FX/data" --shard "$i/3" \
      -o "$FX/shard$i" > /dev/null 2>&1 || return 1
  done
  "$FACETOOL" prepare-real "$FX/face.png" -o "$FX/real" > /dev/null 2>&1 || return 1
  sed 's/"version": 1,/"version": 1, "version": 1,/' "$FX/light.json" > "$FX/dup_light.json"
  printf '1 2 3\033]0;pwned\007\033[2J\n' > "$FX/escape.txt"
  big_png_header 8000 8000 > "$FX/big.png"
  return 0
}

# A PNG header saying W x H RGB, with 4 KiB of (undecodable) data: enough bytes for its pixel
# count to be plausible, so that only the memory budget refuses it. CRC-32 from gzip's trailer.
big_png_header() {
  be32() { printf '%08x' "$1" | sed 's/../\\x&/g' | xargs -0 printf; }
  local ihdr crc
  ihdr=$(mktemp)
  { printf IHDR; be32 "$1"; be32 "$2"; printf '\x08\x02\x00\x00\x00'; } > "$ihdr"
  crc=$(gzip -c < "$ihdr" | tail -c8 | head -c4 | od -An -tx1 | awk '{printf "%s%s%s%s", $4, $3, $2, $1}')
  printf '\x89PNG\r\n\x1a\n'; be32 13; cat "$ihdr"; be32 "$((16#$crc))"
  be32 4096; printf IDAT; head -c 4096 /dev/zero; be32 0
  rm -f "$ihdr"
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
  mkdir -p "$out/photo" && cp "$FX/photo.jpg" "$out/photo/photo.jpg"  # a photo in its own output folder
  cp "$FX/raw.safetensors" "$out/raw.safetensors"
  # Round two: results of other runs that a bad run must not touch.
  for run in run finished negative past shard0 shard1 shard2 real synth_out; do
    cp -r "$FX/$run" "$out/$run"
  done
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
  if [ -n "$LIMITS" ]; then
    message=$(cd "$WORK" && timeout -k 5 "$TIME_LIMIT" bash -c "$LIMITS; exec \"\$0\" \"\$@\"" \
      "$FACETOOL" "$@" 2>&1 < /dev/null)
  else
    message=$(cd "$WORK" && timeout -k 5 "$TIME_LIMIT" "$FACETOOL" "$@" 2>&1 < /dev/null)
  fi
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
    if ! grep -qF -- "$needle" <<< "$message" || grep -qE -- "$RAW_PHRASES" <<< "$message" ||
       [[ "$message" == *$'\e'* ]]; then
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
pipe|$FX/pipe.png
dangling-link|$FX/dangling.png
link-loop|$FX/loop_a.png
EOF
}

# Round two's special files (what every file facetool reads is checked for), given to the file
# options of the commands beyond infer and render.
special_files() {
  bad_files | grep -E '^(missing|folder|device|pipe|dangling-link|link-loop)[|]'
}

# GROUP|OPTION-NAME|arguments, as file_slots.
round_two_slots() {
  cat <<'EOF'
train|config|train --config {BAD} --out {OUT}/newrun
train|from|train --config {FX}/cfg.json --from {BAD} --out {OUT}/newrun
eval|model|eval --model {BAD} --data {FX}/data -o {OUT}/eval
pseudo-label|input|pseudo-label --model {FX}/run/weights.safetensors {BAD} -o {OUT}/pl
pseudo-label|model|pseudo-label --model {BAD} {FX}/data/sample_00000000.exr -o {OUT}/pl
prepare-real|input|prepare-real {BAD} -o {OUT}/newreal
relight|photo|relight --init random --input-size 32 --width 8 {BAD} --light {FX}/light.json -o {OUT}/relight
relight|light|relight --init random --input-size 32 --width 8 {FX}/face.png --light {BAD} -o {OUT}/relight
relight|envmap|relight --init random --input-size 32 --width 8 {FX}/face.png --envmap {BAD} -o {OUT}/relight
infer|photo|infer --init random --input-size 32 --width 8 {BAD} -o {OUT}/infer
infer|landmark-model|infer --init random --input-size 32 --width 8 --landmark-model {BAD} {FX}/face.png -o {OUT}/infer
bench|photo|bench photo --photo {BAD} --repeats 1
bench|model|bench infer --model {BAD} --photos {FX}/face.png --repeats 1
EOF
}

# Round two's named cases: GROUP/NAME|NAMED THING|arguments.
round_two_cases() {
  cat <<'EOF'
train/config-duplicate-key|"steps" twice|train --config {FX}/dup.json --out {OUT}/newrun
train/epsilon-zero|optimizer.epsilon|train --config {FX}/eps0.json --out {OUT}/newrun
train/loss-weight-huge|terms.albedo|train --config {FX}/bigweight.json --out {OUT}/newrun
train/config-is-a-folder|is a folder|train --config {FX}/folder --out {OUT}/newrun
train/over-a-finished-run|--overwrite|train --config {FX}/cfg.json --out {OUT}/finished
train/resume-step-negative|step -5|train --config {FX}/cfg.json --out {OUT}/negative --resume
train/resume-step-past-the-end|step 99|train --config {FX}/cfg.json --out {OUT}/past --resume
train/data-dangling-sample|dangling symbolic link|train --config {FX}/dangling_cfg.json --out {OUT}/newrun
eval/merge-missing-shard|2/3|eval --merge {OUT}/shard0 {OUT}/shard1 -o {OUT}/merged
eval/merge-output-is-a-shard|shard0|eval --merge {OUT}/shard0 {OUT}/shard1 {OUT}/shard2 -o {OUT}/shard0
eval/merge-pipe-table|per_image.csv|eval --merge {FX}/fifo_shard -o {OUT}/merged
eval/merge-shard-folder-missing|no_such_shard|eval --merge {OUT}/shard0 {FX}/no_such_shard -o {OUT}/merged
eval/data-dangling-sample|dangling symbolic link|eval --model {FX}/run/weights.safetensors --data {FX}/dangling_data -o {OUT}/eval
eval/data-is-a-file|is a file, not a folder|eval --model {FX}/run/weights.safetensors --data {FX}/cfg.json -o {OUT}/eval
infer/contact-sheet-is-an-input|--contact-sheet|infer --aligned --init random --input-size 32 --width 8 {OUT}/out.png -o {OUT}/infer --contact-sheet {OUT}/out.png
infer/raw-output-is-an-input|--raw-output|infer --aligned --init random --input-size 32 --width 8 {OUT}/out.png -o {OUT}/infer --raw-output {OUT}/out.png
infer/folder-of-link-loops|loop of symbolic links|infer --init random --input-size 32 --width 8 {FX}/loopdir -o {OUT}/infer
render/output-is-an-input|is the input|render --albedo {OUT}/out.exr --normal {FX}/normal.exr --light {FX}/light.json -o {OUT}/out.exr
render/shading-output-is-an-input|is the input|render --albedo {OUT}/out_shading.exr --normal {FX}/normal.exr --light {FX}/light.json -o {OUT}/out.exr
render/light-duplicate-key|"version" twice|render --albedo {FX}/albedo.exr --normal {FX}/normal.exr --light {FX}/dup_light.json -o {OUT}/out.png
render/light-escape-sequences|escape.txt|render --albedo {FX}/albedo.exr --normal {FX}/normal.exr --light {FX}/escape.txt -o {OUT}/out.png
light/convert-escape-sequences|escape.txt|light convert {FX}/escape.txt {OUT}/light.txt --to sfsnet
pseudo-label/one-name-two-folders|would both be written|pseudo-label --model {FX}/run/weights.safetensors {FX}/data/sample_00000000.exr {FX}/data2/sample_00000000.exr -o {OUT}/pl
pseudo-label/output-over-its-input|would replace|pseudo-label --model {FX}/run/weights.safetensors {OUT}/synth_out/sample_00000000.exr -o {OUT}/synth_out
prepare-real/over-synthetic-samples|another kind|prepare-real {FX}/face.png -o {OUT}/synth_out
prepare-real/other-settings|other settings|prepare-real {FX}/face.png -o {OUT}/real --size 64
EOF
}

# Round three's (issue 55): inputs in the folders a run writes, refused before any work; another
# shard's results.
round_three_cases() {
  cat <<'EOF'
infer/input-in-its-photo-folder|lies in|infer {OUT}/photo/photo.jpg -o {OUT}
infer/with-fit-input-in-its-photo-folder|lies in|infer --with-fit --face-model {FX}/folder {OUT}/photo/photo.jpg -o {OUT}
fit/input-in-its-photo-folder|lies in|fit --face-model {FX}/folder {OUT}/photo/photo.jpg -o {OUT}
relight/photo-in-its-output-folder|lies in|relight {OUT}/photo/photo.jpg --light {FX}/light.json -o {OUT}
relight/light-from-in-an-output-folder|lies in|relight {FX}/photo.jpg --light-from {OUT}/photo/photo.jpg -o {OUT}
eval/shard-over-another-shard|shard 0/3|eval --model {FX}/run/weights.safetensors --data {FX}/data --shard 1/3 -o {OUT}/shard0
eval/unsharded-over-a-shard|shard 0/3|eval --model {FX}/run/weights.safetensors --data {FX}/data -o {OUT}/shard0
EOF
}

# --- limits, signals and two runs at once (issue 21, classes 2, 3 and 6) ------------------------
# The smallest address-space limit (ulimit -v, KiB) under which `facetool ARGS...` still runs,
# from a few candidates; empty when none works.
smallest_working_memory_limit() {
  local limit
  for limit in 400000 600000 800000 1000000 1300000 1700000 2200000 3000000 4000000; do
    if (ulimit -v "$limit" && "$FACETOOL" "$@" > /dev/null 2>&1) 2> /dev/null; then
      echo "$limit"
      return 0
    fi
  done
}

# Runs a named check that is not a single command: NAME, then a function that prints nothing on
# success and the problem otherwise.
run_check() {
  local name=$1 problem
  shift
  [[ "$name" =~ $GROUP ]] || return 0
  tried=$((tried + 1))
  problem=$("$@" 2>&1)
  if [ -n "$problem" ]; then
    failed=$((failed + 1))
    failures+=("$name")
    case "$problem" in
      *hang*) hangs=$((hangs + 1)) ;;
      *lost*) losses=$((losses + 1)) ;;
    esac
    echo "FAIL $name: $problem" | head -8
  else
    echo "ok   $name"
  fi
}

# Waits (up to 20 s) until FILE exists and is not empty.
wait_for_file() {
  local k
  for k in $(seq 200); do
    [ -s "$1" ] && return 0
    sleep 0.1
  done
  return 1
}

# Two trains into one --out: the second is refused while the first runs; the first's log keeps
# one line per step.
check_two_trains() {
  local dir=$WORK/two_trains first rc
  rm -rf "$dir" && mkdir -p "$dir"
  "$FACETOOL" train --config "$FX/cfg.json" --out "$dir/run" --steps 1000000 > /dev/null 2>&1 &
  first=$!
  wait_for_file "$dir/run/log.jsonl" || { kill "$first"; echo "the first train wrote no log (hang)"; return; }
  message=$(timeout -k 5 "$TIME_LIMIT" "$FACETOOL" train --config "$FX/cfg.json" --out "$dir/run" --steps 1000000 2>&1)
  rc=$?
  kill -TERM "$first"
  wait "$first"
  [ "$rc" -ne 0 ] && [ "$rc" -lt 124 ] || echo "the second train exited $rc: $message"
  grep -q "in use by another facetool run" <<< "$message" || echo "unclear refusal: $message"
  local steps unique
  steps=$(grep -o '"step":[0-9]*' "$dir/run/log.jsonl" | wc -l)
  unique=$(grep -o '"step":[0-9]*' "$dir/run/log.jsonl" | sort -u | wc -l)
  [ "$steps" -eq "$unique" ] || echo "steps logged twice ($steps lines, $unique steps): data lost"
}

# Two synths into one --out: the second is refused; SIGTERM then leaves no temporary behind.
check_two_synths() {
  local dir=$WORK/two_synths first rc
  rm -rf "$dir" && mkdir -p "$dir"
  "$FACETOOL" synth --mesh "$FX/triangle.obj" --lights "$FX/light_sfsnet.txt" -o "$dir/out" \
    --size 32 --count 1000000 --threads 1 > /dev/null 2>&1 &
  first=$!
  wait_for_file "$dir/out/sample_00000001.exr" || { kill "$first"; echo "the first synth wrote nothing (hang)"; return; }
  message=$(timeout -k 5 "$TIME_LIMIT" "$FACETOOL" synth --mesh "$FX/triangle.obj" \
    --lights "$FX/light_sfsnet.txt" -o "$dir/out" --size 32 --count 1000000 2>&1)
  rc=$?
  kill -TERM "$first"
  wait "$first"
  [ "$rc" -ne 0 ] && [ "$rc" -lt 124 ] || echo "the second synth exited $rc: $message"
  grep -q "in use by another facetool run" <<< "$message" || echo "unclear refusal: $message"
  ! ls "$dir/out" | grep -q '\.tmp-' || echo "SIGTERM left temporaries: $(ls "$dir/out" | grep '\.tmp-')"
}

# The shards of one run share a folder, but a second process of the same shard, or a shard of
# another splitting, is refused while the first runs.
check_same_shard() {
  local dir=$WORK/same_shard first rc
  rm -rf "$dir" && mkdir -p "$dir"
  local synth=(synth --mesh "$FX/triangle.obj" --lights "$FX/light_sfsnet.txt" -o "$dir/out" --size 32 --threads 1)
  "$FACETOOL" "${synth[@]}" --count 1000000 --shard 0/2 > /dev/null 2>&1 &
  first=$!
  wait_for_file "$dir/out/sample_00000002.exr" || { kill "$first"; echo "the first shard wrote nothing (hang)"; return; }
  message=$(timeout -k 5 "$TIME_LIMIT" "$FACETOOL" "${synth[@]}" --count 1000000 --shard 0/2 2>&1)
  rc=$?
  [ "$rc" -ne 0 ] && [ "$rc" -lt 124 ] || echo "a second shard 0/2 exited $rc: $message"
  grep -q "in use by another facetool run of shard 0/2" <<< "$message" || echo "unclear refusal of shard 0/2: $message"
  message=$(timeout -k 5 "$TIME_LIMIT" "$FACETOOL" "${synth[@]}" --count 1000000 --shard 1/3 2>&1)
  grep -q "another number of shards" <<< "$message" || echo "shard 1/3 beside 0/2 was not refused: $message"
  message=$(timeout -k 5 "$TIME_LIMIT" "$FACETOOL" "${synth[@]}" --count 4 --shard 1/2 2>&1)
  rc=$?
  [ "$rc" -eq 0 ] || echo "shard 1/2 beside shard 0/2 was refused (exit $rc): $message"
  kill -TERM "$first"
  wait "$first"
}

# SIGHUP stops training like SIGTERM: exit 128+1, a checkpoint, no temporary left.
check_train_sighup() {
  local dir=$WORK/sighup first rc
  rm -rf "$dir" && mkdir -p "$dir"
  "$FACETOOL" train --config "$FX/cfg.json" --out "$dir/run" --steps 1000000 > /dev/null 2> "$dir/err" &
  first=$!
  wait_for_file "$dir/run/log.jsonl" || { kill "$first"; echo "train wrote no log (hang)"; return; }
  kill -HUP "$first"
  wait "$first"
  rc=$?
  [ "$rc" -eq 129 ] || echo "train ended with $rc after SIGHUP, not 129; its stderr ends: $(tail -c 600 "$dir/err" | tr '\r' '\n' | tail -5)"
  [ -s "$dir/run/checkpoint.safetensors" ] || echo "no checkpoint after SIGHUP: the run was lost"
  ! ls "$dir/run" | grep -q '\.tmp-' || echo "SIGHUP left temporaries: $(ls "$dir/run" | grep '\.tmp-')"
}

# train under ulimit -f: the checkpoint that does not fit is reported like a full disk (exit 1,
# not SIGXFSZ), and no temporary is left in the run folder.
check_train_file_size() {
  local dir=$WORK/file_size rc
  rm -rf "$dir" && mkdir -p "$dir"
  message=$( (ulimit -f 40; timeout -k 5 "$TIME_LIMIT" "$FACETOOL" train --config "$FX/cfg.json" \
    --out "$dir/run" --steps 2) 2>&1)
  rc=$?
  [ "$rc" -eq 1 ] || echo "train exited $rc under ulimit -f (a crash by SIGXFSZ is 153)"
  grep -q "file-size limit" <<< "$message" || echo "unclear message: $message"
  ! ls "$dir/run" | grep -q '\.tmp-' || echo "temporaries left: $(ls "$dir/run" | grep '\.tmp-')"
}

# Class 9 (data-parallel training): under mpirun -np 2 a global batch of 1 leaves a rank without
# rows; it hung in the batch-norm sums. Every rank now refuses before the first step.
check_batch_smaller_than_ranks() {
  local mpirun dir=$WORK/ranks rc
  mpirun=$(command -v mpirun || command -v mpiexec) || return 0
  rm -rf "$dir" && mkdir -p "$dir"
  sed 's/"batch": 2/"batch": 1/' "$FX/cfg.json" > "$FX/batch1_cfg.json"
  message=$(timeout -k 5 120 "$mpirun" --allow-run-as-root --oversubscribe -np 2 "$FACETOOL" train \
    --config "$FX/batch1_cfg.json" --out "$dir/run" --steps 2 2>&1 < /dev/null)
  rc=$?
  if grep -q "without MPI" <<< "$message"; then return 0; fi  # facetool built without MPI
  [ "$rc" -ne 124 ] && [ "$rc" -ne 137 ] || { echo "mpirun -np 2 with batch 1 did not end (hang)"; return; }
  [ "$rc" -ne 0 ] || echo "mpirun -np 2 with batch 1 exited 0"
  grep -q "fewer rows than the 2 ranks" <<< "$message" || echo "unclear message: $message"
  [ ! -e "$dir/run/checkpoint.safetensors" ] || echo "a checkpoint was written"
}

# Inputs sharing a name, in any order, each get their own output folder.
check_unique_names() {
  local dir=$WORK/names
  rm -rf "$dir" && mkdir -p "$dir/a" "$dir/b" "$dir/c"
  cp "$FX/face.png" "$dir/a/x.png" && cp "$FX/face.png" "$dir/b/x.png" && cp "$FX/face.png" "$dir/c/x_2.png"
  "$FACETOOL" infer --aligned --init random --input-size 32 --width 8 "$dir/a/x.png" "$dir/b/x.png" \
    "$dir/c/x_2.png" -o "$dir/out" > /dev/null 2>&1 || { echo "infer failed"; return; }
  local folders
  folders=$(find "$dir/out" -mindepth 1 -maxdepth 1 -type d | wc -l)
  [ "$folders" -eq 3 ] || echo "3 inputs gave $folders output folders: an output was lost"
}

# prepare-real -o inside its input folder does not take its own samples as photos on a rerun.
check_prepare_real_inside_input() {
  local dir=$WORK/inside
  rm -rf "$dir" && mkdir -p "$dir/photos"
  cp "$FX/face.png" "$dir/photos/"
  "$FACETOOL" prepare-real "$dir/photos" -o "$dir/photos/real" > /dev/null 2>&1
  "$FACETOOL" prepare-real "$dir/photos" -o "$dir/photos/real" > /dev/null 2>&1 ||
    { echo "the rerun failed"; return; }
  ! grep -q 'real/' "$dir/photos/real/manifest.tsv" || echo "the rerun took its own outputs as photos"
}

limit_cases() {
  local common="--aligned --init random --input-size 32 --width 8"
  # shellcheck disable=SC2086
  LIMITS='ulimit -f 4' run_table_case limits/infer-file-size "file-size limit" \
    "infer $common --seed 9 {FX}/face.png -o {OUT}/infer"
  run_check limits/train-file-size check_train_file_size
  if [[ "limits/memory" =~ $GROUP ]]; then
    local base
    # shellcheck disable=SC2086
    base=$(smallest_working_memory_limit infer $common "$FX/face.png" -o "$WORK/probe_infer")
    if [ -n "$base" ]; then
      LIMITS="ulimit -v $((base + 300000))" run_table_case limits/infer-memory \
        "out of memory while reading image" "infer $common {FX}/big.png -o {OUT}/infer"
    else
      skip_case limits/infer-memory "no address-space limit lets facetool start here"
    fi
    # Detection under 450 MB: dlib's landmark alignment calls OpenBLAS, which retries a failed
    # allocation forever; the budget is checked before (issue 55: it hung).
    # (An address sanitizer's shadow memory cannot live under such a limit: skipped there, as
    # the other memory cases are when nothing starts.)
    base=$(smallest_working_memory_limit backends)
    if [ -n "$base" ] && [ "$base" -le 450000 ]; then
      LIMITS="ulimit -v 450000" run_table_case limits/detect-memory "out of memory while" \
        "detect {FX}/photo.jpg --report {OUT}/faces.csv"
    else
      skip_case limits/detect-memory "facetool does not start under a 450 MB address-space limit here"
    fi
    # Reading EXR samples under 650 MB: the OpenImageIO module maps about 0.4 GB of libraries and
    # one of them starts threads while it loads; where that failed, eval said OpenImageIO was not
    # installed, or the process aborted inside the library (issue 55). The budget is checked first.
    if [ -n "$base" ] && [ "$base" -le 450000 ]; then
      LIMITS="ulimit -v 650000" run_table_case limits/eval-memory "out of memory while loading the module" \
        "eval --model {FX}/run/weights.safetensors --data {FX}/data -o {OUT}/eval"
      LIMITS="ulimit -v 650000" run_table_case limits/pseudo-label-memory "out of memory while loading the module" \
        "pseudo-label --model {FX}/run/weights.safetensors {FX}/data/sample_00000000.exr -o {OUT}/pl"
    else
      skip_case limits/eval-memory "facetool does not start under a 450 MB address-space limit here"
      skip_case limits/pseudo-label-memory "facetool does not start under a 450 MB address-space limit here"
    fi
    base=$(smallest_working_memory_limit synth --mesh "$FX/triangle.obj" --lights "$FX/light_sfsnet.txt" \
      -o "$WORK/probe_synth" --size 32 --count 1)
    if [ -n "$base" ]; then
      LIMITS="ulimit -v $((base + 200000))" run_table_case limits/synth-memory \
        "out of memory while generating a 4096x4096 synthetic sample (needs ~4.7 GB)" \
        "synth --mesh {FX}/triangle.obj --lights {FX}/light_sfsnet.txt -o {OUT}/bigsynth --size 4096 --count 1"
    else
      skip_case limits/synth-memory "no address-space limit lets facetool start here"
    fi
    # Training at width 256 (about 15 M parameters, 0.5 GB a step) with 200 MB more than a
    # width-4 run needs: the message names what was being allocated and about how much.
    base=$(smallest_working_memory_limit train --config "$FX/cfg.json" --out "$WORK/probe_train" --steps 1 --overwrite)
    if [ -n "$base" ]; then
      LIMITS="ulimit -v $((base + 200000))" run_table_case limits/train-memory "(needs ~" \
        "train --config {FX}/wide_cfg.json --out {OUT}/newrun --steps 1"
    else
      skip_case limits/train-memory "no address-space limit lets facetool start here"
    fi
  fi
  run_check concurrency/two-trains-one-folder check_two_trains
  run_check concurrency/two-synths-one-folder check_two_synths
  run_check concurrency/same-shard-one-folder check_same_shard
  run_check signals/train-sighup check_train_sighup
  run_check names/infer-unique-names check_unique_names
  run_check distributed/train-batch-smaller-than-ranks check_batch_smaller_than_ranks
  run_check prepare-real/output-inside-input check_prepare_real_inside_input
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
infer/outputs-unknown|nonsense|infer --init random --input-size 32 --width 8 {FX}/face.png -o {OUT}/infer --outputs normal,nonsense
infer/outputs-with-aligned|--outputs|infer --aligned --init random --input-size 32 --width 8 {FX}/face.png -o {OUT}/infer --outputs normal
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
render/light-huge-dpr|huge_dpr.txt|render --albedo {FX}/albedo.exr --normal {FX}/normal.exr --light {FX}/huge_dpr.txt -o {OUT}/out.png
detect/report-is-the-photo|face_copy.png|detect {FX}/face_copy.png --report {FX}/face_copy.png
detect/report-is-a-fifo|not a regular file|detect {FX}/face_copy.png --report {FX}/pipe.png
light/from-envmap-onto-its-input|input of this run|light from-envmap {FX}/face_copy.png -o {FX}/face_copy.png
light/from-direction-one-angle|azimuth,elevation|light from-direction 30 -o {OUT}/light.json
light/from-direction-nan|azimuth,elevation|light from-direction nan,0 -o {OUT}/light.json
light/from-direction-elevation-over-90|azimuth,elevation|light from-direction 0,120 -o {OUT}/light.json
light/from-direction-negative-ambient|--ambient|light from-direction 30,0 --ambient -1 -o {OUT}/light.json
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
fit/jaw-weight-negative|--jaw-weight|fit --face-model {FX}/folder --jaw-weight=-1 {FX}/face.png -o {OUT}/fit
fit/shard-out-of-range|--shard|fit --face-model {FX}/folder --shard 3/2 {FX}/face.png -o {OUT}/fit
fit/output-is-a-file|out.png|fit --face-model {FX}/folder {FX}/face.png -o {OUT}/out.png
fit/image-missing|does_not_exist.png|fit --face-model {FX}/folder {FX}/does_not_exist.png -o {OUT}/fit
fit/infer-with-fit-no-face-model|--face-model|infer --with-fit --init random {FX}/face.png -o {OUT}/infer
fit/infer-with-fit-aligned|--with-fit|infer --with-fit --aligned --init random --face-model {FX}/folder {FX}/face.png -o {OUT}/infer
fit/pseudo-label-from-unknown|--from|pseudo-label --from nonsense {FX}/face.png -o {OUT}/pl
fit/pseudo-label-fit-no-face-model|--face-model|pseudo-label --from fit {FX}/face.png -o {OUT}/pl
fit/pseudo-label-fit-and-model|--model|pseudo-label --from fit --face-model {FX}/folder --model {FX}/raw.safetensors {FX}/face.png -o {OUT}/pl
fit/unwrap-no-face-model|--face-model|unwrap {FX}/data/sample_00000000.exr -o {OUT}/tex
fit/unwrap-not-a-sample|face.png|unwrap --face-model {FX}/folder {FX}/face.png -o {OUT}/tex
fit/unwrap-sample-missing|does_not_exist.exr|unwrap --face-model {FX}/folder {FX}/does_not_exist.exr -o {OUT}/tex
fit/unwrap-size-0|--size|unwrap --face-model {FX}/folder --size 0 {FX}/data/sample_00000000.exr -o {OUT}/tex
fit/unwrap-one-name-two-folders|would both be written|unwrap --face-model {FX}/folder {FX}/data/sample_00000000.exr {FX}/data2/sample_00000000.exr -o {OUT}/tex
synth/albedo-textures-on-a-mesh|--albedo-textures|synth --mesh {FX}/triangle.obj --lights {FX}/light_sfsnet.txt --albedo-textures {FX}/folder -o {OUT}/synth --size 16
synth/albedo-texture-fraction-alone|--albedo-texture-fraction|synth --mesh {FX}/triangle.obj --lights {FX}/light_sfsnet.txt --albedo-texture-fraction 0.5 -o {OUT}/synth --size 16
synth/albedo-texture-fraction-2|--albedo-texture-fraction|synth --mesh {FX}/triangle.obj --lights {FX}/light_sfsnet.txt --albedo-texture-fraction 2 -o {OUT}/synth --size 16
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
  # A bad device index is the opencl module's to name; a build without it (the sanitizer build)
  # can only say that the module is missing.
  if [[ "$name" == */opencl-* && ! -e "$(dirname "$FACETOOL")/facetool_backend_opencl.so" ]]; then
    [[ "$name" =~ $GROUP ]] && skip_case "$name" "this build has no opencl module"
    continue
  fi
  run_table_case "$name" "$needle" "$line"
done < <(option_cases)
while IFS='|' read -r kind path; do
  while IFS='|' read -r group option line; do
    run_table_case "$group/$option-$kind" "$(basename "$path")" "$line" "$path"
  done < <(round_two_slots)
done < <(special_files)
while IFS='|' read -r name needle line; do
  run_table_case "$name" "$needle" "$line"
done < <(round_two_cases)
while IFS='|' read -r name needle line; do
  run_table_case "$name" "$needle" "$line"
done < <(round_three_cases)
limit_cases
if [[ "disk/" =~ $GROUP ]] || [[ "disk/x" =~ $GROUP ]]; then full_disk_cases; fi

echo
echo "$tried cases: $failed failed, $skipped skipped"
[ ${#failures[@]} -eq 0 ] || printf '  failed: %s\n' "${failures[@]}"
if [ "$REPORT" -eq 1 ]; then
  echo "probe figures: cases tried $tried, crashes $crashes, hangs $hangs," \
       "data losses $losses, unclear messages $unclear, exit 0 on bad input $wrong_exit"
fi
[ "$failed" -eq 0 ]
