#!/usr/bin/env bash
# Builds pilempm with AddressSanitizer and UndefinedBehaviorSanitizer (-O1, the "sanitize" preset,
# into build-sanitize/) and runs the test suite under them. Any finding fails the test it occurs
# in (-fno-sanitize-recover=all, halt_on_error).
#
#   bash scripts/test-sanitizers.sh          # CI: the default suite without the whole-run tests
#   bash scripts/test-sanitizers.sh --full   # everything not labelled long (about 45 min on 2 cores)
#
# Under the sanitizers a whole centrifuge run takes about 90 s instead of 3 s, so CI leaves out the
# tests that run whole centrifuge cases, studies and the larger MPM cases (the regex below); the
# parsers, the model, the solver's stages, the checkpoints and the fuzz test all run.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset sanitize >/dev/null
cmake --build --preset sanitize -j "$(nproc)"
heavy='CentrifugeRun|CentrifugeCli|CentrifugeStudy|CalibrationStudy|StudyCli|MpmCli|Restart|ColumnCollapse|StripFooting|LameCylinder|BarVibration|ColumnSelfWeight|AbsorbingBoundary|Threads'
if [ "${1:-}" = "--full" ]; then
  ctest --preset sanitize -j "$(nproc)"
else
  ctest --preset sanitize -j "$(nproc)" -E "$heavy"
fi
