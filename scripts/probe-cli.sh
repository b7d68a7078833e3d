#!/usr/bin/env bash
# Runs every bad-input case of tests/cli against the built facetool and prints the probe figures
# of issues #10 and #21: cases tried, crashes (death by signal), hangs (time limit), data losses
# (the output folder changed), unclear messages (the named file or option missing, raw library
# text, or a raw escape byte). The cases cover every command, non-regular files, outputs over
# inputs, two runs at once, signals and ulimit -f/-v. Full-disk cases need to mount a tmpfs
# (root); they are skipped with a reason otherwise.
#
# usage: scripts/probe-cli.sh [path/to/facetool]   (default: build/bin/facetool)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
facetool=${1:-$root/build/bin/facetool}
[ -x "$facetool" ] || { echo "probe-cli.sh: build facetool first (scripts/build.sh); '$facetool' not found" >&2; exit 2; }
work=$(mktemp -d "${TMPDIR:-/tmp}/facetool-probe.XXXXXX")
trap 'rm -rf "$work"' EXIT
export FACETOOL_BACKEND_PATH=${FACETOOL_BACKEND_PATH:-$(dirname "$facetool")}
status=0
bash "$root/tests/cli/bad_input_cases.sh" "$facetool" --work "$work" --report | tee "$work/log" |
  grep -v '^ok ' || status=$?
grep -q '^probe figures' "$work/log" || exit 1
grep -q ' 0 failed' "$work/log"
