#!/usr/bin/env bash
# The shipped model: found without --model by infer, relight, pseudo-label and eval, at most 20 MB, and
# trained: its reconstruction PSNR on the example photos must reach 15 dB (facetool-v2: 22.4 dB; the
# former facetool-v1 at its 64 x 64 framing: 18.7 dB; untrained weights of v1's shape: 4.1 dB).
# Usage: shipped_model_test.sh FACETOOL SOURCE_DIR
set -euo pipefail
facetool=$1
source_dir=$2
model="$source_dir/models/facetool-v2.safetensors"
[ -s "$model" ] || { echo "FAIL: $model missing"; exit 1; }
bytes=$(stat -c %s "$model")
[ "$bytes" -le 20000000 ] || { echo "FAIL: $model is $bytes bytes, over 20 MB"; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
photos="$source_dir/examples/photos"

# infer without --model equals infer with the shipped file.
"$facetool" infer "$photos/astronaut.png" -o "$work/default" 2>"$work/err" ||
  { cat "$work/err"; echo "FAIL: infer without --model"; exit 1; }
"$facetool" infer "$photos/astronaut.png" --model "$model" -o "$work/explicit" 2>/dev/null
cmp -s "$work/default/astronaut/photo.exr" "$work/explicit/astronaut/photo.exr" ||
  { echo "FAIL: infer without --model differs from --model $model"; exit 1; }
[ -s "$work/default/astronaut/contact_sheet.png" ] || { echo "FAIL: no contact sheet"; exit 1; }

# The landmark normal head it carries changes the normals (and only with it: --no-landmark-normals).
grep -aq '"landmark_normals":"crop ' "$model" || { echo "FAIL: $model carries no landmark normal head"; exit 1; }
"$facetool" infer "$photos/astronaut.png" --no-landmark-normals -o "$work/network" 2>/dev/null
cmp -s "$work/default/astronaut/photo.exr" "$work/network/astronaut/photo.exr" &&
  { echo "FAIL: --no-landmark-normals gives the same photo.exr as the default"; exit 1; }
"$facetool" relight "$photos/astronaut.png" --light-from "$photos/grace_hopper_512x512.jpg" --no-landmark-normals \
  -o "$work/relit-network" 2>/dev/null
# Without the light solve (which takes its albedo from the shading, and so from the normals), the
# head changes the normals only.
"$facetool" infer "$photos/astronaut.png" --no-light-solve -o "$work/no-solve" 2>/dev/null
"$facetool" infer "$photos/astronaut.png" --no-light-solve --no-landmark-normals -o "$work/no-solve-network" 2>/dev/null
cmp -s "$work/no-solve/astronaut/face_0/albedo.exr" "$work/no-solve-network/astronaut/face_0/albedo.exr" ||
  { echo "FAIL: the landmark normal head changed the albedo (it blends the normals only)"; exit 1; }
# The light solve changes the light and the albedo, not the normals, and says what it found.
for layer in light.json albedo.exr; do
  cmp -s "$work/default/astronaut/face_0/$layer" "$work/no-solve/astronaut/face_0/$layer" &&
    { echo "FAIL: --no-light-solve gives the same $layer as the default"; exit 1; }
done
cmp -s "$work/default/astronaut/face_0/normal.exr" "$work/no-solve/astronaut/face_0/normal.exr" ||
  { echo "FAIL: the light solve changed the normals"; exit 1; }
grep -q '"light_solve": {"direction_photo_frame"' "$work/default/astronaut/faces.json" ||
  { echo "FAIL: faces.json does not give the solved light"; exit 1; }
grep -q '"light_solve"' "$work/no-solve/astronaut/faces.json" &&
  { echo "FAIL: faces.json gives a solved light under --no-light-solve"; exit 1; }
# The light's gain (without the solve), fitted in the head's face mask, changes the light and not
# the albedo or normals.
"$facetool" infer "$photos/astronaut.png" --no-light-solve --no-light-gain -o "$work/no-gain" 2>/dev/null
cmp -s "$work/no-solve/astronaut/face_0/light.json" "$work/no-gain/astronaut/face_0/light.json" &&
  { echo "FAIL: --no-light-gain gives the same light as the default"; exit 1; }
for layer in albedo normal; do
  cmp -s "$work/no-solve/astronaut/face_0/$layer.exr" "$work/no-gain/astronaut/face_0/$layer.exr" ||
    { echo "FAIL: the light's gain changed the $layer (it scales the light only)"; exit 1; }
done

# relight without --model: the light of the other example photo.
"$facetool" relight "$photos/astronaut.png" --light-from "$photos/grace_hopper_512x512.jpg" \
  -o "$work/relit" 2>/dev/null || { echo "FAIL: relight without --model"; exit 1; }
[ -n "$(find "$work/relit" -name '*.png' | head -1)" ] || { echo "FAIL: relight wrote no picture"; exit 1; }
cmp -s "$work/relit/astronaut/relit.png" "$work/relit-network/astronaut/relit.png" &&
  { echo "FAIL: relight ignores the landmark normal head"; exit 1; }

# --model and --init together are refused.
if "$facetool" infer "$photos/astronaut.png" --model "$model" --init random -o "$work/both" 2>"$work/err"; then
  echo "FAIL: --model with --init accepted"; exit 1
fi
grep -q "not both" "$work/err" || { cat "$work/err"; exit 1; }

# Quality: reconstruction PSNR in the face mask of the two example photos (eval on prepare-real
# crops at the model's input size and framing, read from its file).
size=$(grep -ao '"input_size":"[0-9]*"' "$model" | grep -o '[0-9]*')
framing=$(grep -ao '"framing":"[^"]*"' "$model" | sed 's/"framing":"//; s/"$//')
[ -n "$size" ] && [ -n "$framing" ] || { echo "FAIL: no input_size or framing in $model's header"; exit 1; }
"$facetool" prepare-real "$photos" --size "$size" --framing "$framing" -o "$work/real" 2>/dev/null
"$facetool" eval --data "$work/real" -o "$work/eval" >/dev/null 2>&1
# eval reads the samples' landmarks for the head: the reconstruction differs without it.
"$facetool" eval --data "$work/real" --no-landmark-normals -o "$work/eval-network" >/dev/null 2>&1
cmp -s "$work/eval/per_image.csv" "$work/eval-network/per_image.csv" &&
  { echo "FAIL: eval ignores the landmark normal head"; exit 1; }
"$facetool" eval --data "$work/real" --no-light-solve -o "$work/eval-no-solve" >/dev/null 2>&1
cmp -s "$work/eval/per_image.csv" "$work/eval-no-solve/per_image.csv" &&
  { echo "FAIL: eval ignores --no-light-solve"; exit 1; }
"$facetool" eval --data "$work/real" --no-light-solve --no-light-gain -o "$work/eval-no-gain" >/dev/null 2>&1
cmp -s "$work/eval-no-solve/per_image.csv" "$work/eval-no-gain/per_image.csv" &&
  { echo "FAIL: eval ignores --no-light-gain"; exit 1; }
"$facetool" pseudo-label "$work/real"/sample_*.exr -o "$work/pseudo" 2>/dev/null
[ -s "$work/pseudo/sample_00000000.exr" ] || { echo "FAIL: pseudo-label without --model wrote nothing"; exit 1; }
# pseudo-label labels the samples (they carry their landmarks) with the landmark normal head's blend.
"$facetool" pseudo-label "$work/real"/sample_*.exr --no-landmark-normals -o "$work/pseudo-network" 2>/dev/null
cmp -s "$work/pseudo/sample_00000000.exr" "$work/pseudo-network/sample_00000000.exr" &&
  { echo "FAIL: pseudo-label ignores the landmark normal head"; exit 1; }
# Samples of another size: a clear error that says how to make them for this model.
"$facetool" prepare-real "$photos" --size 64 -o "$work/real64" 2>/dev/null
if "$facetool" eval --data "$work/real64" -o "$work/eval64" > /dev/null 2> "$work/err"; then
  echo "FAIL: eval accepted 64 x 64 samples for a ${size} x ${size} model"; exit 1
fi
grep -q "make samples of its size and framing (prepare-real or synth --size $size --framing" "$work/err" ||
  { cat "$work/err"; echo "FAIL: no advice on the samples' size"; exit 1; }
psnr() { grep -o '"psnr_db_mean": *[-0-9.e+]*' "$1" | grep -o '[-0-9.e+]*$'; }
trained=$(psnr "$work/eval/summary.json")
echo "shipped model: mean PSNR on the example photos $trained dB"
awk -v p="$trained" 'BEGIN { exit !(p >= 15) }' ||
  { echo "FAIL: the shipped model reconstructs the example photos at $trained dB (< 15 dB)"; exit 1; }
echo "shipped model: ok"
