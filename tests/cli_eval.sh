#!/usr/bin/env bash
# skyfit eval: values against closed forms on the default atmosphere, a
# fitted model's (--model) against the reference and its emitted code, and
# every input error (exit 2, a message on stderr, nothing on stdout).
set -euo pipefail

BIN="${SKYFIT_BIN:?SKYFIT_BIN must name the skyfit binary}"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT

passed=0
failed=0
fail() { echo "FAIL: $*"; failed=$((failed + 1)); }
pass() { echo "ok    $*"; passed=$((passed + 1)); }

# check_rel NAME GOT WANT REL: |got - want| <= rel |want|, numbers printed.
check_rel() {
  local line
  line=$(awk -v g="$2" -v w="$3" -v r="$4" 'BEGIN {
    e = g - w; if (e < 0) e = -e; s = w < 0 ? -w : w; if (s == 0) s = 1;
    printf "%s got %.17g want %.17g rel.err %.3g (bound %g)", (e <= r * s ? "ok" : "FAIL"), g, w, e / s, r }')
  if [[ $line == ok* ]]; then pass "$1: ${line#ok }"; else fail "$1: ${line#FAIL }"; fi
}

# column NAME CSV_TEXT ROW: the value of column NAME in data row ROW (1-based).
column() {
  awk -F, -v name="$1" -v row="$3" 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == name) c = i; next }
    NR == row + 1 { print $c }' <<<"$2"
}

# expect_error NAME STDIN_TEXT GREP_PATTERN ARGS...: exit 2, stderr matching
# the pattern (extended regex), stdout empty.
expect_error() {
  local name="$1" input="$2" pattern="$3"
  shift 3
  local rc=0
  printf '%s' "$input" | "$BIN" eval "$@" >"$TMP/out" 2>"$TMP/err" || rc=$?
  local err
  err=$(cat "$TMP/err")
  if [[ $rc -ne 2 ]]; then fail "$name: exit $rc, want 2 (stderr: $err)"; return; fi
  if [[ -s "$TMP/out" ]]; then fail "$name: stdout not empty: $(head -c 200 "$TMP/out")"; return; fi
  if [[ -z "$err" ]]; then fail "$name: stderr empty"; return; fi
  if ! grep -Eq -- "$pattern" <<<"$err"; then fail "$name: stderr '$err' lacks /$pattern/"; return; fi
  pass "$name: exit 2, stdout empty, stderr: $err"
}

# run_ok NAME STDIN_TEXT ARGS...: exit 0; stdout in $OUT.
run_ok() {
  local name="$1" input="$2"
  shift 2
  local rc=0
  OUT=$(printf '%s' "$input" | "$BIN" eval "$@" 2>"$TMP/err") || rc=$?
  if [[ $rc -ne 0 ]]; then fail "$name: exit $rc: $(cat "$TMP/err")"; return 1; fi
  pass "$name: exit 0"
}

# ---- help -----------------------------------------------------------------
rc=0
"$BIN" eval --help >"$TMP/help" 2>&1 || rc=$?
if [[ $rc -eq 0 ]] && grep -q 'optical_depth' "$TMP/help"; then pass "--help: exit 0, names optical_depth"
else fail "--help: exit $rc"; fi

# ---- optical depth on the default atmosphere --------------------------------
# Vertical ray from the ground to the top (100 km): int e^{-h/H} dh = H (1 - e^{-100/H}).
# Rayleigh H = 1/0.125 = 8 km exactly; Mie's file says exp_scale_per_km = -0.8333333,
# so H = 1/0.8333333 (= 1.2 (1 + 4e-8), a difference 1e-9 relative would see).
# Ozone: a tent, h/15 - 2/3 rising from 10 km to 25 km, 8/3 - h/15 falling to
# 40 km (area 15 km), integrated in awk with the file's rounded constants.
run_ok "optical_depth 0,1" $'h_km,mu\n0,1\n200,0.5\n200,-0.99\n' optical_depth || true
OD="$OUT"
header=$(head -n 1 <<<"$OD")
[[ $header == "h_km,mu,rayleigh,mie,ozone" ]] && pass "optical_depth header: $header" || fail "optical_depth header: $header"
ray=$(column rayleigh "$OD" 1)
mie=$(column mie "$OD" 1)
ozone=$(column ozone "$OD" 1)
check_rel "rayleigh(0,1) = 8(1-e^-12.5)" "$ray" "$(awk 'BEGIN { printf "%.17g", 8 * (1 - exp(-12.5)) }')" 1e-9
check_rel "mie(0,1) = H(1-e^-100/H), H=1/0.8333333" "$mie" \
  "$(awk 'BEGIN { H = 1 / 0.8333333; printf "%.17g", H * (1 - exp(-100 / H)) }')" 1e-9
# ozone: density max(0, a h + b) for h < 25, max(0, c h + d) above, on [0, 100]
want_ozone=$(awk 'function piece(a, b, lo, hi,   z, x0, x1) {
    # integral of max(0, a x + b) over [lo, hi] for a line that is zero at z
    z = -b / a; x0 = lo; x1 = hi
    if (a > 0 && z > x0) x0 = z; if (a < 0 && z < x1) x1 = z
    if (x1 <= x0) return 0
    return a / 2 * (x1 * x1 - x0 * x0) + b * (x1 - x0) }
  BEGIN { printf "%.17g", piece(0.0666667, -0.6666667, 0, 25) + piece(-0.0666667, 2.6666667, 25, 100) }')
