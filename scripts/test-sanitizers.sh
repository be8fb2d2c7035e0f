#!/usr/bin/env bash
# Builds pilempm with AddressSanitizer and UndefinedBehaviorSanitizer (the "sanitize" preset:
# -O1, line tables, warnings as errors, no benchmarks; into build-sanitize/) and runs the test
# suite under them. Any finding fails the test it occurs in (-fno-sanitize-recover=all,
# halt_on_error; leaks too).
#
#   bash scripts/test-sanitizers.sh          # CI (.ci/run): the default suite without the tests
#                                            # that run whole centrifuge cases, studies, fits and
#                                            # the larger MPM cases (HEAVY below)
#   bash scripts/test-sanitizers.sh --full   # everything not labelled long (about 45 min on 2 cores)
#
# Under the sanitizers a whole centrifuge run takes about 90 s instead of 3 s: CI leaves those
# tests to --full. The parsers, the models, the solver's stages and small MPM runs, the
# checkpoints (flipped bits included), the output folders, the command line and the fuzz test
# run in CI. The build and test times are printed at the end (docs/reliability.md).
set -euo pipefail
cd "$(dirname "$0")/.."
full=0
case "${1:-}" in
  --full) full=1 ;;
  "") ;;
  *) echo "usage: bash scripts/test-sanitizers.sh [--full]" >&2; exit 2 ;;
esac
jobs="${PILEMPM_JOBS:-$(nproc)}"
bash scripts/install-deps.sh
start=$(date +%s)
cmake --preset sanitize >/dev/null
if [ $full -eq 1 ]; then
  cmake --build --preset sanitize -j "$jobs"
else
  # CI: the test programs of the layers whose tests run here (study and calibration hold whole
  # runs and fits, left to --full), and the program the command-line tests run.
  cmake --build --preset sanitize -j "$jobs" --target pilempm test_core test_constitutive \
    test_element test_analytic test_mpm test_simulation test_scenario test_io test_cli
fi
built=$(date +%s)
# Whole centrifuge runs and studies, the calibration fits and study, and the MPM verification
# cases with thousands of steps (each 10 s to minutes under the sanitizers).
HEAVY='CentrifugeRun|CentrifugeCli|CentrifugeStudy|CentrifugeTimeStep|CalibrationStudy|QuickStudy|StudyCli|StudyContinuedCli|CalibrateCli|CalibrationRecovery|CalibrationStability|MpmCli|Restart|ColumnCollapse|StripFooting|LameCylinder|BarVibration|ColumnSelfWeight|AbsorbingBoundary|Threads|QuasiStaticPrandtl'
status=0
if [ $full -eq 1 ]; then
  ctest --preset sanitize -j "$jobs" || status=$?
else
  ctest --preset sanitize -j "$jobs" -E "$HEAVY|_NOT_BUILT" || status=$?
fi
end=$(date +%s)
echo "sanitizers: build $((built - start)) s, tests $((end - built)) s ($([ $full -eq 1 ] && echo full || echo CI) run, $jobs jobs)"
exit $status
