#!/usr/bin/env bash
# One command for a fresh Debian machine: install dependencies, build, decompose the bundled example photo.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-dependencies.sh
bash scripts/build.sh
echo
echo "== facetool backends"
build/bin/facetool backends
echo
echo "== facetool infer examples/photos/grace_hopper_512x512.jpg (the shipped model, docs/model-card.md)"
build/bin/facetool infer examples/photos/grace_hopper_512x512.jpg -o build/example
echo
echo "contact sheet: build/example/grace_hopper_512x512/contact_sheet.png"
echo "(albedo, normal, visibility, shading, reconstruction beside it; docs/photos.md)"