check_rel "ozone(0,1) = tent integral" "$ozone" "$want_ozone" 1e-9
for col in rayleigh mie ozone; do
  v=$(column $col "$OD" 2)
  check_rel "space viewer 200,0.5 (misses): $col = 0" "$v" 0 0
done
v=$(column rayleigh "$OD" 3)
awk -v v="$v" 'BEGIN { exit !(v > 8) }' && pass "space viewer 200,-0.99 enters: rayleigh $v > 8 (vertical)" \
  || fail "space viewer 200,-0.99: rayleigh $v, want > 8"

# ---- transmittance ----------------------------------------------------------
run_ok "transmittance" $'h_km,mu\n0,1\n200,0.5\n' transmittance || true
TR="$OUT"
header=$(head -n 1 <<<"$TR")
[[ $header == "h_km,mu,T_r,T_g,T_b" ]] && pass "transmittance header: $header" || fail "transmittance header: $header"
check_rel "T_r(0,1) = exp(-(5.802e-3 ray + 4.44e-3 mie + 0.65e-3 oz))" "$(column T_r "$TR" 1)" \
  "$(awk -v r="$ray" -v m="$mie" -v o="$ozone" 'BEGIN { printf "%.17g", exp(-(5.802e-3 * r + (3.996e-3 + 0.444e-3) * m + 0.650e-3 * o)) }')" 1e-12
check_rel "T_b(0,1) = exp(-(33.1e-3 ray + 4.44e-3 mie + 0.085e-3 oz))" "$(column T_b "$TR" 1)" \
  "$(awk -v r="$ray" -v m="$mie" -v o="$ozone" 'BEGIN { printf "%.17g", exp(-(33.1e-3 * r + (3.996e-3 + 0.444e-3) * m + 0.085e-3 * o)) }')" 1e-12
for col in T_r T_g T_b; do check_rel "space viewer 200,0.5: $col = 1" "$(column $col "$TR" 2)" 1 0; done

# ---- --to-distance: vertical segment [0, 10 km]: 8 (1 - e^{-10/8}) -----------
run_ok "--to-distance 10" $'h_km,mu\n0,1\n' optical_depth --to-distance 10 || true
check_rel "rayleigh(0,1, to 10 km) = 8(1-e^-1.25)" "$(column rayleigh "$OUT" 1)" \
  "$(awk 'BEGIN { printf "%.17g", 8 * (1 - exp(-1.25)) }')" 1e-9
# --to top on a ray that leaves through the top: same as the default
run_ok "--to top, 0,1" $'h_km,mu\n0,1\n' optical_depth --to top || true
check_rel "--to top rayleigh(0,1) = default" "$(column rayleigh "$OUT" 1)" "$ray" 0
expect_error "--to top on a ground-hitting row" $'h_km,mu\n0,1\n1,-0.5\n' 'row 3' optical_depth --to top
# An orbit viewer's segment to its ray's ground point, the distance
# correctly rounded (50 digits): the whole ray, not "below the ground" (the
# entry distance taken off had left it 1.25e-12 km past the ground point)
d_ground=$(python3 -c "
from decimal import Decimal, getcontext
getcontext().prec = 50
R, r, mu = Decimal(6360), Decimal(6510), Decimal('-0.5')
print(repr(float(-r * mu - (R * R - r * r * (1 - mu * mu)).sqrt())))")
run_ok "--to-distance at the ground point, 150 km up" $'h_km,mu\n150,-0.5\n' optical_depth --to-distance "$d_ground" || true
at_ground="$OUT"
run_ok "the whole ray, 150 km up" $'h_km,mu\n150,-0.5\n' optical_depth || true
check_rel "--to-distance $d_ground rayleigh(150,-0.5) = the whole ray" "$(column rayleigh "$at_ground" 1)" \
  "$(column rayleigh "$OUT" 1)" 1e-12
expect_error "a segment 1e-8 km past the ground point" $'h_km,mu\n150,-0.5\n' 'below the ground' optical_depth \
  --to-distance "$(python3 -c "print(repr($d_ground + 1e-8))")"

# ---- single scattering ------------------------------------------------------
SS_IN=$'h_km,mu,mu_s,nu\n1,0.5,0.7,0.3\n0.5,0.2,0.9,-0.1\n'
run_ok "single_scattering" "$SS_IN" single_scattering || true
SS="$OUT"
header=$(head -n 1 <<<"$SS")
want_header="h_km,mu,mu_s,nu,rayleigh_r,rayleigh_g,rayleigh_b,mie_r,mie_g,mie_b"
[[ $header == "$want_header" ]] && pass "single_scattering header (no ozone): $header" \
  || fail "single_scattering header: $header, want $want_header"
run_ok "single_scattering --phase" "$SS_IN" single_scattering --phase || true
SSP="$OUT"
for row in 1 2; do
  nu=$(column nu "$SS" $row)
  check_rel "--phase row $row: rayleigh_r x 3/(16pi)(1+nu^2)" "$(column rayleigh_r "$SSP" $row)" \
    "$(awk -v s="$(column rayleigh_r "$SS" $row)" -v nu="$nu" 'BEGIN { pi = atan2(0, -1); printf "%.17g", s * 3 / (16 * pi) * (1 + nu * nu) }')" 1e-14
  # Mie: Cornette-Shanks g = 0.8, seed 004 eq. 6
  check_rel "--phase row $row: mie_g x CS(0.8, nu)" "$(column mie_g "$SSP" $row)" \
    "$(awk -v s="$(column mie_g "$SS" $row)" -v nu="$nu" 'BEGIN { pi = atan2(0, -1); g = 0.8; k = 1 + g * g - 2 * g * nu;
       printf "%.17g", s * 3 / (8 * pi) * (1 - g * g) * (1 + nu * nu) / ((2 + g * g) * k * sqrt(k)) }')" 1e-14
