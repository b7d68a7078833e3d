#!/usr/bin/env bash
# Runs a table of bad-input facetool invocations under valgrind (memcheck) and reports, per case,
# memory errors, crashes, hangs, bad input that was accepted (exit 0) and messages that are a
# library's rather than facetool's (UNCLEAR). Every case must fail cleanly: a non-zero exit of its
# own with facetool's message, no valgrind error.   usage: scripts/valgrind-cli.sh [FILTER]
set -uo pipefail
cd "$(dirname "$0")/.."
facetool=${FACETOOL_BIN:-build/bin/facetool}
[ -x "$facetool" ] || { echo "valgrind-cli: $facetool not built; run scripts/build.sh" >&2; exit 2; }
command -v valgrind > /dev/null || { echo "valgrind-cli: valgrind not installed (scripts/install-dependencies.sh)" >&2; exit 2; }
filter=${1:-}
limit=${FACETOOL_VALGRIND_TIMEOUT:-300}  # seconds per case; longer counts as a hang
facetool=$(realpath "$facetool")
plugin_dir=$(dirname "$facetool")
suppressions=$PWD/tests/sanitize/valgrind.supp
work=$(mktemp -d "${TMPDIR:-/tmp}/facetool-valgrind-XXXXXX")
# The folder (with each case's output and valgrind log) is kept when a case fails.
keep=0
trap '[ "$keep" -eq 1 ] || rm -rf "$work"' EXIT
cd "$work"

# Bad inputs, made here so that nothing depends on files outside the build.
: > empty.png
printf '\x89PNG\r\n\x1a\n\0\0\0\rIHDR\0\1\x86\xa0\0\1\x86\xa0\x08\x02\0\0\0' > cut-header.png
# A well-formed PNG header (valid CRCs) that claims 100000 x 100000 pixels.
python3 - <<'PY'
import struct, zlib
def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
ihdr = struct.pack(">IIBBBBB", 100000, 100000, 8, 2, 0, 0, 0)
open("huge-header.png", "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) +
                                    chunk(b"IDAT", zlib.compress(b"\0" * 16)) + chunk(b"IEND", b""))
PY
head -c 100 /dev/urandom > noise.exr
mkdir -p a-folder plug out
printf '\x10\0\0\0\0\0\0\0{"a":{"dtype":"F3' > cut.safetensors
printf '{"format": "facetool-light", "version": 1, "coefficients": {"r": [1]}}' > short.json
printf '{"format": 7}' > format-number.json
printf 'nan 0 0 0 0 0 0 0 0\n' > nan-dpr.txt
printf '1 2 3\n' > three.txt
printf '\x7fELF\x02\x01\x01\0' > plug/truncated.ftplugin.so
# A real plugin cut after 3000 bytes: its program headers point past the end of the file.
head -c 3000 "$plugin_dir/sh_renderer.ftplugin.so" > plug/cut.ftplugin.so

# name | arguments (word-split; no spaces inside an argument)
cases=(
  "no_command|"
  "unknown_command|nonsense"
  "unknown_backend|--backend nonsense backends"
  "bench_unknown_target|bench nonsense"
  "bench_bad_batches|bench ops --batches 0,x"
  "infer_missing_image|infer missing.png --init random -o out"
  "infer_empty_png|infer empty.png --init random -o out"
  "infer_cut_png_header|infer cut-header.png --init random -o out"
  "infer_png_claims_huge_size|infer huge-header.png --init random -o out"
  "infer_model_missing|infer empty.png --model missing.safetensors -o out"
  "infer_model_folder|infer empty.png --model a-folder -o out"
  "infer_model_truncated|infer empty.png --model cut.safetensors -o out"
  "infer_no_model|infer empty.png -o out"
  "light_show_short|light show short.json -o out/l.png"
  "light_show_format_number|light show format-number.json -o out/l.png"
  "light_convert_nan|light convert nan-dpr.txt out/l.json --to facetool"
  "light_convert_three_numbers|light convert three.txt out/l.json --to facetool"
  "light_convert_bad_format|light convert short.json out/l.txt --to nonsense"
  "light_from_envmap_noise|light from-envmap noise.exr -o out/l.json"
  "light_from_envmap_missing|light from-envmap missing.hdr -o out/l.json"
  "render_missing_inputs|render --albedo missing.png --normal missing.exr --light short.json -o out/f.png"
  "render_noise_normal|render --albedo empty.png --normal noise.exr --light nan-dpr.txt -o out/f.png"
  "synth_missing_face_model|synth --face-model missing --count 1 --out out/s"
  "synth_missing_mesh|synth --mesh missing.obj --count 1 --out out/s"
  "synth_bad_size|synth --mesh missing.obj --size 0 --out out/s"
  "plugins_truncated_library|plugins --plugin plug/truncated.ftplugin.so"
  "plugins_missing_library|plugins --plugin missing.ftplugin.so"
  "plugins_cut_library|plugins --plugin plug/cut.ftplugin.so"
)

failures=0
printf '%-30s %-8s %s\n' case result detail
for entry in "${cases[@]}"; do
  name=${entry%%|*}
  args=${entry#*|}
  [ -n "$filter" ] && [[ "$name" != *$filter* ]] && continue
  # shellcheck disable=SC2086
  FACETOOL_PLUGIN_PATH="$plugin_dir" FACETOOL_BACKEND_PATH="$plugin_dir" timeout "$limit" \
    valgrind -q --error-exitcode=99 --suppressions="$suppressions" --leak-check=full --errors-for-leak-kinds=definite \
    --show-leak-kinds=definite --log-file="$name.valgrind" "$facetool" $args > "$name.out" 2>&1
  rc=$?
  message=$(grep -m1 -i -E "error|cannot|not " "$name.out" | cut -c1-110)
  if [ "$rc" -eq 99 ]; then
    result=MEMORY; detail=$(grep -m1 -E "Invalid|uninitialised|definitely|Mismatched" "$name.valgrind")
  elif [ "$rc" -eq 124 ]; then
    result=HANG; detail="no exit within ${limit}s"
  elif [ "$rc" -gt 128 ]; then
    result=CRASH; detail="signal $((rc - 128)); $(tail -1 "$name.out" | cut -c1-90)"
  elif [ "$rc" -eq 0 ]; then
    result=ACCEPTED; detail="exit 0 on bad input"
  elif grep -q -E "unexpected failure|std::|basic_filebuf|bad_alloc" "$name.out"; then
    result=UNCLEAR; detail="exit $rc: $message"   # a library's message, not facetool's
  else
    result=ok; detail="exit $rc: $message"
  fi
  [ "$result" = ok ] || failures=$((failures + 1))
  printf '%-30s %-8s %s\n' "$name" "$result" "$detail"
done
if [ "$failures" -gt 0 ]; then
  keep=1
  echo "valgrind-cli: logs in $work (CASE.valgrind, CASE.out)"
fi
echo "valgrind-cli: $failures problem(s)"
[ "$failures" -eq 0 ]
