#!/usr/bin/env bash
# Runs a Python test with the first python3 that has numpy ($PYTHON, python3, /usr/bin/python3); exits 77 (CTest's skip) when none has.
set -euo pipefail
for candidate in "${PYTHON:-}" python3 /usr/bin/python3; do
  if [ -n "$candidate" ] && "$candidate" -c "import numpy" >/dev/null 2>&1; then
    exec "$candidate" "$@"
  fi
done
echo "SKIP: no python3 with numpy (Debian: apt-get install python3-numpy; or set PYTHON)"
exit 77