done

# ---- base: default with a different Mie changes only the mie column ---------
cat >"$TMP/thick_mie.json" <<'EOF'
{"base": "default",
 "constituents": [{"name": "mie",
   "density": [{"width_km": 0, "exp_term": 1, "exp_scale_per_km": -0.5, "linear_per_km": 0, "constant": 0}]}]}
EOF
run_ok "base default, mie H = 2 km" $'h_km,mu\n0,1\n' optical_depth --atmosphere "$TMP/thick_mie.json" || true
check_rel "base default: mie(0,1) = 2(1-e^-50)" "$(column mie "$OUT" 1)" \
  "$(awk 'BEGIN { printf "%.17g", 2 * (1 - exp(-50)) }')" 1e-9
check_rel "base default: rayleigh unchanged" "$(column rayleigh "$OUT" 1)" "$ray" 0
check_rel "base default: ozone unchanged" "$(column ozone "$OUT" 1)" "$ozone" 0

# ---- bad input: exit 2, stderr, empty stdout --------------------------------
expect_error "unknown column" $'h_km,mu,zeta\n0,1,2\n' "unknown column 'zeta'" optical_depth
expect_error "missing column" $'h_km\n0\n' "missing column 'mu'" optical_depth
expect_error "missing column mu_s" $'h_km,mu,nu\n0,1,0.5\n' "missing column 'mu_s'" single_scattering
expect_error "non-numeric field" $'h_km,mu\n0,1\n2,abc\n' 'row 3, column mu' optical_depth
bom_out=$(printf '\xEF\xBB\xBFh_km,mu\n0,1\n' | "$BIN" eval optical_depth 2>&1 || true)
if [[ $(head -1 <<<"$bom_out") == h_km,mu,* && $(wc -l <<<"$bom_out") -eq 2 ]]; then
  pass "a UTF-8 byte order mark before the header is skipped"
else fail "byte order mark: $bom_out"; fi
expect_error "--to and --to-distance together" $'h_km,mu\n0,1\n' "give one" optical_depth --to top --to-distance 5
expect_error "hexadecimal field" $'h_km,mu\n0x10,1\n' "row 2, column h_km: '0x10' is not a number" optical_depth
expect_error "wrong field count" $'h_km,mu\n0,1\n2,0.5,7\n' 'row 3' optical_depth
expect_error "mu > 1" $'h_km,mu\n0,1.5\n' 'row 2, column mu' optical_depth
expect_error "mu < -1" $'h_km,mu\n0,-1.0001\n' 'row 2, column mu' transmittance
expect_error "nu > 1" $'h_km,mu,mu_s,nu\n1,0.5,0.5,1.2\n' 'column nu' single_scattering
expect_error "negative h" $'h_km,mu\n-0.5,1\n' 'row 2, column h_km' optical_depth
# The row a range error names is the input's line: blank lines are skipped,
# so the second point after two blank lines is on line 5, not "row 3" (it had
# counted points, row + 2). The same for the tables' quantities (checked
# before any table is made) and for a ray the segment options refuse.
expect_error "line after blank lines (mu)" $'h_km,mu\n0,1\n\n\n0,1.5\n' 'row 5, column mu' optical_depth
expect_error "line after blank CRLF lines (h)" $'h_km,mu\r\n0,1\r\n\r\n-1,1\r\n' 'row 4, column h_km' transmittance
expect_error "line after blank lines (--to top)" $'h_km,mu\n0,1\n\n10,-0.5\n' 'row 4: the ray hits the ground' \
  optical_depth --to top
expect_error "line after blank lines (tables)" $'h_km,mu,mu_s,nu\n0,1,0.5,0.5\n\n0,1,0.5,-2\n' 'row 4, column nu' \
  sky_radiance --orders 1
expect_error "empty input" '' '.' optical_depth
expect_error "unknown quantity" $'h_km,mu\n0,1\n' 'unknown quantity' radiance_of_doom
expect_error "unknown option" $'h_km,mu\n0,1\n' "unknown option '--frobnicate'" optical_depth --frobnicate
expect_error "negative --to-distance" $'h_km,mu\n0,1\n' 'to-distance' optical_depth --to-distance -3
expect_error "empty --to-distance" $'h_km,mu\n0,1\n' 'to-distance' optical_depth --to-distance ""

# A viewer far out in space sees the column of the ray from where it enters
# (models/view_ray.h): straight down from 1e9, 1e14 or 1e300 km, the same
# depths as from the top (1e9 had given 8.005 for 8.0, 1e14 gave 100), and
# the same single scattering.
printf 'h_km,mu\n100,-1\n1e9,-1\n1e14,-1\n1e300,-1\n' | "$BIN" eval optical_depth >"$TMP/far.csv"
printf 'h_km,mu,mu_s,nu\n100,-1,0.5,-0.5\n1e16,-1,0.5,-0.5\n1e200,-1,0.5,-0.5\n' | "$BIN" eval single_scattering \
  >"$TMP/far_ss.csv"
if python3 - "$TMP/far.csv" "$TMP/far_ss.csv" <<'PY'
import sys
for path in sys.argv[1:]:
    rows = [[float(x) for x in l.split(",")] for l in open(path).read().splitlines()[1:]]
    first = len(rows[0]) - (3 if path.endswith("far.csv") else 6)
    for r in rows[1:]:
        for a, b in zip(r[first:], rows[0][first:]):
            assert abs(a - b) <= 1e-9 * abs(b), f"{path}: {r} vs {rows[0]}"
