#!/usr/bin/env bash
# Resource limits (issue 9): a request for tables larger than memory allows
# fails early — in well under a second of work, before any table is
# computed — with a clear message and exit 2, not by being killed; nothing
# is written. Cases: absurd --resolution values, a huge spectral atmosphere
# (128 wavelengths x 8 scattering constituents) through `skyfit sample
# --atmosphere`, `skyfit sample --scene` and `skyfit build`. The size the
# message states is checked against an independent lower bound (the bytes
# of the output tables alone), and the same atmosphere at a small
# resolution must succeed (the rejection is about size, not the input).
# When memory is smaller than the request although under skyfit's limit
# (simulated with ulimit -v), the run must still end with a message, not a
# signal. (cli_sample.sh covers malformed resolutions.)
set -u
BIN=${SKYFIT_BIN:?SKYFIT_BIN must name the skyfit binary}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
pass() { echo "ok   $*"; }
fail() { echo "FAIL $*"; failures=$((failures + 1)); }
now() { date +%s.%N; }
# Rejections must come before any computation; 10 s leaves room for a
# sanitized build on a loaded machine (the computation itself would take
# minutes and tens of GiB).
early=10

# expect_rejected NAME OUT_DIR ARGS...: exit 2, a message on stderr naming
# the memory needed, fast, no file written under OUT_DIR.
expect_rejected() {
  local name=$1 out=$2
  shift 2
  local t0 rc=0
  t0=$(now)
  "$BIN" "$@" --quiet >"$tmp/stdout" 2>"$tmp/err" || rc=$?
  local secs
  secs=$(awk -v a="$t0" -v b="$(now)" 'BEGIN { printf "%.2f", b - a }')
  local msg
  msg=$(head -c 400 "$tmp/err")
  local files=0
  [ -e "$out" ] && files=$(find "$out" -type f | wc -l)
  if [ $rc -eq 2 ] && [ -s "$tmp/err" ] && [ ! -s "$tmp/stdout" ] && [ "$files" -eq 0 ] &&
     awk -v s="$secs" -v e=$early 'BEGIN { exit !(s < e) }'; then
    pass "$name: exit 2 in $secs s (bound $early s), no file written: $msg"
  else
    fail "$name: exit $rc (want 2) in $secs s (bound $early s), $files files written (want 0): $msg"
  fi
}

# A spectral atmosphere at the largest channel count (SF_MAX_CHANNELS = 128)
# with the most constituents (SF_MAX_CONSTITUENTS = 8), all scattering.
wavelengths=$(awk 'BEGIN { for (i = 0; i < 128; ++i) printf "%s%g", i ? ", " : "", 380 + 3.5 * i }')
ones=$(awk 'BEGIN { for (i = 0; i < 128; ++i) printf "%s1e-3", i ? ", " : "" }')
{
  printf '{"name": "huge-spectral", "bottom_radius_km": 6360, "top_radius_km": 6460,\n'
  printf ' "channels": {"wavelengths_nm": [%s]}, "ground_albedo": 0.1, "sun_irradiance": 1,\n' "$wavelengths"
  printf ' "constituents": ['
  for k in 0 1 2 3 4 5 6 7; do
    [ $k -gt 0 ] && printf ', '
    printf '{"name": "c%d", "scattering": [%s], "absorption": 1e-5, "phase": {"kind": "henyey_greenstein", "g": 0.%d},' "$k" "$ones" "$k"
    printf ' "density": [{"exp_term": 1, "exp_scale_per_km": -0.%d5}]}' "$k"
  done
  printf ']}\n'
} >"$tmp/huge.json"
printf '{"name": "huge", "atmosphere": "huge.json"}\n' >"$tmp/huge-scene.json"

# 1. Absurd resolutions with the default atmosphere.
for res in 1000000x1000000,32x128x32x8 256x64,100000x100000x100000x100000 256x64,2000x2000x200x80 \
           256x64,4000x4000x4000x8 2147483647x2147483647,2x2x2x2 99999999999999999999x2,2x2x2x2; do
  expect_rejected "sample --resolution $res" "$tmp/out-res" sample --out "$tmp/out-res" --resolution "$res"
