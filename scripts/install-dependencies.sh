#!/usr/bin/env bash
# Installs every Debian package facetool needs to build, test and run (uses sudo when not root).
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config ccache
  ocl-icd-opencl-dev opencl-headers pocl-opencl-icd clinfo libclblast-dev
  libdnnl-dev libopenblas-dev
  libembree-dev libopenimageio-dev openimageio-tools
  libboost-program-options-dev googletest libgtest-dev nlohmann-json3-dev
  blender-data   # 8 CC0 studio-light EXRs: facetool synth's default lights
  libdlib-dev libdlib-data  # photos: HOG face detector and the 68-point landmark model
  libopenmpi-dev openmpi-bin  # optional: data-parallel training (mpirun -np K facetool train)
  python3-torch  # tests only: the independent PyTorch reference (scripts/pytorch_reference.py)
  libjemalloc2   # benchmarks only: preloaded under PyTorch by scripts/bench-anchors.py (allocator)
  clang libclang-rt-14-dev valgrind  # tests only: fuzzers, sanitizers, memcheck (docs/testing.md)
)

as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-dependencies: all ${#packages[@]} packages already installed"
  exit 0
fi
echo "install-dependencies: installing ${missing[*]}"
as_root apt-get update -qq
as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
