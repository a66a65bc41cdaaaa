#!/usr/bin/env bash
# skyfit eval: values against closed forms on the default atmosphere, and every
# input error (exit 2, a message on stderr, nothing on stdout).
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
expect_error "wrong field count" $'h_km,mu\n0,1\n2,0.5,7\n' 'row 3' optical_depth
expect_error "mu > 1" $'h_km,mu\n0,1.5\n' 'row 2, column mu' optical_depth
expect_error "mu < -1" $'h_km,mu\n0,-1.0001\n' 'row 2, column mu' transmittance
expect_error "nu > 1" $'h_km,mu,mu_s,nu\n1,0.5,0.5,1.2\n' 'column nu' single_scattering
expect_error "negative h" $'h_km,mu\n-0.5,1\n' 'row 2, column h_km' optical_depth
expect_error "empty input" '' '.' optical_depth
expect_error "unknown quantity" $'h_km,mu\n0,1\n' 'unknown quantity' radiance_of_doom
expect_error "unknown option" $'h_km,mu\n0,1\n' "unknown option '--frobnicate'" optical_depth --frobnicate
expect_error "negative --to-distance" $'h_km,mu\n0,1\n' 'to-distance' optical_depth --to-distance -3

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

echo "$passed passed, $failed failed"
[[ $failed -eq 0 ]]
