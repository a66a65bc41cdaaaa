#!/bin/bash
# skyfit build / report end to end on small tables and views: metrics.json
# holds only finite figures, report.html renders in headless Chromium to a
# non-blank screenshot without script errors, and bad scenes exit 2.
set -uo pipefail
bin=${SKYFIT_BIN:?}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
small=(--resolution 32x16,8x16x8x4 --views 48x27 --samples 2000 --timing-points 20000 --repetitions 3 --quick --quiet)

"$bin" build "${small[@]}" --out "$tmp/out" > "$tmp/stdout" 2> "$tmp/stderr"
rc=$?
cat "$tmp/stdout"
[ $rc -eq 0 ] || { echo "FAIL build exited $rc"; cat "$tmp/stderr"; exit 1; }
grep -q "report: $tmp/out/report.html" "$tmp/stdout" || { echo "FAIL last lines do not name the report"; fail=1; }
grep -q "transmittance: chose" "$tmp/stdout" || { echo "FAIL no transmittance choice printed"; fail=1; }
for f in report.html report.md metrics.json; do [ -s "$tmp/out/$f" ] || { echo "FAIL missing $f"; fail=1; }; done
n_png=$(ls "$tmp/out/views/"*.png | wc -l); n_exr=$(ls "$tmp/out/views/"*-error.exr | wc -l)
echo "views: $n_png PNG, $n_exr EXR error maps"
[ "$n_png" -ge 12 ] && [ "$n_exr" -ge 5 ] || { echo "FAIL too few view files"; fail=1; }

# Every number in metrics.json is finite (null would mean a non-finite one).
python3 - "$tmp/out/metrics.json" <<'PY' || fail=1
import json, math, sys
doc = json.load(open(sys.argv[1]))
count = 0
def walk(v, path):
    global count
    if v is None:
        raise SystemExit(f"FAIL {path}: null (non-finite figure)")
    if isinstance(v, bool):
        return
    if isinstance(v, (int, float)):
        count += 1
        if not math.isfinite(v):
            raise SystemExit(f"FAIL {path}: {v}")
    elif isinstance(v, dict):
        for k, x in v.items(): walk(x, f"{path}.{k}")
    elif isinstance(v, list):
        for i, x in enumerate(v): walk(x, f"{path}[{i}]")
walk(doc, "$")
names = [m["name"] for m in doc["models"]]
assert "naive16" in names and "reference" in names, names
naive = [m for m in doc["models"] if m["name"] == "naive16"][0]
assert abs(naive["cost"]["ratio_to_naive16"] - 1.0) < 1e-12, naive["cost"]
print(f"metrics.json: {count} figures, all finite; models {names}")
PY

# Headless Chromium: a screenshot that is not blank, and no script errors.
if command -v chromium >/dev/null; then
  timeout 120 chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --user-data-dir="$tmp/chrome" \
    --enable-logging=stderr --v=0 --window-size=1200,1600 --screenshot="$tmp/shot.png" \
    "file://$tmp/out/report.html" > "$tmp/chrome.log" 2>&1
  [ -s "$tmp/shot.png" ] || { echo "FAIL no screenshot"; tail -5 "$tmp/chrome.log"; fail=1; }
  if grep -E "Uncaught|CONSOLE\(.*\).*[Ee]rror" "$tmp/chrome.log"; then echo "FAIL script errors"; fail=1; fi
  # Not blank: decode the PNG (zlib) and count distinct pixel rows / colours.
  python3 - "$tmp/shot.png" <<'PY' || fail=1
import struct, sys, zlib
data = open(sys.argv[1], "rb").read()
assert data[:8] == b"\x89PNG\r\n\x1a\n"
pos, idat, w, h = 8, b"", 0, 0
while pos < len(data):
    n, kind = struct.unpack(">I4s", data[pos:pos + 8])
    body = data[pos + 8:pos + 8 + n]
    if kind == b"IHDR":
        w, h, depth, ctype = struct.unpack(">IIBB", body[:10])
    elif kind == b"IDAT":
        idat += body
    pos += 12 + n
raw = zlib.decompress(idat)
stride = len(raw) // h
rows = set(raw[y * stride + 1:(y + 1) * stride] for y in range(h))
nonwhite = sum(1 for b in raw if b < 200)
print(f"screenshot {w}x{h}: {len(rows)} distinct rows, {nonwhite} dark bytes")
if len(rows) < 50 or nonwhite < 5000:
    raise SystemExit("FAIL the screenshot is blank")
PY
else
  echo "FAIL chromium is not installed (scripts/setup.sh installs it)"; fail=1
fi

# Bad input: exit 2 with a message, nothing written.
printf '{"atmosphere": "no-such-file.json"}' > "$tmp/missing.json"
printf '{"quantities": ["sky_radiance", "colour"]}' > "$tmp/quantity.json"
printf '{"viewer_altitude_km": [5, 1]}' > "$tmp/empty.json"
for s in missing quantity empty; do
  "$bin" build "$tmp/$s.json" --out "$tmp/bad-$s" --quiet > /dev/null 2> "$tmp/err"
  rc=$?
  echo "$s scene: exit $rc: $(head -1 "$tmp/err")"
  [ $rc -eq 2 ] && [ -s "$tmp/err" ] && [ ! -e "$tmp/bad-$s/report.html" ] || { echo "FAIL $s scene"; fail=1; }
done

# An impossible budget is not an error: the best available, said so.
printf '{"quantities": ["transmittance"], "error_budget": {"transmittance_rmse": 1e-12}}' > "$tmp/tight.json"
"$bin" build "$tmp/tight.json" "${small[@]}" --no-views --out "$tmp/tight" > "$tmp/tight.out" 2>&1
rc=$?
cat "$tmp/tight.out"
[ $rc -eq 0 ] && grep -q "NO model meets the budget" "$tmp/tight.out" && grep -q "NO MODEL MEETS THE BUDGET" "$tmp/tight/report.md" \
  || { echo "FAIL impossible budget"; fail=1; }
[ $fail -eq 0 ] && echo "all checks passed"
exit $fail
