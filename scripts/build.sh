#!/usr/bin/env bash
# Configures and builds pilempm (Release, warnings as errors) into build/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)"
