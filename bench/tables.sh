#!/bin/bash
# Builds and runs the reference-table benchmark (bench/bench_tables.c):
#   bench/tables.sh [--threads N] [--quick]
# BUILD names the build folder (default: build-bench next to this folder).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$here/build-bench}
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target bench_tables >/dev/null
echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
"$build/bench_tables" "$@"
