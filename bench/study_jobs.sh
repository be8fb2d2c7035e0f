#!/usr/bin/env bash
# A study's runs one after the other against two at once (`pilempm study centrifuge --jobs 2`):
# the `igs` group with four short cases, the quick case (examples/centrifuge/quick.toml: R = 6 D,
# D/4, 1 387 particles here) with IGS 1..4, jacked 1 D, no relaxation and no load test. Prints the
# wall and CPU times of both and whether their CSV files are the same. Run it on an otherwise
# quiet machine:
#
#   bash bench/study_jobs.sh [OUT]          # default OUT: runs/study_jobs
#
# About 3 to 4 minutes on 2 cores (each case 37 to 84 s on one thread under load).
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-runs/study_jobs}"
bin=./build/pilempm
rm -rf "$out"
mkdir -p "$out/cases"
for n in 1 2 3 4; do
  sed -e "s/IGS3/IGS$n/" -e "s/^depth_D = 2.0/depth_D = 1.0/" examples/centrifuge/quick.toml \
    > "$out/cases/igs${n}_small.toml"
  printf '\n[relaxation]\nenabled = false\n\n[load_test]\ndisplacement_D = 0.0\n' \
    >> "$out/cases/igs${n}_small.toml"
done
study=(study centrifuge --groups igs --cases "$out/cases" --no-plots --quiet)
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
/usr/bin/time -f "serial (--jobs 1): wall %e s, CPU %U s" "$bin" "${study[@]}" --out "$out/serial"
echo "load between: $(cut -d' ' -f1-3 /proc/loadavg)"
/usr/bin/time -f "--jobs 2: wall %e s, CPU %U s" "$bin" "${study[@]}" --out "$out/jobs2" --jobs 2
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
same=yes
for f in "$out"/serial/igs*/pile.csv "$out"/serial/igs*/fields_*.csv "$out"/serial/igs*/mpm/*.csv; do
  cmp -s "$f" "$out/jobs2/${f#"$out"/serial/}" || { same=no; echo "differs: ${f#"$out"/serial/}"; }
done
echo "CSV files of --jobs 2 the same as the serial ones: $same (the same only when the serial"
echo "runs took one thread each, as on a busy machine; on two threads they differ in the last digits)"
