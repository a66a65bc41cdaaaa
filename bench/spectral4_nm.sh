#!/bin/bash
# NLopt's Nelder-Mead against SciPy's on the 4-wavelength objective (issue 5):
# same objective, same start (the grid search's best point), same initial
# simplex; evaluations, final loss and wall time in one run.
#   bench/spectral4_nm.sh [--quick]
# BUILD names the build folder (default: build-bench next to this folder);
# the spectral reference tables are cached in $BUILD/spectral4-cache.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$here/build-bench}
# SciPy from Debian (python3-scipy) lives in the system Python, which may not
# be the first python3 on PATH (pyenv and the like).
py=python3
if ! $py -c "import scipy" 2>/dev/null; then
  py=/usr/bin/python3
  if ! $py -c "import scipy" 2>/dev/null; then
    echo "installing python3-scipy" >&2
    if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; else SUDO=; fi
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends python3-scipy >/dev/null
  fi
fi
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target bench_spectral4_nm >/dev/null
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
"$build/bench_spectral4_nm" --out "$out" --cache "$build/spectral4-cache" "$@"
$py "$here/bench/spectral4_nm.py" "$out/objective.json" "$here/data/physical/cie1931_2deg_5nm.csv"
