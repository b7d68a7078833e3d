#!/usr/bin/env bash
# `facetool view` without a browser: pages for an infer folder and for one photo's folder, a name
# with quotes and <script> escaped in the file, and clear refusals (the sanitizer subset runs this
# one; view_browser drives the pages themselves).
# usage: view_cli_test.sh FACETOOL EXAMPLE_PHOTOS WORK
set -u
# Under the address sanitizer (scripts/sanitize.sh) without the leak check: LeakSanitizer's tracer
# crashed ("Tracer caught signal 11") in every `facetool view` run under ctest here, never in the
# same runs from a shell; memory errors are still caught.
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
facetool=$1 photos=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
fail() { echo "FAIL: $*"; exit 1; }
"$facetool" infer "$photos/grace_hopper_512x512.jpg" -o "$work/out" > "$work/infer.log" 2>&1 ||
  { cat "$work/infer.log"; fail "infer"; }
"$facetool" view "$work/out" > "$work/view.log" 2>&1 || { cat "$work/view.log"; fail "view OUT"; }
[ -s "$work/out/index.html" ] || fail "view OUT wrote no index.html"
page=$work/out/grace_hopper_512x512/view.html
[ -s "$page" ] || fail "view OUT wrote no view.html"
grep -q 'id="facetool-data"' "$page" || fail "the page holds no data block"
! grep -q 'src="http\|href="http' "$page" || fail "the page names an outside URL"
odd="$work/odd/a \"b\" 'c' <script>alert(1)"
mkdir -p "$work/odd" && cp -r "$work/out/grace_hopper_512x512" "$odd"
"$facetool" view "$odd" > "$work/odd.log" 2>&1 || { cat "$work/odd.log"; fail "view of a folder named with quotes and <script>"; }
! grep -q '<script>alert(1)' "$odd/view.html" || fail "the odd name reached the page unescaped"
grep -q '&lt;script&gt;alert(1)' "$odd/view.html" || fail "the odd name is not in the page, escaped"
mkdir -p "$work/plain"
message=$("$facetool" view "$work/plain" 2>&1); rc=$?
[ "$rc" -eq 1 ] || fail "view of a folder that is not an infer output exited $rc: $message"
[[ "$message" == *plain* ]] || fail "the refusal does not name the folder: $message"
rm "$work/out/grace_hopper_512x512/normal.png"
message=$("$facetool" view "$work/out/grace_hopper_512x512" 2>&1); rc=$?
[ "$rc" -eq 1 ] || fail "view with a missing layer exited $rc: $message"
[[ "$message" == *normal.png* ]] || fail "the refusal does not name the missing layer: $message"
echo "ok: pages written, the odd name escaped, a plain folder and a missing layer refused"
