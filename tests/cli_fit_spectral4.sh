#!/usr/bin/env bash
# skyfit fit spectral4: help, every input error exits 2 with a message
# naming the problem and writes nothing, and its cache kept under --cache-limit.
set -euo pipefail

BIN="${SKYFIT_BIN:?SKYFIT_BIN must name the skyfit binary}"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT

passed=0
failed=0
fail() { echo "FAIL: $*"; failed=$((failed + 1)); }
pass() { echo "ok    $*"; passed=$((passed + 1)); }

# expect_error NAME GREP_PATTERN ARGS...: exit 2, stderr matching, no W.json
expect_error() {
  local name=$1 pattern=$2
  shift 2
  local rc=0
  "$BIN" fit spectral4 "$@" >"$TMP/out" 2>"$TMP/err" || rc=$?
  if [[ $rc -ne 2 ]]; then fail "$name: exit $rc, want 2 ($(cat "$TMP/err"))"; return; fi
  if ! grep -q -- "$pattern" "$TMP/err"; then fail "$name: stderr '$(cat "$TMP/err")' lacks '$pattern'"; return; fi
  if [[ -e $TMP/w.json ]]; then fail "$name: wrote w.json"; return; fi
  pass "$name: $(head -1 "$TMP/err")"
}

if "$BIN" fit spectral4 --help | grep -q "usage: skyfit fit spectral4"; then pass "--help"; else fail "--help"; fi
if "$BIN" fit --help | grep -q "spectral4"; then pass "listed by skyfit fit --help"; else fail "not listed"; fi

expect_error "no --out" "--out W.json is required"
expect_error "unknown option" "unknown option '--colour'" --colour red --out "$TMP/w.json"
expect_error "bad orders" "--orders: expected 1..64" --orders 0 --out "$TMP/w.json"
expect_error "bad resolution" "--resolution" --resolution 3x3 --out "$TMP/w.json"
expect_error "missing scene" "missing.json" --scene "$TMP/missing.json" --out "$TMP/w.json"
cat >"$TMP/night.json" <<'JSON'
{"name": "night", "sun_elevation_deg": [-20, -5]}
JSON
# Errors of the scene's inputs name the file they came from, and leave no
# --cache folder behind (it had been made before the checks, empty).
expect_error "sun range misses -2..90" "$TMP/night.json: scene night: sun_elevation_deg \[-20, -5\] misses" --scene "$TMP/night.json" --out "$TMP/w.json" --cache "$TMP/cache"
cat >"$TMP/bad_atm.json" <<'JSON'
{"name": "bad", "bottom_radius_km": 6360, "top_radius_km": 6460, "channels": {"wavelengths_nm": [400, 500]},
 "constituents": [{"name": "rayleigh", "scattering": {"recipe": "rayleigh_bucholtz", "scale": -1}, "absorption": 0,
                   "phase": {"kind": "rayleigh"}, "density": [{"exp_term": 1}]}]}
JSON
expect_error "bad recipe" "constituents\[0\].scattering.scale: negative value" --atmosphere "$TMP/bad_atm.json" --out "$TMP/w.json"
cat >"$TMP/narrow.json" <<'JSON'
{"name": "narrow", "bottom_radius_km": 6360, "top_radius_km": 6460,
 "channels": {"wavelengths_nm": [400, 500, 600]},
 "constituents": [{"name": "rayleigh", "scattering": {"recipe": "rayleigh_bucholtz"}, "absorption": 0,
                   "phase": {"kind": "rayleigh"}, "density": [{"exp_term": 1, "exp_scale_per_km": -0.125}]}]}