PY
then pass "viewers far out in space: the column and the light of the ray from where it enters"
else fail "viewers far out in space"; fi

# ---- bad atmosphere files ---------------------------------------------------
printf '{"base": "default", "constituents": [{"name": "mie", "phase": {"kind": "cornette_shanks", "g": 0.8, "gg": 1}}]}\n' \
  >"$TMP/unknown_key.json"
expect_error "atmosphere: unknown key" $'h_km,mu\n0,1\n' 'unknown_key\.json: constituents\[0\]\.phase\.gg: unknown key' \
  optical_depth --atmosphere "$TMP/unknown_key.json"
expect_error "atmosphere: missing file" $'h_km,mu\n0,1\n' 'no_such\.json' optical_depth --atmosphere "$TMP/no_such.json"
printf '{"base": "default",\n  "top_radius_km": 6500,,\n}\n' >"$TMP/syntax.json"
expect_error "atmosphere: JSON syntax error" $'h_km,mu\n0,1\n' 'syntax\.json: line 2, column [0-9]+' \
  optical_depth --atmosphere "$TMP/syntax.json"
printf '{"base": "default", "top_radius_km": 6360}\n' >"$TMP/flat.json"
expect_error "atmosphere: top <= bottom" $'h_km,mu\n0,1\n' 'flat\.json: top_radius_km' optical_depth --atmosphere "$TMP/flat.json"
printf '{"base": "default", "constituents": [{"name": "mie", "phase": {"kind": "henyey_greenstein", "g": -1}}]}\n' \
  >"$TMP/g.json"
expect_error "atmosphere: |g| >= 1" $'h_km,mu\n0,1\n' 'g\.json: constituents\[0\]\.phase\.g' optical_depth --atmosphere "$TMP/g.json"
printf '{"base": "default", "constituents": [{"name": "rayleigh", "scattering": [5.8e-3, -1e-3, 3.3e-2]}]}\n' \
  >"$TMP/negative.json"
expect_error "atmosphere: negative coefficient" $'h_km,mu\n0,1\n' 'negative\.json: constituents\[0\]\.scattering\[1\]' \
  optical_depth --atmosphere "$TMP/negative.json"
printf '{"bottom_radius_km": 6360, "top_radius_km": 6460, "constituents": []}\n' >"$TMP/empty.json"
expect_error "atmosphere: empty constituents" $'h_km,mu\n0,1\n' 'empty\.json: constituents' \
  optical_depth --atmosphere "$TMP/empty.json"

# ---- --model: a fitted model instead of the reference (cli/eval_model.h) ----
# On the shipped default weights (weights/default/):
#   - the transmittance network against the reference integrator on 3000
#     random rays of the default scene's domain: RMSE within the scene's
#     budget (1e-3), which the build selected it for meeting; segments to
#     10 and 100 km within twice that (a segment is the ratio of two
#     network evaluations, eq. 43); a segment of length 0 is exactly 1;
#   - the sigmoid's RMSE within twice the RMSE its weights file records;
#   - the sky models: a ray from the ground into it has no length (the
#     network gives exactly 0); Preetham and Hosek take no altitude (the
#     same values at 0 and 5 km, the latter counted on stderr as outside
#     their domain);
#   - all five against their emitted C;
#   - the refusals.
SRC="${SKYFIT_SOURCE_DIR:?SKYFIT_SOURCE_DIR must name the source folder}"
W="$SRC/weights/default"

# The fitted models in double (--model) for viewers far out, straight down:
# the values of the ray from the top (the sigmoid had given T_b 0.9995 for
# 0.659 from 1e13 km, its entry taken from a discriminant that cancels; the
# networks no atmosphere from 1e20 km, the top sphere's two crossings merged
# in the viewer's radius).
far_same() {   # NAME QUANTITY MODEL COLUMNS_AFTER_INPUTS ROWS
  printf '%s' "$5" | "$BIN" eval "$2" --model "$W/$3.json" 2>/dev/null >"$TMP/far_model.csv"
  if python3 - "$TMP/far_model.csv" "$4" <<'PY'
import sys
rows = [[float(x) for x in l.split(",")] for l in open(sys.argv[1]).read().splitlines()[1:]]
n = int(sys.argv[2])
assert len(rows) >= 4 and all(0 < v < 1 for v in rows[0][-n:]), rows
for r in rows[1:]:
    for a, b in zip(r[-n:], rows[0][-n:]):
        assert abs(a - b) <= 1e-12 * abs(b), f"{r} vs {rows[0]}"
PY
  then pass "$1 in double: viewers 1e13, 1e20, 1e300 km out see the ray from the top"
  else fail "$1 in double, viewers far out: $(cat "$TMP/far_model.csv")"; fi
}
far_same sigmoid transmittance sigmoid 3 $'h_km,mu\n200,-1\n1e13,-1\n1e20,-1\n1e300,-1\n'
far_same mlp-transmittance transmittance mlp-transmittance 3 $'h_km,mu\n200,-1\n1e13,-1\n1e20,-1\n1e300,-1\n'
far_same mlp-scattering sky_radiance mlp-scattering 3 \
  $'h_km,mu,mu_s,nu\n200,-1,0.5,-0.5\n1e13,-1,0.5,-0.5\n1e20,-1,0.5,-0.5\n1e300,-1,0.5,-0.5\n'

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
# its segments (eq. 43, as the emitted skyfit_sigmoid_transmittance_segment)
# and rays to the top within the same bound as its full rays
for d in 10 100; do
  "$BIN" eval transmittance --to-distance $d --model "$W/sigmoid.json" <"$TMP/up.csv" >"$TMP/sigmoid_$d.csv"
  rmse_within "sigmoid, segments of $d km" "$TMP/ref_$d.csv" "$TMP/sigmoid_$d.csv" "$(python3 -c "print(2 * $sigmoid_rmse)")"
