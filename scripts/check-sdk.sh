#!/usr/bin/env bash
# The SDK stage of CI: installs build/ into a temporary prefix; checks its layout and that every
# public header compiles alone against it (CMake package and pkg-config); builds examples/plugins
# and the C++ API example examples/api from copies outside the repository against that prefix
# alone (no include or link path into the source or build tree), runs the plugins' tests with the
# installed facetool and the API example on a photo; then cpack -G DEB,
# unpacks facetool and facetool-dev into a clean root (dpkg -x) and runs its `facetool plugins`
# without LD_LIBRARY_PATH, and (as root) again in a chroot holding only the runtime package and
# the libraries it needs.   usage: scripts/check-sdk.sh   (FACETOOL_JOBS: parallel jobs, 2)
set -euo pipefail
cd "$(dirname "$0")/.."
src=$PWD
build=$src/build
jobs=${FACETOOL_JOBS:-2}
start=$(date +%s)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "check-sdk: FAIL: $*" >&2; exit 1; }
[ -f "$build/build.ninja" ] || bash scripts/build.sh
cmake --build "$build" -j "$jobs" > "$work/build.log" || { cat "$work/build.log"; fail "building"; }
step() { echo "check-sdk: $* ($(($(date +%s) - start)) s)"; }

# 1. Install and layout.
prefix=$work/prefix
cmake --install "$build" --prefix "$prefix" > "$work/install.log"
for f in bin/facetool lib/libfacetool_core.so lib/facetool/plugins/sh_renderer.ftplugin.so \
         lib/facetool/plugins/paper_network.ftplugin.so lib/facetool/plugins/paper_losses.ftplugin.so \
         lib/cmake/facetool/facetoolConfig.cmake lib/cmake/facetool/facetoolTargets.cmake \
         lib/pkgconfig/facetool.pc include/facetool/core/plugin/plugin_api.h \
         lib/libfacetool.so include/facetool/libs/photo/photo_pipeline.h \
         share/facetool/dlib/frontal_face_detector.dat \
         share/facetool/dlib/shape_predictor_68_face_landmarks.copy; do
  [ -e "$prefix/$f" ] || fail "the install lacks $f"
done
if grep -q FACETOOL_BUILD_OPENCL:BOOL=ON "$build/CMakeCache.txt"; then
  [ -e "$prefix/lib/facetool/facetool_backend_opencl.so" ] || fail "the opencl module is not installed"
fi
[ -z "$(find "$prefix/include" -path '*backends*')" ] || fail "backend internals among the headers"
[ -z "$(find "$prefix/lib" -name 'libfacetool_*.a')" ] || fail "static libraries installed"
if grep -rl -e "$src" "$prefix/lib/cmake" "$prefix/lib/pkgconfig"; then
  fail "the CMake package or pkg-config file names the source or build tree"
fi
step "installed into a temporary prefix"

# The installed program finds its shipped model (share/facetool/models) without --model.
if [ -e models/facetool-v2.safetensors ]; then
  [ -e "$prefix/share/facetool/models/facetool-v2.safetensors" ] || fail "the shipped model is not installed"
  "$prefix/bin/facetool" infer examples/photos/astronaut.png -o "$work/installed-infer" 2> "$work/infer.log" ||
    { cat "$work/infer.log"; fail "the installed facetool could not decompose an example photo with its model"; }
  [ -s "$work/installed-infer/astronaut/contact_sheet.png" ] || fail "installed infer wrote no contact sheet"
  step "the installed facetool decomposes a photo with the shipped model"
fi

# 2. Every public header alone, with the flags of pkg-config; a program linked by them.
cflags=$(PKG_CONFIG_PATH=$prefix/lib/pkgconfig pkg-config --cflags facetool)
libs=$(PKG_CONFIG_PATH=$prefix/lib/pkgconfig pkg-config --libs facetool)
count=0
while IFS= read -r header; do
  echo "#include \"${header#"$prefix/include/facetool/"}\"" |
    c++ $cflags -fsyntax-only -x c++ - || fail "$header does not compile alone"
  count=$((count + 1))
done < <(find "$prefix/include/facetool" -name '*.h' | sort)
printf '#include "core/backend/registry.h"\n#include "core/tensor/tensor.h"\nint main() {\n  %s\n  %s\n}\n' \
  'facetool::Tensor t = facetool::Tensor::zeros(facetool::get_backend("cpu"), facetool::Shape{2, 3});' \
  'return t.to_host().size() == 6 ? 0 : 1;' > "$work/pc_program.cpp"
