#!/usr/bin/env bash
# Sets up, builds, and runs pilempm's main job on its built-in default case: the centrifuge
# pile test's quick case (docs/centrifuge.md): the small model (R = 6 D), a coarse mesh, the
# K0 stress at 40 g, the pile jacked 2 D, relaxed and load-tested over 0.1 D. About a minute on
# 2 cores; results in results/centrifuge/ (head-force plots, pile.csv, fields, summary.md).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
out="${1:-results/centrifuge}"
./build/pilempm centrifuge run --out "$out" --overwrite  # replaces an earlier quick run there
echo
echo "Results are in $out/: summary.md, installation.png and load_test.png (head force against"
echo "displacement), pile.csv (forces against displacement and depth), fields_*.png/.csv/.vtu."
