#!/usr/bin/env bash
# `infer --outputs LIST` on the example photos: exactly the files named (faces.json always), each
# byte for byte the same file of a full run; unknown names and conflicting options are usage errors.
#
# usage: outputs_test.sh FACETOOL SOURCE_DIR
# The reference is a full run (every output) of the same photos with the same options. --batch 1
# in every run: a face then goes through the network alone whatever the writer's pace, so the
# runs see the same batches (the network's floats may differ in the last bit between batch sizes).
set -u
FACETOOL=$1
PHOTOS=$2/examples/photos
WORK=$(mktemp -d "${TMPDIR:-/tmp}/facetool-outputs-test.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
infer() { "$FACETOOL" infer "$PHOTOS" --batch 1 "$@" 2> "$WORK/stderr"; }

infer -o "$WORK/full" || { cat "$WORK/stderr"; echo "FAIL: the full run failed"; exit 1; }
(cd "$WORK/full" && find . -type f | sort) > "$WORK/full.list"
photos=$(cd "$WORK/full" && find . -mindepth 1 -maxdepth 1 -type d | wc -l)
[ "$photos" -ge 2 ] || fail "the full run wrote $photos photo folders, expected one per example photo (2 or more)"

# The files of the full run an output names, as a regex on ./<photo>/<file> (faces.json: always).
pattern_of() {
  case "$1" in
    albedo|normal|visibility|shading|reconstruction) echo "^\./[^/]*/$1\.png$" ;;
    exr) echo '^\./[^/]*/photo\.exr$' ;;
    faces) echo '^$' ;;
    contact-sheet) echo '^\./[^/]*/contact_sheet\.png$' ;;
    face-folders) echo '^\./[^/]*/face_[0-9]+/' ;;
    all) echo '.' ;;
  esac
}

check_outputs() {  # LIST NAME...: infer --outputs LIST writes the full run's files of NAME... and faces.json
  local list=$1 out=$WORK/run-$2
  shift
  if ! infer -o "$out" --outputs "$list"; then
    cat "$WORK/stderr"
    fail "--outputs '$list' exited non-zero"
    return
  fi
  local expected='^\./[^/]*/faces\.json$'
  for name in "$@"; do expected="$expected|$(pattern_of "$name")"; done
  grep -E "$expected" "$WORK/full.list" > "$WORK/expected.list"
  (cd "$out" && find . -type f | sort) > "$WORK/got.list"
  if ! diff -u "$WORK/expected.list" "$WORK/got.list" > "$WORK/diff"; then
    fail "--outputs '$list' wrote other files than the full run's $* and faces.json:"
    cat "$WORK/diff"
  fi
  while read -r file; do
    [ -f "$out/$file" ] || continue
    cmp -s "$WORK/full/$file" "$out/$file" || fail "--outputs '$list': $file differs from the full run's"
  done < "$WORK/got.list"
  echo "ok: --outputs '$list' ($(wc -l < "$WORK/got.list") files, each the full run's)"
}

for name in albedo normal visibility shading reconstruction exr faces contact-sheet face-folders all; do
  check_outputs "$name" "$name"
done
check_outputs "normal, albedo" normal albedo
check_outputs "visibility,face-folders,contact-sheet" visibility face-folders contact-sheet

usage_error() {  # WHAT ARGS...: infer ARGS exits 2 (a usage error); its message is left in $WORK/stderr
  local what=$1
  shift
  "$FACETOOL" infer "$@" 2> "$WORK/stderr"
  local rc=$?
  [ "$rc" -eq 2 ] || { fail "$what: exit $rc, expected 2 (usage error)"; cat "$WORK/stderr"; }
}

usage_error "an unknown name" "$PHOTOS" -o "$WORK/bad" --outputs normal,normals
grep -q "unknown output 'normals'" "$WORK/stderr" || fail "an unknown name: the message does not name it: $(cat "$WORK/stderr")"
for name in albedo normal visibility shading reconstruction exr faces contact-sheet face-folders all; do
  grep -q -- "$name" "$WORK/stderr" || fail "an unknown name: the message does not list the valid name '$name'"
done
usage_error "an empty name" "$PHOTOS" -o "$WORK/bad" --outputs normal,,albedo
usage_error "--outputs with --aligned" --aligned "$PHOTOS/astronaut.png" -o "$WORK/bad" --outputs normal
usage_error "--view without the files it reads" "$PHOTOS" -o "$WORK/bad" --outputs normal --view
[ ! -e "$WORK/bad" ] || fail "a usage error wrote into its output folder"
"$FACETOOL" infer --help | grep -q -- "--outputs LIST" || fail "infer --help does not show --outputs"

if [ "$failures" -gt 0 ]; then
  echo "$failures failure(s)"
  exit 1
fi
echo "all --outputs checks passed"