done
"$BIN" eval transmittance --to top --model "$W/sigmoid.json" <"$TMP/up.csv" >"$TMP/sigmoid_top.csv"
rmse_within "sigmoid, rays to the top" "$TMP/ref_top.csv" "$TMP/sigmoid_top.csv" "$(python3 -c "print(2 * $sigmoid_rmse)")"

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
c=$("$BIN" eval sky_radiance --model "$W/hosek.json" --quiet <"$TMP/high.csv" 2>"$TMP/err_quiet" | cut -d, -f2-)
if [[ $c == "$b" && ! -s "$TMP/err_quiet" ]]; then pass "--quiet: the same values, no note"
else fail "--quiet: '$c' against '$b'; stderr $(cat "$TMP/err_quiet")"; fi

# ---- against the emitted code -----------------------------------------------
# The emitted float32 functions (skyfit codegen from the same weights) at
# 2000 random sky points (the transmittance models also on segments of 30
# km): eval --model's doubles within 1e-4 of them,
# relative to max(|value|, 1e-3 of the model's largest value), which float32
# rounding keeps (tests/test_codegen_headers.c states the tighter
# per-function bounds) and any mix-up of inputs or models breaks. The sky
# network's segments (eq. 44, S(v) - T S(p)) relative to the un-cancelled
# whole ray's value too, as that test takes them: a 30 km segment from 83 km
# toward the limb had 3e-5 of the ray's 0.076, a float32 difference.
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
#define SEGMENT_KM 30.0f   /* the segments' length (T, S) */
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
      case 'T': v = skyfit_mlp_transmittance_segment((float)h, (float)mu, SEGMENT_KM); break;
      case 'M': v = skyfit_mlp_sky_radiance_segment((float)h, (float)mu, (float)mu_s, (float)nu, SEGMENT_KM); break;
      case 'S': v = skyfit_sigmoid_transmittance_segment((float)h, (float)mu, SEGMENT_KM); break;
      default: v = skyfit_sigmoid_transmittance((float)h, (float)mu); break;
    }
    printf("%.9g,%.9g,%.9g\n", v.x, v.y, v.z);
  }
  return 0;
}
C
cut -d, -f1,2 "$TMP/sky.csv" >"$TMP/ray.csv"
# the rays whose 30 km segment ends above the ground (eval refuses the
# others), those toward the ground included: 2000 of them, with a sun for
# the sky network's segments (the transmittance drivers ignore it)
python3 - "$TMP/segment.csv" "$TMP/segment4.csv" <<'PY'
import math, random, sys
r, sun, R, n = random.Random(11), random.Random(12), 6360.0, 0
with open(sys.argv[1], "w") as f, open(sys.argv[2], "w") as f4:   # f4: the driver's 4 columns
    f.write("h_km,mu\n")
    f4.write("h_km,mu,mu_s,nu\n")
    while n < 2000:
        h, mu = r.uniform(0, 100), r.uniform(-1, 1)
        rad = R + h
        disc = rad * rad * (mu * mu - 1) + R * R
        if mu < 0 and disc >= 0 and -rad * mu - math.sqrt(disc) < 30.5:
            continue
        f.write("%.17g,%.17g\n" % (h, mu))
        f4.write("%.17g,%.17g,%.17g,%.17g\n" % (h, mu, sun.uniform(-0.17, 1), sun.uniform(-1, 1)))
        n += 1
PY
if cc -std=c99 -O2 -I"$TMP/gen" -o "$TMP/drive" "$TMP/drive.c" -lm; then
  for m in mlp-scattering preetham hosek mlp-transmittance sigmoid mlp-transmittance-segment sigmoid-segment \
           mlp-scattering-segment; do
    segment=() drive_in=sky.csv
    case $m in
      mlp-transmittance) q=transmittance key=t points=ray.csv ;;
      sigmoid) q=transmittance key=s points=ray.csv ;;
      mlp-transmittance-segment) q=transmittance key=T points=segment.csv drive_in=segment4.csv segment=(--to-distance 30) ;;
      sigmoid-segment) q=transmittance key=S points=segment.csv drive_in=segment4.csv segment=(--to-distance 30) ;;
      mlp-scattering-segment) q=sky_radiance key=M points=segment4.csv drive_in=segment4.csv
        segment=(--to-distance 30 --transmittance-model "$W/mlp-transmittance.json") ;;
      *) q=sky_radiance key=$m points=sky.csv ;;
    esac
    # the values only: the columns after the inputs
    "$BIN" eval $q --model "$W/${m%-segment}.json" "${segment[@]}" <"$TMP/$points" 2>/dev/null |
      awk -F, -v skip=$([[ $q == transmittance ]] && echo 2 || echo 4) 'NR > 1 {
        s = $(skip + 1); for (i = skip + 2; i <= NF; ++i) s = s "," $i; print s }' >"$TMP/eval_$m"
    "$TMP/drive" "$key" <"$TMP/$drive_in" >"$TMP/c_$m"
    : >"$TMP/whole_$m"   # the un-cancelled scale: the whole ray's values (sky segments), else none
    if [[ $m == mlp-scattering-segment ]]; then
      "$BIN" eval sky_radiance --model "$W/mlp-scattering.json" <"$TMP/$points" 2>/dev/null |
        awk -F, 'NR > 1 { print $5 "," $6 "," $7 }' >"$TMP/whole_$m"
    fi
    line=$(python3 - "$TMP/eval_$m" "$TMP/c_$m" "$TMP/whole_$m" <<'PY'
import sys
d = [[float(x) for x in l.split(",")] for l in open(sys.argv[1])]
c = [[float(x) for x in l.split(",")] for l in open(sys.argv[2])]
w = [[float(x) for x in l.split(",")] for l in open(sys.argv[3])] or [[0.0] * len(row) for row in d]
assert len(d) == len(c) == len(w) == 2000, (len(d), len(c), len(w))
scale = max(abs(x) for row in d for x in row)
worst = max(abs(a - b) / max(abs(a), abs(s), 1e-3 * scale)
            for rd, rc, rw in zip(d, c, w) for a, b, s in zip(rd, rc, rw))
print("%s worst %.3g (bound 1e-4) over %d values" % ("ok" if worst <= 1e-4 else "FAIL", worst, 3 * len(d)))
PY
)
    if [[ $line == ok* ]]; then pass "$m: eval --model against the emitted C: ${line#ok }"
    else fail "$m: eval --model against the emitted C: ${line#FAIL }"; fi
  done
