#!/usr/bin/env bash
# skyfit eval QUANTITY --model W.json (SPEC §11, cli/eval_model.h) on the
# shipped default weights (weights/default/):
#   - the transmittance network against the reference integrator on 3000
#     random rays of the default scene's domain: RMSE within the scene's
#     budget (1e-3), which the build selected it for meeting; segments to
#     10 and 100 km within twice that (a segment is the ratio of two
#     network evaluations, eq. 43); a segment of length 0 is exactly 1;
#   - the sigmoid's RMSE within twice the RMSE its weights file records;
#   - the sky models: a ray from the ground into the ground has no length
#     (the network gives exactly 0); Preetham and Hosek take no altitude
#     (the same values at 0 and 5 km, the latter counted on stderr as
#     outside their domain);
#   - the refusals: exit 2, a message naming the file or option, nothing
#     on stdout.
set -euo pipefail

BIN="${SKYFIT_BIN:?SKYFIT_BIN must name the skyfit binary}"
SRC="${SKYFIT_SOURCE_DIR:?SKYFIT_SOURCE_DIR must name the source folder}"
W="$SRC/weights/default"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT

passed=0
failed=0
fail() { echo "FAIL: $*"; failed=$((failed + 1)); }
pass() { echo "ok    $*"; passed=$((passed + 1)); }

# points FILE SEED MU_MIN: 3000 rays, h uniform in [0, 100] km, mu in [MU_MIN, 1]
points() {
  python3 - "$1" "$2" "$3" <<'PY'
import random, sys
r = random.Random(int(sys.argv[2]))
with open(sys.argv[1], "w") as f:
    f.write("h_km,mu\n")
    for _ in range(3000):
        f.write("%.17g,%.17g\n" % (r.uniform(0, 100), r.uniform(float(sys.argv[3]), 1)))
PY
}

# rmse_within NAME REFERENCE.csv MODEL.csv BOUND: the RMSE over every value
# column (after the first 2) at most BOUND, the input columns the same.
rmse_within() {
  local line
  line=$(python3 - "$2" "$3" "$4" <<'PY'
import csv, math, sys
ref = list(csv.reader(open(sys.argv[1])))
mod = list(csv.reader(open(sys.argv[2])))
bound = float(sys.argv[3])
assert ref[0] == mod[0] and len(ref) == len(mod), "different columns or rows"
sq, n, worst = 0.0, 0, 0.0
for a, b in zip(ref[1:], mod[1:]):
    assert a[:2] == b[:2], "different input columns"
    for x, y in zip(a[2:], b[2:]):
        e = float(y) - float(x)
        sq, n, worst = sq + e * e, n + 1, max(worst, abs(e))
rmse = math.sqrt(sq / n)
print("%s RMSE %.3g over %d values (bound %g), max abs %.3g" % ("ok" if rmse <= bound else "FAIL", rmse, n, bound, worst))
PY
)
  if [[ $line == ok* ]]; then pass "$1: ${line#ok }"; else fail "$1: ${line#FAIL }"; fi
}

# expect_error NAME STDIN_FILE GREP_PATTERN ARGS...: exit 2, stderr matching, stdout empty.
expect_error() {
  local name="$1" input="$2" pattern="$3"
  shift 3
  local rc=0
  "$BIN" eval "$@" <"$input" >"$TMP/out" 2>"$TMP/err" || rc=$?
  local err
  err=$(cat "$TMP/err")
  if [[ $rc -ne 2 ]]; then fail "$name: exit $rc, want 2 (stderr: $err)"; return; fi
  if [[ -s "$TMP/out" ]]; then fail "$name: stdout not empty: $(head -c 200 "$TMP/out")"; return; fi
  if ! grep -Eq -- "$pattern" <<<"$err"; then fail "$name: stderr '$err' lacks /$pattern/"; return; fi
  pass "$name: exit 2, stdout empty, stderr: $err"
}

# ---- transmittance against the reference ----------------------------------
points "$TMP/all.csv" 7 -1
points "$TMP/up.csv" 8 0
"$BIN" eval transmittance <"$TMP/all.csv" >"$TMP/ref.csv"
"$BIN" eval transmittance --model "$W/mlp-transmittance.json" <"$TMP/all.csv" >"$TMP/mlp.csv"
rmse_within "mlp-transmittance, full rays" "$TMP/ref.csv" "$TMP/mlp.csv" 1e-3
for d in 10 100; do
  "$BIN" eval transmittance --to-distance $d <"$TMP/up.csv" >"$TMP/ref_$d.csv"
  "$BIN" eval transmittance --to-distance $d --model "$W/mlp-transmittance.json" <"$TMP/up.csv" >"$TMP/mlp_$d.csv"
  rmse_within "mlp-transmittance, segments of $d km" "$TMP/ref_$d.csv" "$TMP/mlp_$d.csv" 2e-3
