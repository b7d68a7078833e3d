#!/usr/bin/env bash
# Runs the whole test suite (builds first if needed); the opencl tests run on PoCL.
set -euo pipefail
cd "$(dirname "$0")/.."
[ -f build/build.ninja ] || bash scripts/build.sh
cmake --build build -j "$(nproc)"
ctest --test-dir build --output-on-failure -j "$(nproc)" --timeout 1200