else fail "the emitted header did not compile"; fi

# Preetham and Hosek never give a negative radiance: Hosek's default fit
# dipped to -0.0038 in G near the horizon at a low sun (mu_s < 0.053, mu
# < 0.028, 648 points of this grid). A grid over their domain, the horizon
# and the low sun refined.
python3 - "$TMP/sky_grid.csv" <<'PY'
import math, sys
with open(sys.argv[1], "w") as f:
    f.write("h_km,mu,mu_s,nu\n")
    mus = [i / 400 for i in range(0, 41)] + [0.1 * i for i in range(2, 11)]
    mu_ss = [i / 600 for i in range(0, 61)] + [0.1 * i for i in range(2, 11)]
    for mu in mus:
        for mu_s in mu_ss:
            s = math.sqrt(max(0.0, (1 - mu * mu) * (1 - mu_s * mu_s)))
            for k in range(24):   # nu over its range at (mu, mu_s): the azimuth
                phi = math.pi * k / 23
                f.write("0,%.17g,%.17g,%.17g\n" % (mu, mu_s, mu * mu_s + s * math.cos(phi)))
PY
for m in preetham hosek; do
  "$BIN" eval sky_radiance --model "$W/$m.json" < "$TMP/sky_grid.csv" > "$TMP/sky_grid_$m.csv" 2>/dev/null
  low=$(awk -F, 'NR > 1 { for (i = 5; i <= NF; ++i) if (n == 0 || $i < min) { min = $i; n = 1 } } END { printf "%.17g", min }' \
    "$TMP/sky_grid_$m.csv")
  rows=$(($(wc -l < "$TMP/sky_grid_$m.csv") - 1))
  if awk -v v="$low" 'BEGIN { exit !(v >= 0) }' && [[ $rows -gt 50000 ]]; then
    pass "$m: no negative radiance on $rows grid points (smallest $low)"
  else fail "$m: smallest radiance $low on $rows grid points"; fi
done

# ---- refusals ---------------------------------------------------------------
expect_error "--model for optical depth" "$(cat "$TMP/all.csv")" "fitted models give transmittance or sky_radiance" \
  optical_depth --model "$W/sigmoid.json"
expect_error "--model with --atmosphere" "$(cat "$TMP/all.csv")" "leave out --atmosphere" \
  transmittance --model "$W/sigmoid.json" --atmosphere "$SRC/examples/atmospheres/mars_dusty.json"
expect_error "a sky model for transmittance" "$(cat "$TMP/all.csv")" 'mlp-scattering.json: model: "mlp-scattering" gives sky_radiance' \
  transmittance --model "$W/mlp-scattering.json"
expect_error "a transmittance model for sky radiance" "$(cat "$TMP/ground.csv")" 'sigmoid.json: model: "sigmoid" gives transmittance' \
  sky_radiance --model "$W/sigmoid.json"
"$BIN" fit mlp --layers 2,2,1 --write-init "$TMP/generic.json" --data /dev/null --inputs 1 >/dev/null 2>&1 || true
if [[ -s "$TMP/generic.json" ]]; then
  expect_error "a model eval does not take" "$(cat "$TMP/all.csv")" 'generic.json: model: eval does not evaluate model "mlp"' \
    transmittance --model "$TMP/generic.json"
else fail "could not write a generic network's weights file"; fi
expect_error "multiple scattering of a fitted model" "$(cat "$TMP/ground.csv")" \
  "--model: fitted models give transmittance or sky_radiance, not multiple_scattering" \
  multiple_scattering --model "$W/mlp-scattering.json"
expect_error "--tables with --model" "$(cat "$TMP/ground.csv")" "--tables: the reference's multiple_scattering" \
  sky_radiance --model "$W/mlp-scattering.json" --tables "$TMP"
