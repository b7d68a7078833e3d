#!/usr/bin/env bash
# Fails if libfacetool_core needs a library above the compute core (its ELF NEEDED entries) or if a
# source of the core's folders includes a header from a folder above it.
# Usage: check_core_layering.sh LIBFACETOOL_CORE.so SOURCE_DIR
set -euo pipefail
lib=$1
src=$2
status=0
needed=$(readelf -d "$lib" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p')
[ -n "$needed" ] || { echo "FAIL: no NEEDED entries read from $lib"; exit 1; }
# Any facetool library but the core itself (libfacetool.so, libfacetool_<name>).
forbidden='embree|OpenImageIO|OpenEXR|Imath|dlib|ceres|mpi|boost|libfacetool[._]'
if bad=$(grep -E "$forbidden" <<<"$needed" | grep -v '^libfacetool_core\.so'); then
  echo "FAIL: $lib links to libraries above the compute core:"; echo "$bad"; status=1
fi
# The core's folders (core/CMakeLists.txt) and the cpu backend built into it.
core_dirs=(core/tensor core/backend core/ops core/autograd core/plugin core/sh core/util backends/cpu)
allowed='core/(tensor|backend|ops|autograd|plugin|sh|util)/|backends/cpu/'
for dir in "${core_dirs[@]}"; do
  while IFS= read -r hit; do
    echo "FAIL: the compute core includes a header from above it: $hit"; status=1
  done < <(grep -HnE '^#include "(core|backends)/' "$src/$dir"/*.h "$src/$dir"/*.cpp |
           grep -vE "#include \"($allowed)" || true)
  if grep -lE '#include <(OpenImageIO|embree3|dlib|ceres|mpi)' "$src/$dir"/*.h "$src/$dir"/*.cpp; then
    echo "FAIL: the compute core includes a third-party header of a layer above it"; status=1
  fi
done
[ $status -eq 0 ] && echo "core layering: ok ($(wc -l <<<"$needed") NEEDED entries, none above the core)"
exit $status
