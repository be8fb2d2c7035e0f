#!/usr/bin/env bash
# Sets up, builds, and runs pilempm's main job on its built-in default case.
# Until the pile simulation exists, the main job is the element-test set of the study
# (BRIEF.md §3): oedometer, cyclic oedometer, drained triaxial, high-pressure triaxial and the
# alpha series, written to results/element/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
out="${1:-results/element}"
./build/pilempm element run --out "$out"
echo
echo "Results are in $out/ (one CSV curve and one JSON summary per test; summary.csv and summary.md for all)."