done
"$BIN" eval transmittance --to top <"$TMP/up.csv" >"$TMP/ref_top.csv"
"$BIN" eval transmittance --to top --model "$W/mlp-transmittance.json" <"$TMP/up.csv" >"$TMP/mlp_top.csv"
rmse_within "mlp-transmittance, rays to the top" "$TMP/ref_top.csv" "$TMP/mlp_top.csv" 1e-3
zero=$("$BIN" eval transmittance --to-distance 0 --model "$W/mlp-transmittance.json" <"$TMP/up.csv" |
  awk -F, 'NR > 1 && ($3 != 1 || $4 != 1 || $5 != 1) { ++bad } END { print bad + 0 }')
if [[ $zero -eq 0 ]]; then pass "segments of length 0: T = 1 exactly on all 3000 rays"
else fail "segments of length 0: $zero rays with T != 1"; fi
sigmoid_rmse=$(python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['metrics']['rmse'])" "$W/sigmoid.json")
"$BIN" eval transmittance --model "$W/sigmoid.json" <"$TMP/all.csv" >"$TMP/sigmoid.csv"
rmse_within "sigmoid, full rays (twice its file's RMSE $sigmoid_rmse)" "$TMP/ref.csv" "$TMP/sigmoid.csv" \
  "$(python3 -c "print(2 * $sigmoid_rmse)")"

# ---- sky radiance -----------------------------------------------------------
printf 'h_km,mu,mu_s,nu\n0,-0.5,0.5,0.1\n0,-0.01,0.9,0.2\n' >"$TMP/down.csv"
out=$("$BIN" eval sky_radiance --model "$W/mlp-scattering.json" <"$TMP/down.csv")
if [[ $(head -1 <<<"$out") == "h_km,mu,mu_s,nu,L_r,L_g,L_b" ]] &&
   [[ $(awk -F, 'NR > 1 && ($5 != 0 || $6 != 0 || $7 != 0)' <<<"$out") == "" ]]; then
  pass "mlp-scattering: rays from the ground into it have radiance 0"
else fail "mlp-scattering: rays from the ground into it: $out"; fi
printf 'h_km,mu,mu_s,nu\n0,0.5,0.5,0.9\n0,0.9,0.2,0.3\n' >"$TMP/ground.csv"
printf 'h_km,mu,mu_s,nu\n5,0.5,0.5,0.9\n5,0.9,0.2,0.3\n' >"$TMP/high.csv"
for m in preetham hosek; do
  a=$("$BIN" eval sky_radiance --model "$W/$m.json" <"$TMP/ground.csv" 2>"$TMP/err_ground" | cut -d, -f2-)
  b=$("$BIN" eval sky_radiance --model "$W/$m.json" <"$TMP/high.csv" 2>"$TMP/err_high" | cut -d, -f2-)
  if [[ -n $a && $a == "$b" && ! -s "$TMP/err_ground" ]] &&
     grep -q "2 of 2 points lie outside the domain the model was fitted on (h_km 0..0" "$TMP/err_high"; then
    pass "$m: a ground viewer's values whatever h_km; h_km 5 counted outside its domain"
  else fail "$m: 0 km '$a' against 5 km '$b'; stderr $(cat "$TMP/err_ground" "$TMP/err_high")"; fi
done

# ---- against the emitted code -----------------------------------------------
# The emitted float32 functions (skyfit codegen from the same weights) at
# 2000 random sky points: eval --model's doubles within 1e-4 of them,
# relative to max(|value|, 1e-3 of the model's largest value), which float32
# rounding keeps (tests/test_codegen_headers.c states the tighter
# per-function bounds) and any mix-up of inputs or models breaks.
mkdir -p "$TMP/gen"
"$BIN" codegen --weights "$W/mlp-scattering.json" --weights "$W/preetham.json" --weights "$W/hosek.json" \
  --weights "$W/mlp-transmittance.json" --weights "$W/sigmoid.json" --lang c --out "$TMP/gen" 2>/dev/null
python3 - "$TMP/sky.csv" <<'PY'
import random, sys
r = random.Random(9)
with open(sys.argv[1], "w") as f:
    f.write("h_km,mu,mu_s,nu\n")
    for _ in range(2000):
        f.write("%.17g,%.17g,%.17g,%.17g\n" % (r.uniform(0, 100), r.uniform(-1, 1), r.uniform(-0.17, 1), r.uniform(-1, 1)))
