#!/usr/bin/env bash
# Fuzzes the safetensors parser with libFuzzer (clang) for SECONDS (default 120); keeps crashes.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-120}
work=$(mktemp -d)
clang++ -std=c++17 -g -O1 -fsanitize=fuzzer,address,undefined -I. \
  tests/fuzz/safetensors_fuzz.cpp core/model/safetensors.cpp core/io/atomic_file.cpp \
  -o "$work/safetensors_fuzz"
mkdir -p "$work/corpus" tests/fuzz/regressions
cp tests/fuzz/regressions/* "$work/corpus/" 2>/dev/null || true
# Seeds: small valid files written by a plain generator.
printf '\x36\x00\x00\x00\x00\x00\x00\x00{"a":{"dtype":"F32","shape":[1],"data_offsets":[0,4]}}\x00\x00\x80\x3f' \
  > "$work/corpus/one"
printf '\x13\x00\x00\x00\x00\x00\x00\x00{"__metadata__":{}}' > "$work/corpus/meta"
"$work/safetensors_fuzz" "$work/corpus" -max_total_time="$seconds" -artifact_prefix="$work/" \
  -max_len=4096 || true
found=0
for f in "$work"/crash-* "$work"/timeout-* "$work"/leak-* "$work"/oom-*; do
  [ -e "$f" ] || continue
  cp "$f" tests/fuzz/regressions/
  found=1
  echo "fuzz: kept $(basename "$f") in tests/fuzz/regressions/"
done
rm -rf "$work"
[ "$found" -eq 0 ] && echo "fuzz: no crash in ${seconds}s"
exit 0
