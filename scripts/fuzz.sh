#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan) in build-fuzz and runs one or all of them for
# SECONDS each (default: all, 60 s); crashing, hanging or leaking inputs are kept as regression
# files under tests/fuzz/regressions/<target>/, which the normal test suite replays.
# usage: scripts/fuzz.sh [TARGET|all] [SECONDS]    targets: all_targets below
# FACETOOL_FUZZ_RUNS=N stops a target after N executions when that comes before SECONDS (the
# documented long run: FACETOOL_FUZZ_RUNS=1000000 scripts/fuzz.sh all 3600).
set -euo pipefail
cd "$(dirname "$0")/.."
target=${1:-all}
seconds=${2:-60}
all_targets=(safetensors light_json light_text obj synth_sample plugin_descriptor image_file)
if [ "$target" = all ]; then
  targets=("${all_targets[@]}")
elif [[ " ${all_targets[*]} " == *" $target "* ]]; then
  targets=("$target")
else
  echo "fuzz: unknown target '$target'; targets: all ${all_targets[*]}" >&2
  exit 2
fi
build=${FACETOOL_FUZZ_BUILD_DIR:-build-fuzz}
jobs=${FACETOOL_JOBS:-2}

mkdir -p "$build"
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DFACETOOL_BUILD_FUZZERS=ON -DFACETOOL_BUILD_OPENCL=OFF > "$build/configure.log" 2>&1 ||
  { cat "$build/configure.log"; exit 1; }
cmake --build "$build" -j "$jobs" --target $(printf 'fuzz_%s ' "${targets[@]}")

found=0
for t in "${targets[@]}"; do
  corpus="$build/fuzz-corpus/$t"        # grows from run to run (not committed)
  artifacts="$build/fuzz-artifacts/$t"
  rm -rf "$artifacts"
  mkdir -p "$corpus" "$artifacts"
  inputs=("$corpus" "tests/fuzz/seeds/$t")
  [ -d "tests/fuzz/regressions/$t" ] && inputs+=("tests/fuzz/regressions/$t")
  log="$build/fuzz-$t.log"
  # -timeout: an input taking over 10 s is a hang; -rss_limit_mb: over 2 GiB is unbounded memory.
  "$build/bin/fuzz_$t" "${inputs[@]}" -max_total_time="$seconds" -runs="${FACETOOL_FUZZ_RUNS:--1}" \
    -print_final_stats=1 \
    -timeout=10 -rss_limit_mb=2048 -artifact_prefix="$artifacts/" > "$log" 2>&1 || true
  executions=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  speed=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  echo "fuzz: $t: ${executions:-?} executions (${speed:-?}/s, limit ${seconds}s), corpus $(ls "$corpus" | wc -l) inputs"
  for f in "$artifacts"/*; do
    [ -e "$f" ] || continue
    mkdir -p "tests/fuzz/regressions/$t"
    cp "$f" "tests/fuzz/regressions/$t/"
    found=1
    echo "fuzz: $t: kept $(basename "$f") in tests/fuzz/regressions/$t/ (log: $log)"
    grep -m1 -E "ERROR|fuzz invariant|terminate called|libFuzzer: deadly" "$log" || true
  done
done
if [ "$found" -ne 0 ]; then
  echo "fuzz: inputs found that crash, hang or leak; fix the parser, keep the files (the test suite replays them)"
  exit 1
fi
echo "fuzz: nothing found"
