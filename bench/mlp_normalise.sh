#!/bin/bash
# The scattering network with and without the brightness normalisation
# (fit/output_norm.h, `skyfit fit mlp-scattering --normalise brightness`),
# per standard view of seed 000 App. B, for a few seeds (training noise is
# of the size of the effect in some views, so one seed decides nothing):
#   bench/mlp_normalise.sh [OUT] [--seeds "1 2"] [--epochs 60]
# OUT: a `skyfit build` of the built-in scene (made there if missing, about a
# minute; default /tmp/skyfit-views-scale); its table cache is the data.
# Prints, per network, bench_views_scale's table (our RMSE beside App. B's
# Neural Net), then per view the RMSE of each run and the geometric mean
# over the 12 views of ours / the seed's.
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
for seed in $seeds; do
  for norm in none brightness; do
    w=$work/$norm-$seed.json
    "$build/skyfit" fit mlp-scattering --tables "$out/cache" --epochs "$epochs" --seed "$seed" --normalise "$norm" \
      --quiet --out "$w"
    echo "== --normalise $norm --seed $seed --epochs $epochs"
    "$build/bench_views_scale" "$out" "$w" | tee "$work/$norm-$seed.txt" | tail -n +2
  done
done
/usr/bin/python3 - "$work" $seeds <<'PY'
import math, os, sys
work, seeds = sys.argv[1], sys.argv[2:]
runs = [(n, s) for n in ("none", "brightness") for s in seeds]
rows, ratio = {}, {}
for n, s in runs:
    for line in open(os.path.join(work, f"{n}-{s}.txt")):
        f = [x.strip() for x in line.split("|")]
        if len(f) == 5 and f[0] and not f[0].startswith("view"):
            view = f[0]
            rows.setdefault(view, {})[(n, s)] = float(f[2].split()[0])
            ratio.setdefault((n, s), []).append(float(f[4].split()[1]))
print("%-22s" % "view" + "".join("%16s" % f"{n} s{s}" for n, s in runs))
for view, r in rows.items():
    print("%-22s" % view + "".join("%16.3g" % r[k] for k in runs))
print("%-22s" % "geo-mean ours/seed" +
      "".join("%16.2f" % math.exp(sum(map(math.log, ratio[k])) / len(ratio[k])) for k in runs))
PY
