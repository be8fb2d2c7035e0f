#!/usr/bin/env bash
# Installs the Debian 12 packages that pilempm needs to build, test and plot, and GNU parallel
# (its test runs a study's command list with it).
# Safe to run again; does nothing when everything is present. Needs root (or sudo).
set -euo pipefail

packages=(
  build-essential cmake
  libeigen3-dev libtomlplusplus-dev libcli11-dev libfmt-dev
  libgtest-dev googletest libbenchmark-dev
  libhdf5-dev
  libceres-dev libnlopt-cxx-dev
  libsuitesparse-dev
  libmumps-seq-dev  # the quasi-static analysis's default sparse LU (docs/quasi-static.md)
  libopenblas0-serial  # BLAS for MUMPS and UMFPACK: 1.3-1.6 times ATLAS's speed (docs/benchmarks.md)
  python3-matplotlib
  parallel  # GNU parallel: the command list of `pilempm study centrifuge --write-commands` (tested)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
