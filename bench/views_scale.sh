#!/bin/bash
# Scale of the per-view sky-radiance RMSE against seed 000 App. B
# (bench/bench_views_scale.c): our reference's RMS per standard view, a
# white image's and single scattering's mean squared errors beside App. B's
# "Empty" and "Naive" columns (its figures are mean squares), and the
# scattering network's error split into sky and ground pixels, over the
# seed's Neural Net as an RMSE.
#   bench/views_scale.sh [OUT [W.json]]
# OUT: a `skyfit build` of the built-in scene (made there if missing, about
# a minute; default /tmp/skyfit-views-scale). W.json: another scattering
# network to measure in place of the build's (e.g. a longer `skyfit fit
# mlp-scattering` run).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$here/build-bench}
out=${1:-/tmp/skyfit-views-scale}
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target skyfit bench_views_scale >/dev/null
[ -s "$out/weights/mlp-scattering.json" ] || "$build/skyfit" build --out "$out" --quiet
"$build/bench_views_scale" "$out" "${@:2}"