expect_error "--scene with the reference's transmittance" "h_km,mu
0,1
" "--scene: the reference's multiple_scattering and sky_radiance read tables" transmittance --scene "$TMP/none.json"
expect_error "a missing weights file" "$(cat "$TMP/all.csv")" "no_such.json" transmittance --model "$TMP/no_such.json"
# Parameters the model does not read (they had been ignored): a misspelt
# one, the sky network's ground network in a transmittance file, a layer
# past a gap in the numbering.
python3 - "$W" "$TMP" <<'PY'
import json, sys
w, d = sys.argv[1], sys.argv[2]
s = json.load(open(w + "/mlp-scattering.json"))
t = json.load(open(w + "/mlp-transmittance.json"))
s["params"]["norm_capp"] = s["params"]["norm_cap"]
json.dump(s, open(d + "/s_misspelt.json", "w"))
t2 = dict(t, params=dict(t["params"], ground_W0=t["params"]["W0"]))
json.dump(t2, open(d + "/t_ground.json", "w"))
t3 = dict(t, params=dict(t["params"], W4=t["params"]["W2"]))
json.dump(t3, open(d + "/t_gap.json", "w"))
# a layer wider than the evaluators' buffers (256 units): 2000 had overrun the stack
n_out = len(t["params"]["W2"])
t4 = dict(t, params={"W0": [[0.1, 0.2]] * 2000, "b0": [0.0] * 2000, "W1": [[0.001] * 2000] * n_out, "b1": [0.0] * n_out})
json.dump(t4, open(d + "/t_wide.json", "w"))
PY
expect_error "a misspelt parameter" "$(cat "$TMP/ground.csv")" \
  's_misspelt.json: params.norm_capp: not a parameter of this mlp-scattering model' sky_radiance --model "$TMP/s_misspelt.json"
expect_error "a ground network in a transmittance file" "$(cat "$TMP/all.csv")" \
  't_ground.json: params.ground_W0: not a parameter of this mlp-transmittance model' transmittance --model "$TMP/t_ground.json"
expect_error "a layer past a gap" "$(cat "$TMP/all.csv")" \
  't_gap.json: params.W4: not a parameter' transmittance --model "$TMP/t_gap.json"
expect_error "a layer of 2000 units" "$(cat "$TMP/all.csv")" \
  't_wide.json: params.W0: 2000 rows \(units\), expected 1 to 256' transmittance --model "$TMP/t_wide.json"
# The sky network's segments (seed 000 eq. 44) take its transmittance
# network: without it, with another model, one fitted for another
# atmosphere (mars's, its hash as codegen states it) are refused; with it
# a segment of length 0 is dark and one past the top is the whole ray.
expect_error "a segment of the sky network without its transmittance" "$(cat "$TMP/ground.csv")" \
  "add --transmittance-model T.json" sky_radiance --model "$W/mlp-scattering.json" --to-distance 5
expect_error "the sky network's segments with a sigmoid" "$(cat "$TMP/ground.csv")" \
  'sigmoid.json: model: --transmittance-model takes an mlp-transmittance network, got "sigmoid"' \
  sky_radiance --model "$W/mlp-scattering.json" --to-distance 5 --transmittance-model "$W/sigmoid.json"
expect_error "--transmittance-model for hosek" "$(cat "$TMP/ground.csv")" \
  'hosek.json: --transmittance-model joins an mlp-scattering model' \
  sky_radiance --model "$W/hosek.json" --to-distance 5 --transmittance-model "$W/mlp-transmittance.json"
# the option given is the one named (--to-distance had been answered about --to top)
expect_error "hosek with --to-distance" "$(cat "$TMP/ground.csv")" \
  'hosek.json: model "hosek" evaluates the full ray .*; --to-distance takes sigmoid, mlp-transmittance or mlp-scattering' \
  sky_radiance --model "$W/hosek.json" --to-distance 5
expect_error "hosek with --to top" "$(cat "$TMP/ground.csv")" \
  'hosek.json: model "hosek" evaluates the full ray .*; --to top takes a transmittance model' \
  sky_radiance --model "$W/hosek.json" --to top
expect_error "--transmittance-model without --to-distance" "$(cat "$TMP/ground.csv")" \
  '--transmittance-model: for sky_radiance --model \(mlp-scattering\) with --to-distance only' \
  sky_radiance --model "$W/mlp-scattering.json" --transmittance-model "$W/mlp-transmittance.json"
mkdir -p "$TMP/mars_hash"
"$BIN" codegen --baselines naive --atmosphere "$SRC/examples/atmospheres/mars_dusty.json" --lang c --out "$TMP/mars_hash" \
  --quiet
mars_hash=$(sed -n 's/.*atmosphere: mars-dusty, hash \([0-9a-f]\{16\}\).*/\1/p' "$TMP/mars_hash/skyfit.h" | head -1)
python3 - "$W/mlp-transmittance.json" "$SRC/examples/atmospheres/mars_dusty.json" "$mars_hash" "$TMP/t_mars.json" <<'PY'
import json, sys
t = json.load(open(sys.argv[1]))
t["atmosphere"], t["atmosphere_hash"] = json.load(open(sys.argv[2])), sys.argv[3]
json.dump(t, open(sys.argv[4], "w"))
PY
expect_error "a transmittance network of another atmosphere" "$(cat "$TMP/ground.csv")" \
  "t_mars.json: atmosphere_hash: $mars_hash, fitted for another atmosphere" \
  sky_radiance --model "$W/mlp-scattering.json" --to-distance 5 --transmittance-model "$TMP/t_mars.json"
