#!/usr/bin/env bash
# Cross-checks facetool's paper_network against an independent PyTorch version of it: random
# weights written by PyTorch, loaded by `facetool infer`, outputs compared (needs python3-torch).
# Usage: check-pytorch-parity.sh [BACKEND]; FACETOOL=path/to/facetool overrides build/bin/facetool.
# Exits 77 (a skip for CTest) when no python3 has torch and numpy, or the backend is unavailable.
set -euo pipefail
cd "$(dirname "$0")/.."
backend="${1:-cpu}"
facetool="${FACETOOL:-build/bin/facetool}"
python=""
for candidate in "${PYTHON:-}" python3 /usr/bin/python3; do
  if [ -n "$candidate" ] && "$candidate" -c "import torch, numpy" 2>/dev/null; then
    python="$candidate"
    break
  fi
done
if [ -z "$python" ]; then
  echo "check-pytorch-parity: no python3 with torch and numpy (Debian: apt-get install python3-torch; or set PYTHON)" >&2
  exit 77
fi
if ! "$facetool" --backend "$backend" backends > /dev/null 2>&1; then
  echo "check-pytorch-parity: backend '$backend' is not available here ($facetool backends says why)" >&2
  exit 77
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$python" scripts/pytorch_reference.py export-random "$work/random.safetensors" --width 32 --seed 7
"$facetool" --backend "$backend" infer --aligned --stretch "$work/random.png" --model "$work/random.safetensors" \
  -o "$work/out" --no-contact-sheet --raw-output "$work/raw.safetensors" --no-mirror-average
"$python" scripts/pytorch_reference.py compare "$work/random.safetensors" "$work/raw.safetensors" --seed 7
# infer's default: each crop beside its mirror image, the answers averaged.
"$facetool" --backend "$backend" infer --aligned --stretch "$work/random.png" --model "$work/random.safetensors" \
  -o "$work/mirrored" --no-contact-sheet --raw-output "$work/mirrored.safetensors"
"$python" scripts/pytorch_reference.py compare "$work/random.safetensors" "$work/mirrored.safetensors" --seed 7 \
  --mirror-average
