#!/usr/bin/env bash
# Sets up, builds and runs the default test suite (everything not labelled "long").
# Pass "--long" to run only the long physics checks instead.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
if [ "${1:-}" = "--long" ]; then
  ctest --test-dir build -L long --output-on-failure -j "$(nproc)"
else
  ctest --preset release -j "$(nproc)"
fi
