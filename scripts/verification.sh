#!/usr/bin/env bash
# Runs the MPM verification cases of examples/mpm/ (docs/verification.md) with the built
# `pilempm` into results/verification/<case>/, then tools/plot/plot_verification.py, which checks
# each against its analytical or experimental reference, prints one PASS/FAIL line per check,
# writes results/verification/summary.md and draws docs/figures/verification/*.png.
# Exits non-zero when a run or a check fails.
#
#   bash scripts/verification.sh                 # all the cases (about 2.5 minutes on one core)
#   bash scripts/verification.sh --long          # and the finer collapse a = 4 (+ ~40 s)
#   bash scripts/verification.sh bar_vibration   # only the named cases, then their checks
#   bash scripts/verification.sh --plots-only    # the checks and figures of the results there
#
# Environment: PILEMPM (the binary, default build/pilempm; built with scripts/build.sh when
# missing), PYTHON (default /usr/bin/python3, which has matplotlib on Debian), RESULTS (default
# results/verification), FIGURES (default docs/figures/verification).
set -uo pipefail
cd "$(dirname "$0")/.."

PILEMPM=${PILEMPM:-build/pilempm}
PYTHON=${PYTHON:-/usr/bin/python3}
RESULTS=${RESULTS:-results/verification}
FIGURES=${FIGURES:-docs/figures/verification}
[ -x "$PYTHON" ] || PYTHON=python3

# The cases, in the order of issue 4's list. strip_footing_8 and _16 (the rigid footing pushed
# in) are no checks, only a comparison in the footing's figure (docs/verification.md, 5).
CASES=(
  column_self_weight_plane_strain_16
  column_self_weight_plane_strain_32
  column_self_weight_plane_strain_64
  column_self_weight_axisymmetric_16
  column_self_weight_axisymmetric_32
  column_self_weight_axisymmetric_64
  bar_vibration
  lame_cylinder_32
  lame_cylinder_64
  lame_cylinder_128
  column_collapse_a0p5_8
  column_collapse_a0p5_16
  column_collapse_a2_8
  column_collapse_a2_16
  column_collapse_a4_8
  strip_footing_load_10
  strip_footing_load_16
  strip_footing_8
  strip_footing_16
  inclined_plane_slide
  inclined_plane_stick
  restart_collapse
)
# --long: the collapse at a = 4 on 16 cells over L0 too (its runout is then extrapolated from 8
# and 16 cells, as at a = 0.5 and 2), about 40 s on one core.
LONG_CASES=(column_collapse_a4_16)

run_cases=()
plots_only=0
for arg in "$@"; do
  case "$arg" in
    --plots-only) plots_only=1 ;;
    --long) CASES+=("${LONG_CASES[@]}") ;;
    -h | --help) sed -n '2,15p' "$0"; exit 0 ;;
    -*) echo "verification: unknown option $arg" >&2; exit 2 ;;
    *) run_cases+=("$arg") ;;
  esac
done
[ ${#run_cases[@]} -eq 0 ] && run_cases=("${CASES[@]}")

failed=0
# run NAME ARGS...: runs pilempm ARGS, logs into $RESULTS/NAME.log, prints the time or FAIL.
run() {
  local name=$1
  shift
  local start ms
  start=$(date +%s%N)
  if "$PILEMPM" "$@" >"$RESULTS/$name.log" 2>&1; then
    ms=$((($(date +%s%N) - start) / 1000000))
    printf 'ran   %-40s %4d.%d s\n' "$name" $((ms / 1000)) $((ms % 1000 / 100))
  else
    echo "FAIL  run $name (see $RESULTS/$name.log):"
    tail -n 5 "$RESULTS/$name.log"
    failed=1
    return 1
  fi
}

if [ $plots_only -eq 0 ]; then
  if [ ! -x "$PILEMPM" ]; then
    echo "verification: $PILEMPM not found, building it (scripts/build.sh)"
    bash scripts/build.sh || exit 1
  fi
  mkdir -p "$RESULTS"
  for name in "${run_cases[@]}"; do
    file="examples/mpm/$name.toml"
    if [ ! -f "$file" ]; then
      echo "FAIL  run $name: no $file"
      failed=1
      continue
    fi
    run "$name" mpm run "$file" --out "$RESULTS/$name" --quiet --overwrite || continue
    # A restart case: run it again from the checkpoint of its first phase into <case>_resumed;
    # the checks compare the two.
    if [[ $name == restart_* ]]; then
      checkpoint=$(ls "$RESULTS/$name"/checkpoint_01_*.h5 2>/dev/null | head -n 1)
      if [ -z "$checkpoint" ]; then
        echo "FAIL  run $name: no checkpoint_01_*.h5 in $RESULTS/$name"
        failed=1
        continue
      fi
      run "${name}_resumed" mpm run "$file" --out "$RESULTS/${name}_resumed" \
        --restart "$checkpoint" --quiet --overwrite
    fi
  done
fi

only=$(IFS=,; echo "${run_cases[*]}")
"$PYTHON" tools/plot/plot_verification.py --results "$RESULTS" --cases examples/mpm \
  --figures "$FIGURES" --only "$only" || failed=1
exit $failed