JSON
expect_error "spectral atmosphere too narrow" "$TMP/narrow.json: atmosphere \"narrow\": channels.wavelengths_nm cover 400-600 nm; the spectral reference needs coefficients over 360-830 nm" --atmosphere "$TMP/narrow.json" --out "$TMP/w.json" --cache "$TMP/cache"
sed 's/"name": "narrow",/"name": "dark", "sun_irradiance": [0, 0, 0],/; s/\[400, 500, 600\]/[300, 600, 900]/' "$TMP/narrow.json" >"$TMP/dark.json"
expect_error "a sun the eye cannot see" "$TMP/dark.json: sun_irradiance: the sun has no luminance" --atmosphere "$TMP/dark.json" --out "$TMP/w.json" --cache "$TMP/cache"
# The fit is to the sky without aerosols (seed 003), every scatterer whose
# phase is not Rayleigh's left out: with none left that sky is black (the
# fit had exited 1, "no finite loss", after the tables; build too, with
# nothing but its cache written).
cat >"$TMP/iso.json" <<'JSON'
{"name": "iso", "bottom_radius_km": 6360, "top_radius_km": 6460,
 "constituents": [{"name": "haze", "scattering": [0.01, 0.02, 0.04], "absorption": 0,
   "phase": {"kind": "isotropic"}, "density": [{"exp_term": 1, "exp_scale_per_km": -0.125}]}]}
JSON
expect_error "no Rayleigh scatterer" "$TMP/iso.json: constituents: none scatters with the \"rayleigh\" phase" \
  --atmosphere "$TMP/iso.json" --out "$TMP/w.json" --cache "$TMP/cache"
printf '{"atmosphere": "iso.json", "viewer_altitude_km": [0, 2], "quantities": ["sky_radiance"], "color": "spectral4"}\n' \
  >"$TMP/iso_scene.json"
rc=0
"$BIN" build "$TMP/iso_scene.json" --quick --no-views --out "$TMP/iso_out" >/dev/null 2>"$TMP/err" || rc=$?
if [[ $rc -eq 2 && ! -e $TMP/iso_out ]] && grep -q 'none scatters with the "rayleigh" phase' "$TMP/err"; then
  pass "build of a spectral4 scene without a Rayleigh scatterer: exit 2 before the tables, nothing written"
else fail "build of a spectral4 scene without a Rayleigh scatterer: exit $rc, $(cat "$TMP/err")"; fi
if [[ -e $TMP/cache ]]; then fail "input errors left the --cache folder"; else pass "input errors leave no --cache folder"; fi

expect_error "bad cache limit" "--cache-limit: expected a size in MiB" --cache-limit 12x --out "$TMP/w.json"
# digits only: strtol had taken a blank and a sign
expect_error "cache limit with a sign" "--cache-limit: expected a size in MiB" --cache-limit +5 --out "$TMP/w.json"
expect_error "cache limit with a blank" "--cache-limit: expected a size in MiB" --cache-limit " 5" --out "$TMP/w.json"

# The default cache beside W.json is kept under --cache-limit after a
# successful run (util/cache_prune.h): entries unused the longest go first,
# this run's tables and files not named as entries stay. Small tables, two
# scattering orders: a few seconds a run.
small=(--resolution 32x8,8x16x8x4 --orders 2 --threads 2)
mkdir -p "$TMP/fit/skyfit-cache"
stale="$TMP/fit/skyfit-cache/transmittance-0123456789abcdef.exr"
head -c 100000 /dev/zero >"$stale"
touch -d "2020-01-01" "$stale"
echo "mine" >"$TMP/fit/skyfit-cache/notes.txt"
"$BIN" fit spectral4 "${small[@]}" --out "$TMP/fit/w.json" --cache-limit 0 >"$TMP/out" 2>"$TMP/err" || true
own=$(find "$TMP/fit/skyfit-cache" -name '*.exr' ! -name 'transmittance-0123456789abcdef.exr' | wc -l)
if [[ -s $TMP/fit/w.json && ! -e $stale && -e $TMP/fit/skyfit-cache/notes.txt && $own -ge 5 ]] &&
   grep -q "cache: removed 1 entries unused the longest" "$TMP/out"; then
  pass "--cache-limit 0: the stale entry removed, this run's $own tables and notes.txt kept"