c++ $cflags "$work/pc_program.cpp" -o "$work/pc_program" $libs -Wl,-rpath,"$prefix/lib"
"$work/pc_program" || fail "a program built with pkg-config's flags failed"
step "$count public headers compile alone; pkg-config works"

# 3. The example plugins, from a copy outside the repository, against the prefix alone.
cp -r examples/plugins "$work/examples"
ex=$work/examples-build
cmake -S "$work/examples" -B "$ex" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" > "$work/ex-configure.log" ||
  { cat "$work/ex-configure.log"; fail "configuring the examples"; }
cmake --build "$ex" -j "$jobs" > "$work/ex-build.log" || { cat "$work/ex-build.log"; fail "building the examples"; }
if grep -n -e "$src" "$ex/build.ninja" "$ex/CMakeCache.txt" | head -5 | grep .; then
  fail "the examples' build refers to the source or build tree"
fi
step "examples built against the prefix only"
ctest --test-dir "$ex" --output-on-failure -j "$jobs" || fail "the examples' tests"
step "examples' tests passed"

# 3a. The C++ API example (facetool::facetool), from a copy outside the repository, against the
# prefix alone; run on an example photo with the installed shipped model and plugins.
cp -r examples/api "$work/api"
api=$work/api-build
cmake -S "$work/api" -B "$api" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" > "$work/api-configure.log" ||
  { cat "$work/api-configure.log"; fail "configuring the API example"; }
cmake --build "$api" > "$work/api-build.log" || { cat "$work/api-build.log"; fail "building the API example"; }
if grep -n -e "$src" "$api/build.ninja" "$api/CMakeCache.txt" | head -5 | grep .; then
  fail "the API example's build refers to the source or build tree"
fi
if [ -e models/facetool-v2.safetensors ] && [ -e /usr/share/dlib/shape_predictor_68_face_landmarks.dat ]; then
  env -u FACETOOL_PLUGIN_PATH -u FACETOOL_MODEL_DIR "$api/decompose_photo" examples/photos/astronaut.png \
    "$work/api-out" > "$work/api-run.log" 2>&1 || { cat "$work/api-run.log"; fail "the API example failed"; }
  grep -q "^face 0: score" "$work/api-run.log" || { cat "$work/api-run.log"; fail "the API example found no face"; }
  [ -s "$work/api-out/relit.png" ] || fail "the API example wrote no relit photo"
  # Its decomposition is infer's, file for file (the model's framing and the CLI's defaults).
  for file in albedo.png normal.png visibility.png shading.png reconstruction.png photo.exr \
              face_0/normal.exr face_0/visibility.exr face_0/light.json; do
    cmp -s "$work/api-out/$file" "$work/installed-infer/astronaut/$file" ||
      fail "the API example's $file differs from the installed infer's"
  done
  step "the C++ API example built against the prefix decomposes a photo as infer does (9 files equal) and relights it"
else
  step "the C++ API example built against the prefix (not run: no shipped model or landmark model)"
fi

# 3b. The tutorial of docs/plugins.md, as written there: its three blocks, under 40 lines.
tut=$work/tutorial
mkdir -p "$tut/albedo_mse"
awk '/^## Tutorial/ {on = 1} /^## ABI policy/ {on = 0} on' docs/plugins.md > "$tut/page.md"
block() { awk -v lang="$1" '$0 == "```" lang {f = 1; next} /^```/ {f = 0} f' "$tut/page.md"; }
block cmake > "$tut/albedo_mse/CMakeLists.txt"
block cpp > "$tut/albedo_mse/albedo_mse.cpp"
block sh | sed -E "s#(^|[ =])PREFIX#\\1$prefix#g" > "$tut/steps.sh"
lines=$(cat "$tut/albedo_mse/CMakeLists.txt" "$tut/albedo_mse/albedo_mse.cpp" "$tut/steps.sh" | wc -l)
[ "$lines" -lt 40 ] || fail "the tutorial has $lines lines (promised: under 40)"
printf 'v -8 -10 0\nv 8 -10 0\nv 8 10 0\nv -8 10 0\nv 0 0 6\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n' > "$tut/face.obj"
printf '2 2 2\n0.5 0.5 0.5\n0.8 0.8 0.8\n0.2 0.2 0.2\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n' > "$tut/light.txt"
"$prefix/bin/facetool" synth --mesh "$tut/face.obj" --lights "$tut/light.txt" --count 6 --size 16 \
  --directions 16 --threads 1 -o "$tut/data" > /dev/null 2>&1 || fail "synth for the tutorial"
