#!/usr/bin/env bash
# Run times under load: the quick centrifuge case and a larger one (MPM-1, the full model's K0 and
# 0.1 D load test), each at 1 and 2 threads and at the default (threads = 0: the count the program
# chooses), with 0, 1 and 2 busy processes (`yes > /dev/null`) beside it. Writes a Markdown table
# to stdout (and the runs' folders under $OUT). Run it on an otherwise quiet machine:
#
#   bash bench/load_table.sh [OUT]          # default OUT: runs/load_table
#
# Each row is one run; the whole table takes about 20 min on 2 cores (the quick case takes 40 s
# alone on 2 threads, MPM-1 about 20 s).
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-runs/load_table}"
bin=./build/pilempm
mkdir -p "$out"
cases=("quick:examples/centrifuge/quick.toml" "mpm1:examples/centrifuge/mpm1_wished_in_place.toml")

# The case file with [solver] threads = N (the table added, or the key set in it).
with_threads() {
  local file="$1" threads="$2" target="$3"
  /usr/bin/python3 - "$file" "$threads" "$target" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
line = f"threads = {sys.argv[2]}"
if re.search(r"^\[solver\]\s*$", text, re.M):
    text = re.sub(r"^threads\s*=.*$\n?", "", text, flags=re.M)
    text = re.sub(r"^\[solver\]\s*$", "[solver]\n" + line, text, count=1, flags=re.M)
else:
    text += "\n[solver]\n" + line + "\n"
open(sys.argv[3], "w").write(text)
PY
}

echo "| case | busy processes beside it | threads | wall time s |"
echo "|---|---|---|---|"
for entry in "${cases[@]}"; do
  name="${entry%%:*}"
  file="${entry#*:}"
  for busy in 0 1 2; do
    for threads in 1 2 0; do
      run="$out/${name}_busy${busy}_threads${threads}"
      rm -rf "$run"
      mkdir -p "$run"
      with_threads "$file" "$threads" "$run.toml"
      pids=()
      for ((k = 0; k < busy; ++k)); do
        yes > /dev/null &
        pids+=("$!")
      done
      sleep 2  # let the busy processes take their cores
      start=$(date +%s.%N)
      "$bin" centrifuge run "$run.toml" --out "$run" --no-plots --quiet > "$run.log" 2>&1 || true
      end=$(date +%s.%N)
      for pid in "${pids[@]}"; do kill "$pid"; done
      wait 2>/dev/null || true
      printf '| %s | %d | %s | %.1f |\n' "$name" "$busy" \
        "$([ "$threads" = 0 ] && echo default || echo "$threads")" \
        "$(awk "BEGIN { print $end - $start }")"
    done
  done
done
