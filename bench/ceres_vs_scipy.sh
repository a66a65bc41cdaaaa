#!/bin/bash
# Ceres (through fit/ceres_shim.h) against SciPy's least_squares on the same
# sky fits (SPEC §7.2): same samples, same start, same residuals, analytic
# Jacobians on both sides; time (median of repeats) and final cost side by
# side, in one run.
#   bench/ceres_vs_scipy.sh [repeats] [tolerance]
# tolerance (default 1e-14) is Ceres' function, parameter and gradient
# tolerance and SciPy's ftol, xtol and gtol.
# BUILD names the build folder (default: build-bench next to this folder).
# Needs python3-scipy (Debian); installed here if missing (an optional
# dependency of this benchmark only).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$here/build-bench}
repeats=${1:-7}
tolerance=${2:-1e-14}
py=/usr/bin/python3
if ! "$py" -c "import scipy, numpy" 2>/dev/null; then
  echo "installing python3-scipy (benchmark dependency)..." >&2
  if [ "$(id -u)" = 0 ]; then apt-get install -y python3-scipy >/dev/null; else sudo apt-get install -y python3-scipy >/dev/null; fi
fi
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target bench_ceres_fit >/dev/null
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg); tolerance $tolerance; Ceres 1 thread, numpy/SciPy $("$py" -c 'import scipy;print(scipy.__version__)')"
OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 "$build/bench_ceres_fit" "$dir" "$repeats" "$tolerance"
echo
OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 "$py" "$here/bench/ceres_vs_scipy.py" "$dir" "$repeats"
