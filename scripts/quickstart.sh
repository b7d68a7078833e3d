#!/usr/bin/env bash
# One command for a fresh Debian machine: install dependencies, build, run the bundled example job.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-dependencies.sh
bash scripts/build.sh
echo
echo "== facetool backends"
build/bin/facetool backends
echo
echo "== facetool bench ops --quick (cpu)"
build/bin/facetool bench ops --quick --backend cpu
