#!/bin/bash
# Likely unit mistakes in an atmosphere file (models/atmosphere_units.h):
# each mistaken file gets exactly its one warning on stderr, naming the
# file, the key, the value and what was meant, and the command still runs
# (exit 0, output written); a command that loads the atmosphere through a
# scene warns once; the shipped atmospheres and real planets get none.
set -u
BIN=${SKYFIT_BIN:?SKYFIT_BIN must name the skyfit binary}
SRC=${SKYFIT_SOURCE_DIR:?SKYFIT_SOURCE_DIR must name the source tree}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
check() {   # description, command
  if eval "$2"; then echo "ok   $1"; else echo "FAIL $1"; failures=$((failures + 1)); fi
}

# eval_atm FILE: optical depth straight up from the ground; stdout to
# $tmp/out, stderr to $tmp/err, the exit code in rc.
eval_atm() {
  printf 'h_km,mu\n0,1\n' | "$BIN" eval optical_depth --atmosphere "$1" >"$tmp/out" 2>"$tmp/err"
  rc=$?
}

# name|JSON|the key and value the warning names|what it says was meant
cases=(
  'radius_metres|{"base": "default", "bottom_radius_km": 6360000, "top_radius_km": 6460000}|bottom_radius_km = 6.36e+06|given in metres? (that is 6360 km'
  'top_metres|{"base": "default", "top_radius_km": 6460000}|top_radius_km = 6.46e+06|given in metres? (that is 6460 km'
  'too_thick|{"base": "default", "top_radius_km": 64600}|top_radius_km = 64600|more than the planet'
  'sun_degrees|{"base": "default", "sun_angular_radius_rad": 0.27}|sun_angular_radius_rad = 0.27|given in degrees? (0.27 degrees is 0.00471 rad)'
  'rising|{"base": "default", "constituents": [{"name": "rayleigh", "density": [{"exp_term": 1, "exp_scale_per_km": 0.125}]}]}|"rayleigh" density[0].exp_scale_per_km = 0.125|did you mean -0.125'
  'scale_per_metre|{"base": "default", "constituents": [{"name": "mie", "density": [{"exp_term": 1, "exp_scale_per_km": -0.0008333}]}]}|"mie" density[0].exp_scale_per_km = -0.0008333|given per metre? (-0.8333 per km'
  'coefficients_per_metre|{"base": "default", "constituents": [{"name": "rayleigh", "scattering": [5.802e-6, 13.558e-6, 33.1e-6]}, {"name": "mie", "scattering": 3.996e-6, "absorption": 0.444e-6}, {"name": "ozone", "absorption": [0.65e-6, 1.881e-6, 0.085e-6]}]}|"rayleigh" scattering[2] = 3.31e-05|given per metre?'
  'width_metres|{"base": "default", "constituents": [{"name": "ozone", "density": [{"width_km": 25000, "linear_per_km": 0.0666667, "constant": -0.6666667}, {"linear_per_km": -0.0666667, "constant": 2.6666667}]}]}|"ozone" density[0].width_km = 25000|given in metres? (that is 25 km)'
  'micrometres|{"bottom_radius_km": 6360, "top_radius_km": 6460, "channels": {"wavelengths_nm": [0.44, 0.55, 0.68]}, "constituents": [{"name": "air", "scattering": [0.03, 0.013, 0.006], "absorption": 0, "phase": {"kind": "rayleigh"}, "density": [{"exp_term": 1, "exp_scale_per_km": -0.125}]}]}|wavelengths_nm[0] = 0.44|given in micrometres? (0.44 um is 440 nm)'
)
for c in "${cases[@]}"; do
  IFS='|' read -r name json key meant <<<"$c"
  printf '%s\n' "$json" >"$tmp/$name.json"
  eval_atm "$tmp/$name.json"
  want=1
  [ "$name" = radius_metres ] && want=2   # both radii, each its own key
  n=$(grep -c 'warning' "$tmp/err")
  check "$name: exit $rc, optical depth written" "[ $rc -eq 0 ] && [ \$(wc -l <'$tmp/out') -eq 2 ]"
  check "$name: $n warning(s), want $want: $(head -c 300 "$tmp/err")" "[ $n -eq $want ]"
  check "$name: names the file, '$key' and '$meant'" \
    "grep -F -- '$name.json: ' '$tmp/err' | grep -F -- '$key' | grep -qF -- '$meant'"