printf 'h_km,mu,mu_s,nu\n0,0.3,0.5,0.2\n5,0.8,-0.1,0.4\n60,0.05,0.9,0.1\n' >"$TMP/sky_up.csv"
"$BIN" eval sky_radiance --model "$W/mlp-scattering.json" <"$TMP/sky_up.csv" >"$TMP/sky_full.csv"
"$BIN" eval sky_radiance --model "$W/mlp-scattering.json" --transmittance-model "$W/mlp-transmittance.json" \
  --to-distance 1e5 <"$TMP/sky_up.csv" >"$TMP/sky_past_top.csv"
"$BIN" eval sky_radiance --model "$W/mlp-scattering.json" --transmittance-model "$W/mlp-transmittance.json" \
  --to-distance 0 <"$TMP/sky_up.csv" >"$TMP/sky_zero.csv"
if [[ -s $TMP/sky_full.csv ]] && cmp -s "$TMP/sky_full.csv" "$TMP/sky_past_top.csv" &&
   [[ $(awk -F, 'NR > 1 && ($5 != 0 || $6 != 0 || $7 != 0)' "$TMP/sky_zero.csv" | wc -l) -eq 0 ]] &&
   [[ $(wc -l < "$TMP/sky_zero.csv") -eq 4 ]]; then
  pass "the sky network's segments: past the top the whole ray (same bytes), of length 0 dark"
else fail "the sky network's segments: $(paste -d'|' "$TMP/sky_full.csv" "$TMP/sky_past_top.csv" "$TMP/sky_zero.csv")"; fi
expect_error "--to top through the ground" "$(cat "$TMP/all.csv")" "row [0-9]+: the ray hits the ground" \
  transmittance --model "$W/mlp-transmittance.json" --to top
expect_error "sky radiance without mu_s" "$(cat "$TMP/all.csv")" "missing column 'mu_s'" \
  sky_radiance --model "$W/mlp-scattering.json"

# A sun the atmosphere file accepts but float32 tables cannot hold (1e39):
# the tables are refused, exit 2, before anything is printed.
printf '{"base": "default", "sun_irradiance": [1e39, 1, 1]}\n' > "$TMP/sun39.json"
expect_error "tables holding inf" "$(printf 'h_km,mu,mu_s,nu\n1,0.5,0.5,0.9\n')" \
  "its single_rayleigh table holds inf .*too large for tables of float32" \
  sky_radiance --atmosphere "$TMP/sun39.json" --resolution 32x16,8x16x8x4
# A scattering coefficient of 1e12 per km: finite values, exit 0. The count
# of quadrature parts had overflowed int (UBSan: data/ray_quadrature.c)
# and the tables held NaN.
printf '{"base": "default", "constituents": [{"name": "rayleigh", "scattering": [1e12, 1e12, 1e12]}]}\n' \
  > "$TMP/huge.json"
if printf 'h_km,mu,mu_s,nu\n1,0.5,0.5,0.9\n' |
  "$BIN" eval sky_radiance --atmosphere "$TMP/huge.json" --resolution 32x16,8x16x8x4 --quiet > "$TMP/out" 2>"$TMP/err" &&
  ! grep -Eiq 'nan|inf' "$TMP/out" && awk -F, 'NR == 2 { for (i = 5; i <= 7; ++i) if ($i + 0 < 0) exit 1 }' "$TMP/out"; then
  pass "1e12 per km: finite, non-negative radiance"
else
  fail "1e12 per km: $(cat "$TMP/out" "$TMP/err" | head -c 300)"
fi

# A read error is named (a folder on stdin had read as "empty input"); a
# long field is cut in the message, which keeps its verdict (it had been
# cut off by the field).
rc=0
"$BIN" eval transmittance <"$TMP" >"$TMP/out" 2>"$TMP/err" || rc=$?
[[ $rc -eq 2 && ! -s $TMP/out ]] && grep -q "stdin: cannot read: Is a directory" "$TMP/err" &&
  pass "stdin a folder: exit 2, $(cat "$TMP/err")" || fail "stdin a folder: exit $rc, $(cat "$TMP/err")"
expect_error "a 1200-digit field" "h_km,mu"$'\n'"1,$(printf '9%.0s' $(seq 1200))x"$'\n' \
  "row 2, column mu: '9{60}\.\.\.' is not a number" transmittance

# Finite inputs whose values overflow (a weights file's extreme but finite
# parameters, a sun of 1e308) had printed inf, exit 0: now exit 2 naming
# the file, the column and the point, nothing on stdout.
python3 -c "
import json, sys
d = json.load(open(sys.argv[1])); d['params']['b2'] = [-1000.0] * len(d['params']['b2'])
json.dump(d, open(sys.argv[2], 'w'))" "$W/mlp-scattering.json" "$TMP/overflow.json"
expect_error "--model whose output overflows" $'h_km,mu,mu_s,nu\n0,0.5,0.5,1\n' \
  'overflow.json: L_r is not finite at point 1 \(h_km=0, mu=0.5, mu_s=0.5, nu=1\)' sky_radiance --model "$TMP/overflow.json"
printf '{"base": "default", "sun_irradiance": [1.7e308, 1.7e308, 1.7e308], "constituents": [
  {"name": "mie", "phase": {"kind": "henyey_greenstein", "g": 0.999}}]}\n' >"$TMP/bright.json"
expect_error "single scattering that overflows" $'h_km,mu,mu_s,nu\n5,0.2,0.3,0.9\n0,0.5,0.5,1\n' \
  "bright.json: mie_r is not finite at point 2 .*the atmosphere's values overflow" \
  single_scattering --phase --atmosphere "$TMP/bright.json"

echo "$passed passed, $failed failed"
[[ $failed -eq 0 ]]
