#!/usr/bin/env bash
# Determinism (issue 9): the same inputs and seed give byte-identical
# tables (skyfit sample), weights (skyfit fit sigmoid, hosek,
# mlp-transmittance, mlp-scattering), headers (skyfit codegen) and build
# outputs (skyfit build: tables, weights with the restarts of its networks,
# sky.h, sky.glsl, metrics.json, report.md) across two runs and across
# thread counts: --threads 1 with OMP_NUM_THREADS=1 (twice), --threads 2
# with OMP_NUM_THREADS=2, and no --threads with OMP_NUM_THREADS=3
# (OpenMP's default; sigmoid has no --threads and always follows
# OMP_NUM_THREADS). Reduced resolutions and
# epochs; the scattering network trains on whole batches of > 5,500
# samples so that its gradient sums really are split over threads
# (fit/train.h: SF_TRAIN_PARALLEL_WORK). Build timings are measured once and
# copied into the other builds' cost caches, since timings are the one
# thing that is not reproducible (they are cached by design, SPEC §12);
# each build runs with the same relative --out, as the report quotes it.
set -u
BIN=${SKYFIT_BIN:?SKYFIT_BIN must name the skyfit binary}
BIN=$(cd "$(dirname "$BIN")" && pwd)/$(basename "$BIN")   # the builds run elsewhere
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
pass() { echo "ok   $*"; }
fail() { echo "FAIL $*"; failures=$((failures + 1)); }

res=32x16,16x16x8x4
build_res=32x16,8x16x8x4
cat >"$tmp/scene.json" <<'EOF'
{"name": "determinism", "viewer_altitude_km": [0, 20], "view": "all", "sun_elevation_deg": [-10, 90],
 "quantities": ["transmittance", "sky_radiance"],
 "error_budget": {"transmittance_rmse": 1e-3, "sky_radiance_rel_rmse": 0.05}}
EOF

# run_all NAME OMP_THREADS [--threads N]: every stage into $tmp/NAME.
run_all() {
  local name=$1 omp=$2
  shift 2
  local d=$tmp/$name threads=("$@")
  mkdir -p "$d/weights" "$d/headers"
  local log=$d/log
  (
    export OMP_NUM_THREADS=$omp
    set -e
    "$BIN" sample --out "$d/tables" --resolution $res --orders 2 "${threads[@]}" --quiet
    "$BIN" fit sigmoid --out "$d/weights/sigmoid.json" --grid 12x24 --quiet
    "$BIN" fit hosek --out "$d/weights/hosek.json" --tables "$d/tables" --resolution $res --orders 2 \
      --elevations 6 --grid 8x8 "${threads[@]}" --quiet
    "$BIN" fit mlp-transmittance --out "$d/weights/mlp-transmittance.json" --tables "$d/tables" --resolution $res \
      --epochs 20 --polish 3 "${threads[@]}" --quiet
    "$BIN" fit mlp-scattering --out "$d/weights/mlp-scattering.json" --tables "$d/tables" --resolution $res \
      --orders 2 --epochs 4 --batch 0 --validation 0.05 --polish 2 "${threads[@]}" --quiet
    "$BIN" codegen --weights "$d/weights/sigmoid.json" --weights "$d/weights/hosek.json" \
      --weights "$d/weights/mlp-transmittance.json" --weights "$d/weights/mlp-scattering.json" \
      --baselines naive,chapman,taylor,flat --lang both --out "$d/headers" --name sky --quiet
    if [ -d "$tmp/costs" ]; then mkdir -p "$d/build/cache/costs"; cp "$tmp/costs/"* "$d/build/cache/costs/"; fi
    # relative --out: the report names its files by the path given
    cd "$d"
    "$BIN" build "$tmp/scene.json" --out build --resolution $build_res --no-views --samples 1000 \
      --timing-points 5000 --repetitions 1 --mlp-epochs 20,2 --mlp-samples 2000 --quick --mlp-restarts 2 --seed 3 \
      "${threads[@]}" --quiet >/dev/null
  ) >"$log" 2>&1
}

# compare NAME: every output of NAME equals run a's, byte for byte.
compare() {
  local name=$1 label=$2 n=0 bad=0 f rel
  while IFS= read -r -d '' f; do
    rel=${f#"$tmp/a/"}
    [ "$rel" = log ] && continue
    n=$((n + 1))
    if ! cmp -s "$f" "$tmp/$name/$rel"; then
      bad=$((bad + 1))
      echo "     differs: $rel"
    fi
  done < <(find "$tmp/a" -type f -print0)
  local extra
  extra=$(cd "$tmp/$name" && find . -type f ! -name log | wc -l)
  if [ $bad -eq 0 ] && [ "$extra" -eq $n ]; then
    pass "$label: $n files byte-identical to run a (cmp)"
  else
    fail "$label: $bad of $n files differ from run a ($extra files in this run)"
  fi
}

t0=$(date +%s.%N)
run_all a 1 --threads 1 || { cat "$tmp/a/log"; fail "run a (--threads 1) failed"; exit 1; }
mkdir -p "$tmp/costs"
cp "$tmp/a/build/cache/costs/"* "$tmp/costs/"
echo "compared per run (run a, --threads 1, OMP_NUM_THREADS=1):"
(cd "$tmp/a" && find . -type f ! -name log | sort | sed 's/^/     /')
run_all b 1 --threads 1 || { cat "$tmp/b/log"; fail "run b failed"; }
run_all c 2 --threads 2 || { cat "$tmp/c/log"; fail "run c failed"; }
run_all d 3 || { cat "$tmp/d/log"; fail "run d failed"; }
# The tiny tables miss the budgets: the build's restarts (mlp-*-2) are
# among the files compared.
for w in mlp-transmittance-2 mlp-scattering-2; do
  [ -s "$tmp/a/build/weights/$w.json" ] && pass "the build trained $w" || fail "the build trained no $w"
done
compare b "second run, --threads 1, OMP_NUM_THREADS=1"
compare c "--threads 2, OMP_NUM_THREADS=2"
compare d "no --threads, OMP_NUM_THREADS=3"
echo "wall $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }') s for 4 runs"

echo "$failures failed"
[ $failures -eq 0 ]
