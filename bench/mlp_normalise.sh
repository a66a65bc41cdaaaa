#!/bin/bash
# The scattering network without and with the brightness normalisation
# (fit/output_norm.h, `skyfit fit mlp-scattering --normalise brightness`),
# uncapped and with the default cap, per standard view of seed 000 App. B,
# for a few seeds (training noise is of the size of the effect in some
# views, so one seed decides nothing):
#   bench/mlp_normalise.sh [OUT] [--seeds "1 2"] [--epochs 60]
# OUT: a `skyfit build` of the built-in scene (made there if missing, about a
# minute; default /tmp/skyfit-views-scale); its table cache is the data.
# Prints, per network, bench_views_scale's table (our RMSE beside App. B's
# Neural Net as an RMSE), then per view the RMSE of each run, the number of
# views below the seed's, and the geometric mean over the 12 views of ours /
# the seed's.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$here/build-bench}
out=/tmp/skyfit-views-scale
seeds="1 2"
epochs=60
while [ $# -gt 0 ]; do
  case "$1" in
    --seeds) seeds=$2; shift 2 ;;
    --epochs) epochs=$2; shift 2 ;;
    -*) echo "unknown option $1" >&2; exit 2 ;;
    *) out=$1; shift ;;
  esac
done
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target skyfit bench_views_scale >/dev/null
[ -s "$out/weights/mlp-scattering.json" ] || "$build/skyfit" build --out "$out" --quiet
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
variants="none uncapped capped"
for seed in $seeds; do
  for v in $variants; do
    case $v in
      none) opts="--normalise none" ;;
      uncapped) opts="--normalise brightness --normalise-cap none" ;;
      capped) opts="--normalise brightness" ;;
    esac
    w=$work/$v-$seed.json
    # shellcheck disable=SC2086
    "$build/skyfit" fit mlp-scattering --tables "$out/cache" --epochs "$epochs" --seed "$seed" $opts --quiet --out "$w"
    echo "== $opts --seed $seed --epochs $epochs"
    "$build/bench_views_scale" "$out" "$w" | tee "$work/$v-$seed.txt" | tail -n +2
  done
done
/usr/bin/python3 - "$work" "$variants" $seeds <<'PY'
import math, os, sys
work, variants, seeds = sys.argv[1], sys.argv[2].split(), sys.argv[3:]
runs = [(n, s) for n in variants for s in seeds]
rows, ratio = {}, {}
for n, s in runs:
    for line in open(os.path.join(work, f"{n}-{s}.txt")):
        f = [x.strip() for x in line.split("|")]
        if len(f) == 7 and f[0] and not f[0].startswith("view"):
            view = f[0]
            rows.setdefault(view, {})[(n, s)] = float(f[4].split()[0])
            ratio.setdefault((n, s), []).append(float(f[6].split()[1]))
print("%-22s" % "view" + "".join("%15s" % f"{n} s{s}" for n, s in runs))
for view, r in rows.items():
    print("%-22s" % view + "".join("%15.3g" % r[k] for k in runs))
print("%-22s" % "below the seed" + "".join("%15d" % sum(x < 1 for x in ratio[k]) for k in runs))
print("%-22s" % "geo-mean ours/seed" +
      "".join("%15.2f" % math.exp(sum(map(math.log, ratio[k])) / len(ratio[k])) for k in runs))
PY