cat > "$tut/my.json" <<'JSON'
{"name": "tutorial", "network": {"width": 4, "input_size": 16}, "steps": 2, "checkpoint_every": 2,
 "validation": {"every": 2, "holdout_every": 3, "batches": 1},
 "sources": [{"name": "synthetic", "directory": "data", "batch": 2,
              "terms": {"albedo_mse": 1.0, "recon_all": 1.0}}]}
JSON
(cd "$tut" && bash -e steps.sh > steps.log 2>&1) || { cat "$tut/steps.log"; fail "the tutorial's steps"; }
grep -q "^  albedo_mse " "$tut/steps.log" || { cat "$tut/steps.log"; fail "tutorial: plugins does not list albedo_mse"; }
grep -q '"synthetic/albedo_mse":' "$tut/runs/mine/log.jsonl" || fail "tutorial: the run did not use albedo_mse"
step "the tutorial ($lines lines) builds and trains"

# 4. Debian packages, unpacked into a clean root and run from there.
(cd "$work" && cpack -G DEB --config "$build/CPackConfig.cmake" -B "$work/deb" > "$work/cpack.log" 2>&1) ||
  { cat "$work/cpack.log"; fail "cpack -G DEB"; }
runtime=$(ls "$work"/deb/facetool_*.deb) && dev=$(ls "$work"/deb/facetool-dev_*.deb) ||
  fail "cpack made no facetool and facetool-dev packages"
depends=$(dpkg-deb -f "$runtime" Depends)
[ -n "$depends" ] || fail "the facetool package declares no dependencies"
for dep in $(tr ',' '\n' <<<"$depends" | sed 's/(.*//; s/|.*//' | tr -d ' '); do
  dpkg-query -W "$dep" > /dev/null 2>&1 || fail "dependency $dep of the facetool package is not a known package"
done
dpkg-deb -f "$dev" Depends | grep -q '^facetool\b\|, facetool (' ||
  dpkg-deb -f "$dev" Depends | grep -q 'facetool' || fail "facetool-dev does not depend on facetool"
root=$work/root
dpkg -x "$runtime" "$root"
dpkg -x "$dev" "$root"
listing=$(env -u LD_LIBRARY_PATH -u FACETOOL_PLUGIN_PATH -u FACETOOL_BACKEND_PATH \
          "$root/usr/bin/facetool" plugins) || fail "the packaged facetool does not run"
for name in sh_renderer paper_network paper_losses; do
  grep -q "^  $name .*" <<<"$listing" || { echo "$listing"; fail "packaged facetool misses $name"; }
done
grep -q "file: $root/usr/\(bin/\.\./\)\?lib/facetool/plugins/sh_renderer.ftplugin.so" <<<"$listing" ||
  { echo "$listing"; fail "the packaged facetool loads plugins from outside its root"; }
[ -e "$root/usr/lib/cmake/facetool/facetoolConfig.cmake" ] || fail "facetool-dev lacks the CMake package"
env -u LD_LIBRARY_PATH "$root/usr/bin/facetool" backends > "$work/backends.txt" ||
  fail "the packaged facetool backends"
step "packages $(basename "$runtime") and $(basename "$dev") unpacked and run"

# 4b. As root: a chroot holding only the runtime package and the shared libraries it needs
# (copied from this machine, as its Depends would install them), with /proc for the executable's
# own path: facetool plugins inside it finds the shipped plugins, with no path to the host.
if [ "$(id -u)" = 0 ] && command -v chroot > /dev/null && mountpoint -q /proc; then
  jail=$work/jail
  dpkg -x "$runtime" "$jail"
  for elf in "$jail/usr/bin/facetool" "$jail"/usr/lib/facetool/plugins/*.so; do
    ldd "$elf" | grep -o '/[^ ]*' | grep -v "^$jail" | while read -r lib; do
      cp --parents -L -n "$lib" "$jail/"
    done
  done
  mkdir -p "$jail/proc" "$jail/tmp"
  mount -t proc proc "$jail/proc"
  trap 'umount "$jail/proc" 2> /dev/null || true; rm -rf "$work"' EXIT
  jailed=$(env -i PATH=/usr/bin "$(command -v chroot)" "$jail" /usr/bin/facetool plugins) ||
    fail "facetool plugins does not run in a chroot holding only the package and its libraries"
  umount "$jail/proc"
  for name in sh_renderer paper_network paper_losses; do
    grep -q "^  $name " <<<"$jailed" || { echo "$jailed"; fail "chroot: facetool plugins misses $name"; }
  done
  step "facetool plugins in a chroot of the package and its $(find "$jail" -name '*.so*' -path '*x86_64*' | wc -l) libraries"
else
  echo "check-sdk: not root (or no chroot, or no /proc): the chroot check is left out"
fi
echo "check-sdk: ok in $(($(date +%s) - start)) s"
