#!/usr/bin/env bash
# Builds (Release, into build-bench, if needed) and runs the optical-depth
# benchmark: speed and accuracy of the reference, raymarching, Chapman,
# Taylor and flat methods on the default atmosphere (SPEC §7.6).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$root/build-bench"
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$build" -j2 --target bench_optical_depth >/dev/null
exec "$build/bench_optical_depth" "$@"
