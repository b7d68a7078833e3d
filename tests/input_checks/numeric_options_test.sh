#!/usr/bin/env bash
# Every numeric option of every command, given a non-finite, absurd or out-of-range value, must
# stop at once (no hang: each run has 60 s) with a non-zero exit and a message naming the option;
# a value inside the range must pass the check. Usage: numeric_options_test.sh FACETOOL
set -u
facetool=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0

# expect_refused "<option>" <value> <arguments...>
expect_refused() {
  local option=$1 value=$2
  shift 2
  local output rc
  output=$(timeout 60 "$facetool" "$@" "--$option=$value" 2>&1)
  rc=$?
  if [ "$rc" -eq 0 ] || [ "$rc" -eq 124 ] || [ "$rc" -ge 128 ]; then
    echo "FAIL: $* --$option=$value exited $rc (0: accepted, 124: hang, >=128: crash)"
    failures=$((failures + 1))
  elif ! grep -q -- "--$option" <<<"$output"; then
    echo "FAIL: $* --$option=$value: the message does not name --$option: $output"
    failures=$((failures + 1))
  fi
}

# expect_in_range "<option>" <value> <arguments...>: the range check lets it through.
expect_in_range() {
  local option=$1 value=$2
  shift 2
  local output
  output=$(timeout 60 "$facetool" "$@" "--$option=$value" 2>&1)
  if grep -q -- "--$option must be\|--$option.*is invalid" <<<"$output"; then
    echo "FAIL: $* --$option=$value is valid but was refused: $output"
    failures=$((failures + 1))
  fi
}

# command arguments that get past the required options without doing real work
synth=(synth --out "$work/synth" --mesh "$work/missing.obj")
bench=(bench nonsense-target)
infer=(infer --init random -o "$work/infer" "$work/missing.png")
show=(light show "$work/missing.json" -o "$work/x.png")

for value in nan inf -inf 1e300 -1e300 -3 abc ""; do
  for option in count threads directions max-expressions contact-sheet-rows identity-truncation; do
    expect_refused "$option" "$value" "${synth[@]}"
  done
  for option in repeats width input-size train-batch; do
    expect_refused "$option" "$value" "${bench[@]}"
  done
  for option in width input-size batch; do
    expect_refused "$option" "$value" "${infer[@]}"
  done
  expect_refused size "$value" "${show[@]}"
done
for value in nan 1e300 abc; do
  expect_refused seed "$value" "${synth[@]}"
  expect_refused seed "$value" "${infer[@]}"
done
# The listed examples of issue 10: endless loops and silently replaced values.
for value in 1e-300 0 0.001 101; do expect_refused identity-truncation "$value" "${synth[@]}"; done
expect_refused directions 0 "${synth[@]}"
expect_refused threads 0 "${synth[@]}"
expect_refused batch 0 "${infer[@]}"
expect_refused size 15 "${show[@]}"
expect_refused size 4097 "${show[@]}"
expect_refused repeats 0 "${bench[@]}"
expect_refused batch 1025 "${infer[@]}"
expect_refused input-size 1025 "${bench[@]}"
expect_refused count 10000001 "${synth[@]}"
# --batches is a list: each entry is checked.
output=$(timeout 60 "$facetool" bench ops --batches=1,2000 2>&1)
if [ $? -eq 0 ] || ! grep -q -- "--batches" <<<"$output"; then
  echo "FAIL: bench --batches=1,2000 was not refused naming --batches: $output"
  failures=$((failures + 1))
fi

# Values inside the ranges pass the check (the command then fails for its missing inputs).
expect_in_range identity-truncation 2.5 "${synth[@]}"
expect_in_range identity-truncation 0.01 "${synth[@]}"
expect_in_range directions 8 "${synth[@]}"
expect_in_range count 0 "${synth[@]}"
expect_in_range seed 18446744073709551615 "${synth[@]}"
expect_in_range train-batch 0 "${bench[@]}"
expect_in_range batch 1 "${infer[@]}"
expect_in_range size 16 "${show[@]}"

if [ "$failures" -ne 0 ]; then
  echo "$failures numeric option case(s) failed"
  exit 1
fi
echo "all numeric option cases passed"