done

# A scene's atmosphere: warned once per command, however many stages use it
# (sample: the tables; build: tables, fits, report, headers).
scene='"viewer_altitude_km": [0, 0], "view": "above_horizon", "sun_elevation_deg": [0, 90], "color": "rgb"'
printf '{"name": "deg", "atmosphere": "sun_degrees.json", %s, "quantities": ["transmittance"], "error_budget": {"transmittance_rmse": 1e-2}}\n' \
  "$scene" >"$tmp/scene.json"
"$BIN" sample --scene "$tmp/scene.json" --out "$tmp/tables" --resolution 32x8,6x12x6x4 --quiet 2>"$tmp/err"
rc=$?
check "sample --scene: exit $rc, tables written" "[ $rc -eq 0 ] && [ -s '$tmp/tables/tables.json' ]"
check "sample --scene: one warning ($(grep -c warning "$tmp/err"))" \
  "[ \$(grep -c warning '$tmp/err') -eq 1 ] && grep -q '^skyfit sample: warning: .*sun_angular_radius_rad = 0.27' '$tmp/err'"
"$BIN" build "$tmp/scene.json" --resolution 32x16,8x16x8x4 --no-views --samples 2000 --timing-points 2000 \
  --repetitions 1 --mlp-epochs 10,1 --quick --quiet --out "$tmp/build" >/dev/null 2>"$tmp/err"
rc=$?
check "build: exit $rc, report and headers written" "[ $rc -eq 0 ] && [ -s '$tmp/build/report.html' ] && [ -s '$tmp/build/sky.h' ]"
check "build: one warning ($(grep -c warning "$tmp/err"))" \
  "[ \$(grep -c warning '$tmp/err') -eq 1 ] && grep -q '^skyfit build: warning: .*sun_angular_radius_rad' '$tmp/err'"

# Real skies stay silent: the shipped files, and planets at the edges of the
# thresholds (Venus' near sun, Titan's deep haze, a Jupiter-sized planet, a
# 100 km world, a rising haze layer aloft, SPEC §10's 0.01 km and 100 km
# scale heights).
planet() {   # name bottom top sun_rad exp_scale
  printf '{"name": "%s", "bottom_radius_km": %s, "top_radius_km": %s, "sun_angular_radius_rad": %s, "constituents": [{"name": "air", "scattering": [0.001, 0.002, 0.004], "absorption": 0, "phase": {"kind": "rayleigh"}, "density": [{"exp_term": 1, "exp_scale_per_km": %s}]}, {"name": "haze", "scattering": 0.01, "absorption": 0.001, "phase": {"kind": "henyey_greenstein", "g": 0.7}, "density": [{"width_km": 30, "exp_term": 0.01, "exp_scale_per_km": 0.15}, {"exp_term": 90, "exp_scale_per_km": -0.15}]}]}\n' \
    "$@" >"$tmp/real_$1.json"
}
planet venus 6051.8 6151.8 0.0066 -0.0629
planet titan 2574.7 3174.7 0.000487 -0.025
planet jupiter 69911 70911 0.000899 -0.037
planet tiny 100 200 0.004675 -0.125
planet scale_0.01 6360 6460 0.004675 -100
planet scale_100 6360 6460 0.004675 -0.01
for f in "$SRC"/examples/atmospheres/*.json "$SRC"/tests/fuzz/corpus/atmosphere/*.json "$tmp"/real_*.json; do
  eval_atm "$f"
  check "$(basename "$f"): exit $rc, no warning $(head -c 300 "$tmp/err")" "[ $rc -eq 0 ] && [ ! -s '$tmp/err' ]"
done
"$BIN" sample --scene "$SRC/examples/scenes/mars.json" --out "$tmp/mars" --resolution 32x8,6x12x6x4 --quiet 2>"$tmp/err"
rc=$?
check "examples/scenes/mars.json: exit $rc, no warning $(head -c 300 "$tmp/err")" "[ $rc -eq 0 ] && [ ! -s '$tmp/err' ]"

[ $failures -eq 0 ] || { echo "$failures failure(s)"; exit 1; }
echo "all passed"
