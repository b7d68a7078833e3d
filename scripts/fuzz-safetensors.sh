#!/usr/bin/env bash
# Fuzzes the safetensors parser for SECONDS (default 120): kept as a shortcut for scripts/fuzz.sh.
exec bash "$(dirname "$0")/fuzz.sh" safetensors "${1:-120}"