else
  fail "--cache-limit 0: w.json $([[ -s $TMP/fit/w.json ]] && echo written || echo missing), stale $([[ -e $stale ]] && echo kept || echo removed), $own own tables; $(cat "$TMP/out" "$TMP/err" | tail -3)"
fi
"$BIN" fit spectral4 "${small[@]}" --out "$TMP/fit/w2.json" --cache-limit 0 >"$TMP/out" 2>"$TMP/err" || true
own2=$(find "$TMP/fit/skyfit-cache" -name '*.exr' | wc -l)
if grep -q "reference .* (cached)" "$TMP/out" && ! grep -q "cache: removed" "$TMP/out" && [[ $own2 -eq $own ]]; then
  pass "a second run hits the cache and removes nothing ($own2 tables)"
else
  fail "second run: $own2 tables (want $own); $(cat "$TMP/out" "$TMP/err" | tail -3)"
fi
head -c 100000 /dev/zero >"$stale"
touch -d "2020-01-01" "$stale"
"$BIN" fit spectral4 "${small[@]}" --out "$TMP/fit/w3.json" --cache-limit none >"$TMP/out" 2>"$TMP/err" || true
if [[ -s $TMP/fit/w3.json && -e $stale ]]; then pass "--cache-limit none keeps every entry"; else fail "--cache-limit none: $(tail -3 "$TMP/err")"; fi

# SPEC §8's training seed and epochs: nothing is drawn (seed 0); an epoch is
# a Nelder-Mead evaluation, a pass over every sample (the metrics' count).
if python3 -c "
import json, sys
w = json.load(open(sys.argv[1])); t = w['training']
assert t['seed'] == 0 and t['epochs'] == w['metrics']['evaluations'] >= 1, t" "$TMP/fit/w.json"; then
  pass "training: seed 0, epochs = the Nelder-Mead evaluations"
else fail "training seed/epochs"; fi

# The header states the weights' colour error against the full spectrum,
# the file's own figures (it had stated the fit's loss alone).
mkdir -p "$TMP/s4_gen"
if "$BIN" codegen --weights "$TMP/fit/w.json" --lang c --out "$TMP/s4_gen" --quiet &&
   python3 - "$TMP/fit/w.json" "$TMP/s4_gen/skyfit.h" <<'PY'
import json, re, sys
m = json.load(open(sys.argv[1]))["metrics"]["without_aerosols"]["spectral4"]
line = [l for l in open(sys.argv[2]) if "measured error" in l][0]
want = "mean %.3g, p99 %.3g, max %.3g" % (m["mean_delta_e2000"], m["p99_delta_e2000"], m["max_delta_e2000"])
assert "CIEDE2000 against the full spectrum" in line and want in line, (line, want)
PY
then pass "the spectral4 header states its CIEDE2000 against the full spectrum"
else fail "the spectral4 header's measured error"; fi

# A parameter the model does not take (it had been ignored): codegen refuses it.
python3 -c "
import json, sys
w = json.load(open(sys.argv[1])); w['params']['weight_nm'] = w['params']['weights_nm']
json.dump(w, open(sys.argv[2], 'w'))" "$TMP/fit/w.json" "$TMP/extra.json"
rc=0
"$BIN" codegen --weights "$TMP/extra.json" --lang c --out "$TMP/extra_gen" >"$TMP/out" 2>"$TMP/err" || rc=$?
if [[ $rc -eq 2 && ! -e $TMP/extra_gen ]] && grep -q "extra.json: params.weight_nm: not a parameter of this spectral4 model" "$TMP/err"; then
  pass "codegen refuses a parameter spectral4 does not take: $(cat "$TMP/err")"
else fail "codegen with params.weight_nm: exit $rc, $(cat "$TMP/err")"; fi

echo "$passed passed, $failed failed"
[[ $failed -eq 0 ]]