done
expect_rejected "build --resolution 256x64,2000x2000x200x80" "$tmp/out-build-res" build --out "$tmp/out-build-res" \
  --resolution 256x64,2000x2000x200x80 --no-views

# 2. The huge spectral atmosphere at the default resolution.
expect_rejected "sample --atmosphere huge.json" "$tmp/out-atm" sample --out "$tmp/out-atm" --atmosphere "$tmp/huge.json"
need=$(sed -n 's/.*needs about \([0-9.]*\) GiB.*limit \([0-9.]*\) GiB.*/\1 \2/p' "$tmp/err")
# Independent lower bound: the output tables alone, float32, 128 channels —
# transmittance 256x64, 8 single-scattering tables and the multiple-
# scattering table of 32x128x32x8 (irradiance and work buffers left out).
bound=$(awk 'BEGIN { printf "%.3f", 4 * 128 * (256 * 64 + 9 * 32 * 128 * 32 * 8) / 2^30 }')
if [ -n "$need" ] && awk -v n="${need% *}" -v l="${need#* }" -v b="$bound" 'BEGIN { exit !(n >= b && n > l) }'; then
  pass "stated need ${need% *} GiB >= independent lower bound $bound GiB, and over the stated limit ${need#* } GiB"
else
  fail "stated need/limit '${need:-none}' GiB: want need >= $bound GiB (output tables alone) and need > limit"
fi
expect_rejected "sample --scene huge-scene.json" "$tmp/out-scene" sample --out "$tmp/out-scene" --scene "$tmp/huge-scene.json"
expect_rejected "build huge-scene.json" "$tmp/out-build" build "$tmp/huge-scene.json" --out "$tmp/out-build" --no-views

# 3. Control: the same atmosphere at a small resolution is accepted.
rc=0
"$BIN" sample --out "$tmp/out-small" --atmosphere "$tmp/huge.json" --resolution 16x4,4x8x4x2 --orders 1 --quiet \
  2>"$tmp/err" || rc=$?
n=$(find "$tmp/out-small" -name '*.exr' 2>/dev/null | wc -l)
if [ $rc -eq 0 ] && [ "$n" -eq 11 ]; then
  pass "control: huge.json at 16x4,4x8x4x2 succeeds with $n tables (transmittance, 8 single, multiple, irradiance)"
else
  fail "control: huge.json at 16x4,4x8x4x2: exit $rc, $n tables (want 0 and 11): $(head -c 300 "$tmp/err")"
fi

# 4. Memory smaller than a request under skyfit's limit (over 2 GiB of
#    tables here), simulated by capping the address space at 1 GiB: the
#    run ends with a message, not a signal. Not with a sanitized binary
#    (AddressSanitizer reserves terabytes of address space up front).
if ldd "$BIN" 2>/dev/null | grep -q 'libasan\|libclang_rt.asan'; then
  echo "skip address-space cap: $BIN is built with AddressSanitizer"
else
  rc=0
  t0=$(now)
  ( ulimit -v 1048576; exec "$BIN" sample --out "$tmp/out-cap" --atmosphere "$tmp/huge.json" \
      --resolution 256x64,32x64x32x8 --orders 1 --quiet ) 2>"$tmp/err" || rc=$?
  secs=$(awk -v a="$t0" -v b="$(now)" 'BEGIN { printf "%.2f", b - a }')
  if [ $rc -ge 1 ] && [ $rc -le 2 ] && [ -s "$tmp/err" ] &&
     awk -v s="$secs" -v e=$early 'BEGIN { exit !(s < e) }'; then
    pass "1 GiB address space: exit $rc in $secs s with a message: $(head -c 300 "$tmp/err")"
  else
    fail "1 GiB address space: exit $rc (want 1 or 2, not a signal) in $secs s: $(head -c 300 "$tmp/err")"
  fi
fi

echo "$failures failed"
[ $failures -eq 0 ]