PY
cat >"$TMP/drive.c" <<'C'
#include <stdio.h>
#include "skyfit.h"
/* argv[1]: the model; stdin: the CSV points; stdout: the values as eval --model writes them */
int main(int argc, char **argv) {
  char line[512];
  if (argc != 2 || !fgets(line, sizeof line, stdin)) return 2;
  double h, mu, mu_s, nu;
  while (scanf("%lf,%lf,%lf,%lf", &h, &mu, &mu_s, &nu) == 4) {
    skyfit_vec3 v;
    switch (argv[1][0]) {
      case 'm': v = skyfit_mlp_sky_radiance((float)h, (float)mu, (float)mu_s, (float)nu); break;
      case 'p': v = skyfit_preetham_sky_radiance((float)mu, (float)mu_s, (float)nu); break;
      case 'h': v = skyfit_hosek_sky_radiance((float)mu, (float)mu_s, (float)nu); break;
      case 't': v = skyfit_mlp_transmittance((float)h, (float)mu); break;
      default: v = skyfit_sigmoid_transmittance((float)h, (float)mu); break;
    }
    printf("%.9g,%.9g,%.9g\n", v.x, v.y, v.z);
  }
  return 0;
}
C
cut -d, -f1,2 "$TMP/sky.csv" >"$TMP/ray.csv"
if cc -std=c99 -O2 -I"$TMP/gen" -o "$TMP/drive" "$TMP/drive.c" -lm; then
  for m in mlp-scattering preetham hosek mlp-transmittance sigmoid; do
    case $m in
      mlp-transmittance) q=transmittance key=t points=ray.csv ;;
      sigmoid) q=transmittance key=s points=ray.csv ;;
      *) q=sky_radiance key=$m points=sky.csv ;;
    esac
    # the values only: the columns after the inputs
    "$BIN" eval $q --model "$W/$m.json" <"$TMP/$points" 2>/dev/null |
      awk -F, -v skip=$([[ $q == transmittance ]] && echo 2 || echo 4) 'NR > 1 {
        s = $(skip + 1); for (i = skip + 2; i <= NF; ++i) s = s "," $i; print s }' >"$TMP/eval_$m"
    "$TMP/drive" "$key" <"$TMP/sky.csv" >"$TMP/c_$m"
    line=$(python3 - "$TMP/eval_$m" "$TMP/c_$m" <<'PY'
import sys
d = [[float(x) for x in l.split(",")] for l in open(sys.argv[1])]
c = [[float(x) for x in l.split(",")] for l in open(sys.argv[2])]
assert len(d) == len(c) == 2000, (len(d), len(c))
scale = max(abs(x) for row in d for x in row)
worst = max(abs(a - b) / max(abs(a), 1e-3 * scale) for rd, rc in zip(d, c) for a, b in zip(rd, rc))
print("%s worst %.3g (bound 1e-4) over %d values" % ("ok" if worst <= 1e-4 else "FAIL", worst, 3 * len(d)))
PY
)
    if [[ $line == ok* ]]; then pass "$m: eval --model against the emitted C: ${line#ok }"
    else fail "$m: eval --model against the emitted C: ${line#FAIL }"; fi
  done
else fail "the emitted header did not compile"; fi

# ---- refusals ---------------------------------------------------------------
expect_error "--model for optical depth" "$TMP/all.csv" "fitted models give transmittance or sky_radiance" \
  optical_depth --model "$W/sigmoid.json"
expect_error "--model with --atmosphere" "$TMP/all.csv" "leave out --atmosphere" \
  transmittance --model "$W/sigmoid.json" --atmosphere "$SRC/examples/atmospheres/mars_dusty.json"
expect_error "a sky model for transmittance" "$TMP/all.csv" 'mlp-scattering.json: model: "mlp-scattering" gives sky_radiance' \
  transmittance --model "$W/mlp-scattering.json"
expect_error "a transmittance model for sky radiance" "$TMP/ground.csv" 'sigmoid.json: model: "sigmoid" gives transmittance' \
  sky_radiance --model "$W/sigmoid.json"
"$BIN" fit mlp --layers 2,2,1 --write-init "$TMP/generic.json" --data /dev/null --inputs 1 >/dev/null 2>&1 || true
if [[ -s "$TMP/generic.json" ]]; then
  expect_error "a model eval does not take" "$TMP/all.csv" 'generic.json: model: eval does not evaluate model "mlp"' \
    transmittance --model "$TMP/generic.json"
else fail "could not write a generic network's weights file"; fi
expect_error "a missing weights file" "$TMP/all.csv" "no_such.json" transmittance --model "$TMP/no_such.json"
expect_error "--to top of the sigmoid" "$TMP/all.csv" "--to top and --to-distance take an mlp-transmittance model" \
  transmittance --model "$W/sigmoid.json" --to top
expect_error "a segment of the sky network" "$TMP/ground.csv" "--to top and --to-distance take an mlp-transmittance" \
  sky_radiance --model "$W/mlp-scattering.json" --to-distance 5
expect_error "--to top through the ground" "$TMP/all.csv" "row [0-9]+: the ray hits the ground" \
  transmittance --model "$W/mlp-transmittance.json" --to top
expect_error "sky radiance without mu_s" "$TMP/all.csv" "missing column 'mu_s'" \
  sky_radiance --model "$W/mlp-scattering.json"

echo "$passed passed, $failed failed"
[[ $failed -eq 0 ]]
