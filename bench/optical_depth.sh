#!/usr/bin/env bash
# Builds (Release, into build-bench, if needed) and runs the optical-depth
# benchmark: speed and accuracy of the reference, raymarching, Chapman,
# Taylor and flat methods on the default atmosphere (SPEC §7.6), then the
# speed and accuracy of the reference single scattering.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$root/build-bench"
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$build" -j2 --target bench_optical_depth bench_single_scattering >/dev/null
"$build/bench_optical_depth" "$@"
echo
echo "Reference single scattering (issue target: >= 1000 evaluations/s per core at <= 1e-7):"
"$build/bench_single_scattering"
