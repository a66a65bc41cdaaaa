#!/bin/bash
# The camera pitch of each place of the standard views against seed 000
# App. B's Empty and Naive columns, which depend on the seed's reference
# images alone (bench/bench_views_calibration.c; models/views_standard.h
# uses the pitches it finds best).
#   bench/views_calibration.sh [OUT]
# OUT: a `skyfit build` of the built-in scene (made there if missing, about
# a minute; default /tmp/skyfit-views-scale, shared with views_scale.sh).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$here/build-bench}
out=${1:-/tmp/skyfit-views-scale}
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target skyfit bench_views_calibration >/dev/null
[ -s "$out/weights/mlp-scattering.json" ] || "$build/skyfit" build --out "$out" --quiet
"$build/bench_views_calibration" "$out"
