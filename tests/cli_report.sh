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
for f in report.html report.md; do   # the segment columns and the sentence that says what they are
  grep -q "seg RMSE" "$tmp/out/$f" && grep -q "transmittance_segment, seed 000 eq. 43" "$tmp/out/$f" ||
    { echo "FAIL $f: no segment errors"; fail=1; }
done
n_png=$(ls "$tmp/out/views/"*.png | wc -l); n_exr=$(ls "$tmp/out/views/"*-error.exr | wc -l)
echo "views: $n_png PNG, $n_exr EXR error maps"
[ "$n_png" -ge 12 ] && [ "$n_exr" -ge 5 ] || { echo "FAIL too few view files"; fail=1; }

# A sky model of whole rays (any but the network) has no segment function:
# the report says skyfit_sky_radiance_segment is not emitted (it had said
# nothing, and the header simply lacked it).
python3 - "$tmp/out" <<'PY' || fail=1
import json, sys
sel = json.load(open(sys.argv[1] + "/metrics.json"))["selection"]["sky_radiance"]
has = "skyfit_sky_radiance_segment(" in open(sys.argv[1] + "/sky.h").read()
if sel["model"] != "mlp-scattering":
    assert not has and "gives whole rays only" in sel.get("emit_note", ""), f"FAIL {sel['model']}: {sel.get('emit_note')}"
    print(f"sky model {sel['model']}: no segment function, and the report says so")
else:
    assert has, "FAIL the sky network's segment function is missing"
PY

# The reference check (data/sky_table_check.h; 1000 points with --quick): its direct value at its
# worst point is eval single_scattering --phase's there, summed over the
# constituents (tests/test_tables.c checks the tables' side at entries).
python3 - "$tmp/out/metrics.json" "$bin" <<'PY' || fail=1
import json, subprocess, sys
c = json.load(open(sys.argv[1]))["reference_check"]
w = c["worst"]
assert c["points"] + c["points_outside"] == 1000 and 0 < c["rel_rmse"] < 1 and 0 < c["multiple_share"] < 1, c
row = "%.17g,%.17g,%.17g,%.17g" % (w["h_km"], w["mu"], w["mu_s"], w["nu"])
out = subprocess.run([sys.argv[2], "eval", "single_scattering", "--phase"], input="h_km,mu,mu_s,nu\n" + row + "\n",
                     capture_output=True, text=True, check=True).stdout.splitlines()
head, vals = out[0].split(","), [float(x) for x in out[1].split(",")]
direct = sum(v for k, v in zip(head, vals) if k.endswith("_" + w["channel"]))
if abs(direct - w["direct"]) > 1e-9 * abs(direct):
    raise SystemExit(f"FAIL reference check: direct {w['direct']} at its worst point, eval gives {direct}")
print(f"reference check: relative RMSE {c['rel_rmse']:.3g}; at its worst point direct {direct:.6g} as eval gives, "
      f"table {w['table']:.6g}")
PY

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
# Every fitted model of SPEC §7 that applies to the default scene is a candidate.
for want in ("sigmoid", "mlp-transmittance", "preetham", "hosek", "mlp-scattering"):
    assert want in names, f"FAIL {want} is not a candidate: {names}"
by = {m["name"]: m for m in doc["models"]}
# The baselines of SPEC §7.6 and §7.2: Galaj's spline, and the published
# Preetham and Hosek at their best turbidity and factors. Our fits of the
# same forms beat them (they are fitted to this reference).
for want in ("naive16", "chapman", "taylor", "flat", "spline", "preetham-published", "hosek-published"):
    assert want in names and by[want]["role"] == "baseline", f"FAIL baseline {want}: {names}"
    assert want.endswith("-published") or by[want]["cost"]["over"] == "the domain", by[want]["cost"]
# Segments (codegen/report.h): every model with a segment function (the
# transmittance baselines, the sigmoid, the networks) has its segment
# errors over the samples' rays; the lookup and the whole-ray skies have none.
samples = doc["options"]["domain_samples"]
for name, m in by.items():
    has = "segment_rmse" in m.get("errors", {})
    want = name in ("naive16", "chapman", "taylor", "flat", "spline", "sigmoid", "mlp-transmittance", "mlp-scattering")
    assert has == want, f"FAIL {name}: segment errors {'present' if has else 'missing'}"
    if has:
        e = m["errors"]
        assert 0 <= e["segment_rmse"] <= e["segment_max_abs"] and e["segment_non_finite_values"] == 0, e
        assert e["segment_values"] == samples * doc["channels"], e
assert by["mlp-scattering"]["errors"]["segment_transmittance"] == "mlp-transmittance", by["mlp-scattering"]["errors"]
print("segments: " + ", ".join(f"{n} {m['errors']['segment_rmse']:.3g}" for n, m in by.items()
                               if "segment_rmse" in m.get("errors", {})))
for form in ("preetham", "hosek"):
    ours, theirs = by[form]["errors"]["rmse"], by[form + "-published"]["errors"]["rmse"]
    assert ours < theirs, f"FAIL {form}: ours {ours} against the published {theirs}"
    print(f"{form}: RMSE {ours:.3g} fitted, {theirs:.3g} published ({by[form + '-published']['description'][:60]}...)")
for ground_only in ("preetham", "hosek", "preetham-published", "hosek-published"):
    m = by[ground_only]
    assert not m["valid_over_domain"] and m["errors"]["over"] == "its valid part of the domain", m
    # and timed there (on the whole scene's inputs it had run 15 % off)
    assert m["cost"]["over"] == "its valid part of the domain", m["cost"]
    d = m["errors"]["domain"]
    assert d["h_max_km"] == 0 and d["mu_s_min"] >= 0, d
    print(f"{ground_only}: rel RMSE {m['errors']['rel_rmse']:.3g} on the ground, sun up ({m['errors']['values']} values)")
    # Its views are compared on the sky alone (codegen/report_views.h):
    # only ground views with the sun up, on the pixels above the horizon
    # (the ground camera looks 3 deg up: a little over half the picture).
    views = {v["view"]: v for v in m["views"]}
    assert set(views) == {"ground-sunrise", "ground-noon"}, f"FAIL {ground_only} views {sorted(views)}"
    for v in views.values():
        assert 0.5 < v["compared_fraction"] < 0.65, f"FAIL {ground_only} {v}"
    print(f"  views {sorted(views)} on {views['ground-noon']['compared_fraction']:.3f} of the pixels")
# The sky network is valid for every sun, the reference only for the
# scene's (sun -10..90 deg): orbit-dawn is compared where the local sun is
# in the domain, the views of the ground and the plane whole.
views = {v["view"]: v for v in by["mlp-scattering"]["views"]}
assert len(views) == 12, f"FAIL mlp-scattering views {sorted(views)}"
assert 0.3 < views["orbit-dawn"]["compared_fraction"] < 0.8, views["orbit-dawn"]
for name in ("ground-noon", "ground-dawn", "plane-sunrise"):
    assert views[name]["compared_fraction"] == 1, views[name]
print(f"mlp-scattering: orbit-dawn compared on {views['orbit-dawn']['compared_fraction']:.3f} of its pixels")
# The Pareto front is of the models that can ship (the table lookup had
# pushed the selection off it): recomputed here from the figures.
for q in ("transmittance", "sky_radiance"):
    ms = [m for m in doc["models"] if m["quantity"] == q and m["role"] != "reference"]
    ship = [m for m in ms if m["can_ship"]]
    def dominated(a):
        ca, ea = a["cost"]["ratio_to_naive16"], a["budget_metric"]
        return any(b is not a and b["cost"]["ratio_to_naive16"] <= ca and b["budget_metric"] <= ea and
                   (b["cost"]["ratio_to_naive16"] < ca or b["budget_metric"] < ea) for b in ship)
    want = sorted(m["name"] for m in ship if not dominated(m))
    got = sorted(m["name"] for m in ms if m["on_pareto_front"])
    sel = [m["name"] for m in ms if m["selected"]]
    print(f"{q}: Pareto front {got}, selected {sel}")
    assert got == want and set(sel) <= set(got), f"FAIL {q} front {got}, want {want}, selected {sel}"
import os, xml.dom.minidom
for q in ("transmittance", "sky_radiance"):
    svg = xml.dom.minidom.parse(os.path.dirname(sys.argv[1]) + f"/plots/{q}-cost-error.svg")
    # the front is marked: a green line through its models, or a green ring
    # around one (a front of one model had not been marked)
    n_front = sum(1 for m in doc["models"] if m["quantity"] == q and m.get("on_pareto_front"))
    lines = [e for e in svg.getElementsByTagName("polyline") if e.getAttribute("stroke") == "#2a7"]
    rings = [e for e in svg.getElementsByTagName("circle") if e.getAttribute("stroke") == "#2a7"]
    marked = (len(lines) == 1 and len(lines[0].getAttribute("points").split()) == n_front) if n_front > 1 else len(rings) == n_front
    assert marked, f"FAIL {q}: front of {n_front} models, {len(lines)} green lines, {len(rings)} green rings"
PY
for w in sigmoid mlp-transmittance preetham hosek mlp-scattering; do
  [ -s "$tmp/out/weights/$w.json" ] || { echo "FAIL no weights file for $w"; fail=1; }
done

# A second run with nothing changed reuses the cache: tables, fits and
# timings; the report is byte-identical. It runs with --cache-limit 0
# (util/cache_prune.h): entries it did not use go (two planted, a day old),
# every one it used stays (made an hour old first: a hit marks them used),
# and files not named as entries stay.
cp "$tmp/out/metrics.json" "$tmp/metrics-first.json"
cp "$tmp/out/report.md" "$tmp/report-first.md"
entries() { (cd "$tmp/out/cache" && ls *-????????????????.exr fits/*-????????????????.json costs/*-????????????????.json) | sort; }
entries > "$tmp/entries-first"
echo "cache after the first run: $(wc -l < "$tmp/entries-first") entries"
(cd "$tmp/out/cache" && touch -d '1 hour ago' $(cat "$tmp/entries-first"))
echo stale > "$tmp/out/cache/single_rayleigh-0123456789abcdef.exr"
echo stale > "$tmp/out/cache/fits/hosek-0123456789abcdef.json"
echo keep > "$tmp/out/cache/notes.txt"
touch -d '1 day ago' "$tmp/out/cache/single_rayleigh-0123456789abcdef.exr" "$tmp/out/cache/fits/hosek-0123456789abcdef.json" \
  "$tmp/out/cache/notes.txt"
start=$(date +%s.%N)
"$bin" build "${small[@]}" --cache-limit 0 --out "$tmp/out" > "$tmp/stdout2" 2> "$tmp/stderr2" || { echo "FAIL rerun"; cat "$tmp/stderr2"; fail=1; }
grep "cache: removed" "$tmp/stdout2"
grep -q "cache: removed 2 entries" "$tmp/stdout2" || { echo "FAIL the rerun did not remove the 2 stale entries"; fail=1; }
entries | cmp -s - "$tmp/entries-first" || { echo "FAIL the rerun's cache entries are not the first run's"; entries | diff "$tmp/entries-first" - | head -5; fail=1; }
[ -f "$tmp/out/cache/notes.txt" ] || { echo "FAIL a file not named as an entry was removed"; fail=1; }
end=$(date +%s.%N)
echo "rerun: $(head -1 "$tmp/stdout2") (wall $(awk -v a="$start" -v b="$end" 'BEGIN {printf "%.2f", b - a}') s)"
grep -q "tables 5/5 from the cache" "$tmp/stdout2" || { echo "FAIL rerun did not take the tables from the cache"; fail=1; }
cmp -s "$tmp/metrics-first.json" "$tmp/out/metrics.json" || { echo "FAIL metrics.json differs on a rerun"; diff "$tmp/metrics-first.json" "$tmp/out/metrics.json" | head -5; fail=1; }
cmp -s "$tmp/report-first.md" "$tmp/out/report.md" || { echo "FAIL report.md differs on a rerun"; fail=1; }
# A fitter's note is part of the report: a sky network whose tables are
# too coarse to brightness-normalise says so, from the cache too (the
# rerun's report had lost the note, and with it byte-identity).
cat > "$tmp/raw-scene.json" <<'EOF'
{"viewer_altitude_km": [0, 0], "view": "above_horizon", "sun_elevation_deg": [0, 90], "quantities": ["sky_radiance"],
 "error_budget": {"sky_radiance_rel_rmse": 0.1}}
EOF
raw=(--resolution 64x16,8x32x16x8 --views 48x27 --timing-points 20000 --quick --quiet)
"$bin" build "$tmp/raw-scene.json" "${raw[@]}" --out "$tmp/raw" > /dev/null 2>&1 && cp "$tmp/raw/report.md" "$tmp/raw-first.md" &&
  cp "$tmp/raw/metrics.json" "$tmp/raw-first.json" && "$bin" build "$tmp/raw-scene.json" "${raw[@]}" --out "$tmp/raw" > /dev/null 2>&1 ||
  { echo "FAIL the raw-targets scene's builds"; fail=1; }
if grep -q "sky network trained on raw targets" "$tmp/raw-first.md" && cmp -s "$tmp/raw-first.md" "$tmp/raw/report.md" &&
   cmp -s "$tmp/raw-first.json" "$tmp/raw/metrics.json"; then
  echo "a fit's note (raw targets) is in the report of a rerun from the cache too, byte for byte"
else
  echo "FAIL a fit's note on a rerun from the cache: $(diff "$tmp/raw-first.md" "$tmp/raw/report.md" | head -5)"; fail=1
fi

# The ratios to the naive raymarch are of timings from one run (SPEC §12):
# with one model's timing gone from the cache, every model is timed again
# (a cached naive raymarch had stood beside a freshly timed model).
gone=$(ls "$tmp/out/cache/costs/"mlp-transmittance-*.json | head -1)
rm -f "$gone"
"$bin" build "${small[@]}" --out "$tmp/out" > "$tmp/stdout3" 2>&1 || { echo "FAIL rerun without one timing"; fail=1; }
python3 - "$tmp/out/cache/costs" <<'PY' || fail=1
import glob, json, sys
runs = {json.load(open(f)).get("run") for f in glob.glob(sys.argv[1] + "/*.json")}
print(f"timings after one was removed: {len(glob.glob(sys.argv[1] + '/*.json'))} entries from {len(runs)} run(s)")
assert len(runs) == 1 and None not in runs, f"FAIL the timings come from several runs: {runs}"
PY

# A cached fit is used only if it is a fit of this atmosphere over this
# domain: another scene's sigmoid, copied over the entry, had been shipped
# as it was. Now it is refitted, and the outputs are those of the fit.
cp "$tmp/out/sky.h" "$tmp/sky-before.h"
cp "$tmp/out/weights/sigmoid.json" "$tmp/sigmoid-before.json"
"$bin" fit sigmoid --scene "${SKYFIT_SOURCE_DIR:?}/examples/scenes/flight.json" --grid 12x24 --quiet --out "$tmp/other-sigmoid.json" &&
  cp "$tmp/other-sigmoid.json" "$(ls "$tmp/out/cache/fits/"sigmoid-*.json | head -1)" &&
  "$bin" build "${small[@]}" --out "$tmp/out" > "$tmp/stdout5" 2>&1 || { echo "FAIL the build over a foreign cached fit"; fail=1; }
grep -o "sigmoid: cached fit unusable, refitting: .*" "$tmp/out/report.md" | head -1
grep -q "sigmoid: cached fit unusable, refitting: .*a fit over another domain" "$tmp/out/report.md" &&
  cmp -s "$tmp/sky-before.h" "$tmp/out/sky.h" && cmp -s "$tmp/sigmoid-before.json" "$tmp/out/weights/sigmoid.json" ||
  { echo "FAIL a foreign cached fit was not refitted"; fail=1; }

# The fits and timings are keyed on the executable's bytes: a copy of it
# (a new modification time) reuses them, another executable refits (here
# the same one with a byte appended: its key changes, not its code). Its
# size and modification time had been the key.
n_fits() { ls "$tmp/out/cache/fits" "$tmp/out/cache/costs" | grep -c -- '-[0-9a-f]\{16\}\.json$'; }
before=$(n_fits)
cp "$bin" "$tmp/skyfit-copy" && touch -d '1 minute ago' "$tmp/skyfit-copy"
"$tmp/skyfit-copy" build "${small[@]}" --out "$tmp/out" > /dev/null 2>&1 || { echo "FAIL a copy's build"; fail=1; }
copied=$(n_fits)
printf 'x' >> "$tmp/skyfit-copy"
"$tmp/skyfit-copy" build "${small[@]}" --out "$tmp/out" > /dev/null 2>&1 || { echo "FAIL another executable's build"; fail=1; }
other=$(n_fits)
echo "fits and timings cached: $before; after a copy's build $copied; after another executable's $other"
[ "$copied" = "$before" ] && [ "$other" -gt "$before" ] || { echo "FAIL the cache's code identity"; fail=1; }

# A damaged cached table is said (SPEC §6: reported and recomputed) by
# build as by sample; build had recomputed it without a word.
loud=()
for a in "${small[@]}"; do [ "$a" = --quiet ] || loud+=("$a"); done
truncate -s 5000 "$(ls "$tmp/out/cache/"multiple-*.exr | head -1)"
"$bin" build "${loud[@]}" --no-views --out "$tmp/out" > /dev/null 2> "$tmp/stderr6" || { echo "FAIL the build over a damaged table"; fail=1; }
grep -o "cache file .*multiple-.* is corrupt: " "$tmp/stderr6" | head -1
grep -q "cache file .*multiple-.*is corrupt: .*; recomputing it" "$tmp/stderr6" || { echo "FAIL a damaged cached table went unsaid"; fail=1; }

# A cache whose fits folder cannot be made ends the build before any fit,
# exit 2 naming it, the published weights kept: every fit had "failed"
# and been skipped, the build had shipped other models, exited 0 and
# removed the weights files of the models it no longer had.
cp -a "$tmp/out/weights" "$tmp/weights-kept"
mv "$tmp/out/cache/fits" "$tmp/fits-saved" && echo "not a folder" > "$tmp/out/cache/fits"
rc=0
"$bin" build "${small[@]}" --out "$tmp/out" > "$tmp/stdout4" 2> "$tmp/stderr4" || rc=$?
echo "fits folder in the way: exit $rc: $(tail -1 "$tmp/stderr4")"
[ "$rc" = 2 ] && grep -q "$tmp/out/cache/fits" "$tmp/stderr4" || { echo "FAIL a fits folder that cannot be made"; fail=1; }
diff -r "$tmp/weights-kept" "$tmp/out/weights" > /dev/null || { echo "FAIL the published weights changed"; fail=1; }
rm -f "$tmp/out/cache/fits" && mv "$tmp/fits-saved" "$tmp/out/cache/fits"

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

# The example scenes (examples/scenes/): ground-only picks Preetham or Hosek;
# the dusty Mars-like atmosphere is retrained end to end (its sky network
# brightness-normalised by default, fit/output_norm.h); spectral4 fits the
# 4 wavelengths and beats plain RGB at 680/550/440 nm in ΔE2000.
tiny=(--resolution 32x16,8x16x8x4 --no-views --samples 2000 --timing-points 2000 --repetitions 1 --mlp-epochs 10,1 --quick --quiet)
src=${SKYFIT_SOURCE_DIR:?}
"$bin" build "$src/examples/scenes/ground.json" "${tiny[@]}" --mlp-normalise none --out "$tmp/ground" > "$tmp/ground.out" 2>&1
rc=$?
grep "chose" "$tmp/ground.out"
[ $rc -eq 0 ] && grep -Eq "sky_radiance: chose (preetham|hosek) \(meets the budget\)" "$tmp/ground.out" \
  || { echo "FAIL ground scene: Preetham/Hosek should win"; cat "$tmp/ground.out"; fail=1; }
# stable_sky_name LABEL DIR CALL: DIR/sky.h, with a call of
# skyfit_sky_radiance, compiles without warnings as C99 and C++17, and
# DIR/sky.glsl with glslangValidator; sky.h holds the line CALL (the
# selected model reached).
stable_sky_name() {
  local label=$1 dir=$2 call=$3
  printf '#include "sky.h"\nfloat g(void) { return skyfit_sky_radiance(0.0f, 0.5f, 0.7f, 0.6f).y; }\n' > "$dir/use.c"
  cc -std=c99 -Wall -Wextra -Werror -pedantic -I"$dir" -c "$dir/use.c" -o "$dir/use.o" &&
    g++ -std=c++17 -Wall -Wextra -Werror -pedantic -x c++ -I"$dir" -c "$dir/use.c" -o "$dir/use2.o" &&
    grep -Eq "$call" "$dir/sky.h" ||
    { echo "FAIL $label: skyfit_sky_radiance does not compile or does not call the selected model"; fail=1; }
  if command -v glslangValidator >/dev/null; then
    { printf '#version 450\nlayout(location = 0) out vec4 c;\n'; cat "$dir/sky.glsl";
      printf 'void main() { c = vec4(skyfit_sky_radiance(0.0, 0.5, 0.7, 0.6), 1.0); }\n'; } > "$dir/use.frag"
    glslangValidator "$dir/use.frag" > "$dir/glsl.log" 2>&1 ||
      { echo "FAIL $label: the GLSL with skyfit_sky_radiance does not compile"; cat "$dir/glsl.log"; fail=1; }
  else
    echo "FAIL glslangValidator is not installed (scripts/setup.sh installs it)"; fail=1
  fi
}
# The stable name of the selected ground model (f(mu, mu_s, nu)) takes and
# ignores h_km.
stable_sky_name "ground scene" "$tmp/ground" "return skyfit_(preetham|hosek)_sky_radiance\(mu, mu_s, nu\);"
# Its plots mark their fronts too (checked as above for the default scene),
# whatever their sizes: a front of one model had not been marked.
python3 - "$tmp/ground" <<'PY' || fail=1
import json, sys, xml.dom.minidom
d = sys.argv[1]
doc = json.load(open(d + "/metrics.json"))
for q in ("transmittance", "sky_radiance"):
    n_front = sum(1 for m in doc["models"] if m["quantity"] == q and m.get("on_pareto_front"))
    try:
        svg = xml.dom.minidom.parse(d + f"/plots/{q}-cost-error.svg")
    except FileNotFoundError:
        continue
    lines = [e for e in svg.getElementsByTagName("polyline") if e.getAttribute("stroke") == "#2a7"]
    rings = [e for e in svg.getElementsByTagName("circle") if e.getAttribute("stroke") == "#2a7"]
    marked = (len(lines) == 1 and len(lines[0].getAttribute("points").split()) == n_front) if n_front > 1 else len(rings) == n_front
    assert marked, f"FAIL ground scene {q}: front of {n_front} models, {len(lines)} green lines, {len(rings)} green rings"
    print(f"ground scene {q}: front of {n_front} marked")
PY
# A ground scene whose sun sets (-10 deg): Preetham and Hosek need the sun
# up, so the network is selected, and its stable name passes h_km on. The
# alias had followed the valid domain (ground only) instead of the model's
# code, and called skyfit_mlp_sky_radiance(mu, mu_s, nu): neither header
# compiled, and the build said nothing. The single-scattering skies are
# left out (--exclude): the budget here takes anything (the network gets 1
# epoch), and the flat sky, 1.0x the raymarch against the network's 0.6x,
# is the cheaper where timings shift (ASan) or tie (2000 points).
no_single=(--exclude naive-sky,raymarched-sky,flat-sky,schuler-sky)
mkdir -p "$tmp/dusk"
sed -e 's/"sun_elevation_deg": \[0, 90\]/"sun_elevation_deg": [-10, 90]/' \
  -e 's/"sky_radiance_rel_rmse": 0.1/"sky_radiance_rel_rmse": 1e6/' "$src/examples/scenes/ground.json" > "$tmp/dusk/scene.json"
grep -q '\[-10, 90\]' "$tmp/dusk/scene.json" || { echo "FAIL the dusk scene was not written"; fail=1; }
"$bin" build "$tmp/dusk/scene.json" "${tiny[@]}" "${no_single[@]}" --out "$tmp/dusk/out" > "$tmp/dusk.out" 2>&1 &&
  grep -q "sky_radiance: chose mlp-scattering" "$tmp/dusk.out" ||
  { echo "FAIL dusk ground scene: the network should be chosen"; cat "$tmp/dusk.out"; fail=1; }
stable_sky_name "dusk ground scene" "$tmp/dusk/out" "return skyfit_mlp_sky_radiance\(h_km, mu, mu_s, nu\);"
grep -q '"normalise":[[:space:]]*"none"' "$tmp/ground/weights/mlp-scattering.json" &&
  ! grep -q '"norm_coef"' "$tmp/ground/weights/mlp-scattering.json" ||
  { echo "FAIL ground scene: --mlp-normalise none still normalised the sky network"; fail=1; }
# The same scene's views: its reference tables hold the sky above the
# horizon alone (they had been extrapolated into a bright ground), so the
# ground views' reference pictures are black below it and every figure is
# over the sky (codegen/report_views.h). The default scene's pictures,
# copied in first, go: views/ shows this report's alone.
cp -r "$tmp/out/views" "$tmp/ground/"
"$bin" report "$src/examples/scenes/ground.json" --resolution 32x16,8x16x8x4 --views 48x27 --samples 2000 \
  --timing-points 2000 --repetitions 1 --mlp-epochs 10,1 --quick --quiet --out "$tmp/ground" > "$tmp/ground-report.out" 2>&1 ||
  { echo "FAIL ground scene report"; cat "$tmp/ground-report.out"; fail=1; }
python3 - "$tmp/ground" <<'PY' || fail=1
import json, struct, sys, zlib
def png_rows(path):
    data = open(path, "rb").read()
    pos, idat = 8, b""
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h = struct.unpack(">II", body[:8])
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw, stride, rows, prev = zlib.decompress(idat), 3 * w + 1, [], bytearray(3 * w)
    for y in range(h):   # undo the PNG filters (RGB, 8 bits: 3 bytes a pixel)
        f, line = raw[y * stride], bytearray(raw[y * stride + 1:(y + 1) * stride])
        for i in range(len(line)):
            a = line[i - 3] if i >= 3 else 0
            b, c = prev[i], prev[i - 3] if i >= 3 else 0
            p = a + b - c
            pred = [0, a, b, (a + b) // 2, a if abs(p - a) <= min(abs(p - b), abs(p - c)) else (b if abs(p - b) <= abs(p - c) else c)][f]
            line[i] = (line[i] + pred) & 255
        rows.append(bytes(line))
        prev = line
    return rows
doc = json.load(open(sys.argv[1] + "/metrics.json"))
ref = [m for m in doc["models"] if m["name"] == "reference" and m["quantity"] == "sky_radiance"][0]
for v in ref["views"]:
    if not v["view"].startswith("ground-"):
        continue
    rows = png_rows(sys.argv[1] + "/" + v["png"])
    print(f"ground scene {v['view']}: reference over {v['compared_fraction']:.3f} of the pixels; "
          f"bottom row max {max(rows[-1])}, top row max {max(rows[0])}")
    assert 0.4 < v["compared_fraction"] < 0.7 and max(rows[-1]) == 0 and max(rows[0]) > 0, f"FAIL {v}"
# The scene asks for sky radiance only: its transmittance figures are
# graded against no budget ("misses" had graded them against the default).
md = open(sys.argv[1] + "/report.md").read()
table = md[md.index("## Transmittance"):md.index("## Sky radiance")]
assert "not asked" in table and "misses" not in table and "meets" not in table, "FAIL transmittance graded"
named = set()
for m in doc["models"]:
    for v in m["views"]:
        named |= {v["png"], v.get("error_exr", v["png"])}
        if m["quantity"] == "sky_radiance" and v["view"].startswith("ground-"):
            assert v["compared_fraction"] < 0.7, f"FAIL {m['name']} {v}"
import os
present = {"views/" + f for f in os.listdir(sys.argv[1] + "/views")}
print(f"ground scene views/: {len(present)} files, {len(named)} named by metrics.json")
assert present == named, f"FAIL views/ holds files the report does not name: {sorted(present - named)[:5]}"
PY
"$bin" build "$src/examples/scenes/mars.json" "${tiny[@]}" --out "$tmp/mars" > "$tmp/mars.out" 2>&1
rc=$?
grep "chose" "$tmp/mars.out"
python3 - "$tmp/mars/metrics.json" <<'PY' || fail=1
import json, math, sys
doc = json.load(open(sys.argv[1]))
assert doc["atmosphere"]["name"] == "mars-dusty", doc["atmosphere"]
fitted = [m for m in doc["models"] if m["role"] == "fitted"]
names = sorted(m["name"] for m in fitted)
assert names == ["hosek", "mlp-scattering", "mlp-transmittance", "preetham", "sigmoid"], names
for m in fitted:
    assert all(math.isfinite(m["errors"][k]) for k in ("rmse", "max_abs", "rel_rmse")), m
w = json.load(open(sys.argv[1].replace("metrics.json", "weights/mlp-scattering.json")))
assert "norm_coef" in w["params"] and "norm_cap" in w["params"] and w["training"]["normalise"] == "brightness", w["training"]
# SPEC §8: every weights file's "training" has a seed and epochs; the
# least-squares fits draw nothing (seed 0) and count Levenberg-Marquardt
# iterations, the most of one problem (Ceres stops at 200, the sky forms'
# fit across elevations at the max_iterations they state): for the sky
# forms, at least the mean of the per-channel counts the file sums
for name in ("sigmoid", "preetham", "hosek"):
    fit = json.load(open(sys.argv[1].replace("metrics.json", f"weights/{name}.json")))
    t = fit["training"]
    cap = 200 if name == "sigmoid" else t["max_iterations"]
    assert t["seed"] == 0 and t["epochs"] == int(t["epochs"]) and 1 <= t["epochs"] <= cap, (name, t)
    if name != "sigmoid":
        channels = len(fit["params"]["coefficients"])
        assert t["global_iterations"] / channels <= t["epochs"] <= t["global_iterations"], (name, t)
print("mars: fitted " + ", ".join(f"{m['name']} (rel RMSE {m['errors']['rel_rmse']:.3g})" for m in fitted))
PY
[ $rc -eq 0 ] || { echo "FAIL mars build exited $rc"; cat "$tmp/mars.out"; fail=1; }
# --mlp-normalise-cap none: the brightness normalised, uncapped (as `fit
# mlp-scattering --normalise-cap none`); a bad cap exits 2, writing nothing.
# The same build's --mlp-loss-floor: the sky network trained on the relative
# loss of that floor, as its weights file says.
"$bin" build "$src/examples/scenes/mars.json" "${tiny[@]}" --mlp-normalise-cap none --mlp-loss-floor 0.01 \
  --out "$tmp/mars-nc" > /dev/null 2>&1 &&
  grep -q '"norm_coef"' "$tmp/mars-nc/weights/mlp-scattering.json" &&
  ! grep -q '"norm_cap"' "$tmp/mars-nc/weights/mlp-scattering.json" ||
  { echo "FAIL mars scene: --mlp-normalise-cap none: norm_coef missing or norm_cap present"; fail=1; }
python3 - "$tmp/mars-nc/weights/mlp-scattering.json" <<'PY' || fail=1
import json, sys
t = json.load(open(sys.argv[1]))["training"]
assert t["loss"] == "rel" and t["loss_floor"] == 0.01, t
PY
"$bin" build "$src/examples/scenes/mars.json" "${tiny[@]}" --mlp-loss-floor 2 --out "$tmp/mars-bad" 2> "$tmp/err"
rc=$?
[ $rc -eq 2 ] && grep -q -- "--mlp-loss-floor" "$tmp/err" && [ ! -e "$tmp/mars-bad" ] ||
  { echo "FAIL --mlp-loss-floor 2 should exit 2 naming the option and write nothing"; fail=1; }
"$bin" build "$src/examples/scenes/mars.json" "${tiny[@]}" --mlp-normalise-cap -1 --out "$tmp/mars-bad" 2> "$tmp/err"
rc=$?
echo "--mlp-normalise-cap -1: exit $rc: $(head -1 "$tmp/err")"
[ $rc -eq 2 ] && grep -q -- "--mlp-normalise-cap" "$tmp/err" && [ ! -e "$tmp/mars-bad" ] ||
  { echo "FAIL --mlp-normalise-cap -1 should exit 2 naming the option and write nothing"; fail=1; }
"$bin" build "$src/examples/scenes/spectral4.json" "${tiny[@]}" --out "$tmp/s4" > "$tmp/s4.out" 2>&1
rc=$?
[ $rc -eq 0 ] || { echo "FAIL spectral4 build exited $rc"; cat "$tmp/s4.out"; fail=1; }
python3 - "$tmp/s4/metrics.json" <<'PY' || fail=1
import json, sys
s4 = json.load(open(sys.argv[1]))["spectral4"]
fit, rgb = s4["without_aerosols"]["spectral4"], s4["without_aerosols"]["rgb_680_550_440"]
print(f"spectral4: {s4['wavelengths_nm']} nm; mean dE2000 {fit['mean_delta_e2000']:.3g} vs plain RGB {rgb['mean_delta_e2000']:.3g}")

assert fit["mean_delta_e2000"] < rgb["mean_delta_e2000"], s4
PY
grep -q "Colour: 4 wavelengths" "$tmp/s4/report.md" || { echo "FAIL no spectral4 section in the report"; fail=1; }
# Its weights file's domain holds the suns it was fitted on, -2..90 deg,
# for a scene whose suns go lower (it had copied the scene's -10).
sed 's/"sun_elevation_deg": \[-2, 90\]/"sun_elevation_deg": [-10, 90]/' "$src/examples/scenes/spectral4.json" > "$tmp/s4low.json"
"$bin" fit spectral4 --scene "$tmp/s4low.json" --resolution 32x8,6x16x6x4 --orders 2 --quiet --out "$tmp/s4low-w.json" ||
  { echo "FAIL fit spectral4 on sun -10..90"; fail=1; }
python3 - "$tmp/s4low.json" "$tmp/s4low-w.json" <<'PY' || fail=1
import json, math, sys
assert json.load(open(sys.argv[1]))["sun_elevation_deg"] == [-10, 90]
d = json.load(open(sys.argv[2]))["domain"]
print(f"spectral4 on sun -10..90 deg: weights domain mu_s {d['mu_s']}")
assert abs(d["mu_s"][0] - math.sin(math.radians(-2))) < 1e-12, f"FAIL spectral4 domain {d}"
PY
# The C header's comment lists its functions with the C types, arguments
# included (skyfit_vec4 radiance; it had listed GLSL's vec4).
mkdir -p "$tmp/s4c"
"$bin" codegen --weights "$tmp/s4low-w.json" --lang c --out "$tmp/s4c" --quiet &&
  grep -q "skyfit_vec3 skyfit_spectral4_to_linear_srgb(skyfit_vec4 radiance)" "$tmp/s4c/skyfit.h" &&
  ! grep -Eq '^ \*     .*[( ]vec[234] ' "$tmp/s4c/skyfit.h" ||
  { echo "FAIL the C header's function list: $(grep -m3 'spectral4_' "$tmp/s4c/skyfit.h")"; fail=1; }
# Its weights file is checked as an atmosphere is (SPEC §4): impossible
# physics exits 2 naming the key, nothing emitted (codegen had emitted them);
# so do matrices that are not the colour matching functions at the
# wavelengths times the weights, or whose sRGB is not the XYZ's.
for edit in "ground_albedo 0 7" "scattering 0 -1" "wavelengths_nm 0 -5" "sun_irradiance 2 -1" \
            "to_xyz 2 7" "to_linear_srgb 1 7" "weights_nm 3 1"; do
  read -r key index value <<<"$edit"
  python3 - "$tmp/s4/weights/spectral4.json" "$tmp/s4-bad.json" "$key" "$index" "$value" <<'PY'
import json, sys
w = json.load(open(sys.argv[1]))
p = w["params"][sys.argv[3]]
(p[0] if isinstance(p[0], list) else p)[int(sys.argv[4])] = float(sys.argv[5])
json.dump(w, open(sys.argv[2], "w"))
PY
  rm -rf "$tmp/s4-cg"
  "$bin" codegen --weights "$tmp/s4-bad.json" --lang both --out "$tmp/s4-cg" 2> "$tmp/err"
  rc=$?
  [ $rc -eq 2 ] && grep -q "params.$key" "$tmp/err" && [ -z "$(ls -A "$tmp/s4-cg" 2>/dev/null)" ] ||
    { echo "FAIL spectral4 weights with $key = $value: exit $rc: $(cat "$tmp/err")"; fail=1; }
done
# Matrices written to 7 significant digits (by hand or another tool) agree.
python3 - "$tmp/s4/weights/spectral4.json" "$tmp/s4-7.json" <<'PY'
import json, sys
w = json.load(open(sys.argv[1]))
for key in ("to_xyz", "to_linear_srgb"):
    w["params"][key] = [[float("%.7g" % v) for v in row] for row in w["params"][key]]
json.dump(w, open(sys.argv[2], "w"))
PY
rm -rf "$tmp/s4-cg" && mkdir "$tmp/s4-cg"
"$bin" codegen --weights "$tmp/s4-7.json" --lang both --out "$tmp/s4-cg" 2> "$tmp/err" ||
  { echo "FAIL spectral4 weights rounded to 7 digits: $(cat "$tmp/err")"; fail=1; }
# The headers ship the 4-wavelength model beside the selected sky model.
for f in "$tmp/s4/sky.h" "$tmp/s4/sky.glsl"; do
  grep -q "skyfit_spectral4_to_linear_srgb" "$f" || { echo "FAIL $f lacks the spectral4 functions"; fail=1; }
done

# A damaged cached spectral4 fit (valid JSON, matrices not the colour
# pipeline's) is refitted: codegen's check had first run on the staged
# copy, and every build exited 2 naming a staging folder long gone.
cp "$tmp/s4/sky.h" "$tmp/s4-sky-before.h"
python3 - "$(ls "$tmp/s4/cache/fits/"spectral4-*.json | head -1)" <<'PY'
import json, sys
w = json.load(open(sys.argv[1]))
w["params"]["to_linear_srgb"][0][0] *= 3
json.dump(w, open(sys.argv[1], "w"))
PY
"$bin" build "$src/examples/scenes/spectral4.json" "${tiny[@]}" --out "$tmp/s4" > "$tmp/s4-again.out" 2>&1
rc=$?
echo "damaged cached spectral4 fit: exit $rc, $(grep -o 'spectral4: cached fit unusable[^:]*' "$tmp/s4/report.md" | head -1)"
[ $rc -eq 0 ] && grep -q "spectral4: cached fit unusable, refitting: .*to_linear_srgb" "$tmp/s4/report.md" &&
  cmp -s "$tmp/s4-sky-before.h" "$tmp/s4/sky.h" || { echo "FAIL a damaged cached spectral4 fit: $(tail -2 "$tmp/s4-again.out")"; fail=1; }

# An atmosphere of wavelengths has no pictures (they are linear sRGB): 3 of
# them had been drawn as if 440 nm were red.
cat > "$tmp/spec3_atm.json" <<'EOF'
{"base": "default", "name": "spec3", "channels": {"wavelengths_nm": [440, 550, 680]},
 "ground_albedo": [0, 0, 0], "sun_irradiance": [1, 1, 1],
 "constituents": [
  {"name": "rayleigh", "scattering": [0.0331, 0.01356, 0.0058], "absorption": [0, 0, 0]},
  {"name": "mie", "scattering": [0.003996, 0.003996, 0.003996], "absorption": [0.000444, 0.000444, 0.000444]},
  {"name": "ozone", "scattering": [0, 0, 0], "absorption": [0.000085, 0.001881, 0.00065]}]}
EOF
printf '{"name": "spec3", "atmosphere": "spec3_atm.json", "quantities": ["transmittance"]}' > "$tmp/spec3.json"
"$bin" report "$tmp/spec3.json" --resolution 32x16,8x16x8x4 --views 48x27 --samples 2000 --timing-points 2000 \
  --repetitions 1 --mlp-epochs 10,1 --quick --quiet --out "$tmp/spec3" > "$tmp/spec3.out" 2>&1
rc=$?
n_views=$(ls "$tmp/spec3/views" 2>/dev/null | wc -l)
echo "3-wavelength atmosphere: exit $rc, $n_views view files; $(grep -o 'The standard views[^.]*' "$tmp/spec3/report.md")"
[ $rc -eq 0 ] && [ "$n_views" -eq 0 ] && grep -q "3 wavelengths" "$tmp/spec3/report.md" &&
  ! grep -q "Error maps" "$tmp/spec3/report.md" ||
  { echo "FAIL a 3-wavelength atmosphere's views"; cat "$tmp/spec3.out"; fail=1; }

# Five wavelengths: no model's code holds them (vec1..vec4), so the build
# emits none and says so, exit 0. Preetham and Hosek had been selected as
# emittable, and the build failed at code generation, exit 2, no report.
sed 's/"spec3", "channels": {"wavelengths_nm": \[440, 550, 680\]}/"spec5", "channels": {"wavelengths_nm": [440, 500, 550, 610, 680]}/;
     s/\[0, 0, 0\]/[0, 0, 0, 0, 0]/; s/\[1, 1, 1\]/[1, 1, 1, 1, 1]/;
     s/\[0.0331, 0.01356, 0.0058\]/[0.0331, 0.021, 0.01356, 0.009, 0.0058]/;
     s/\[0.003996, 0.003996, 0.003996\]/0.003996/; s/\[0.000444, 0.000444, 0.000444\]/0.000444/;
     s/\[0.000085, 0.001881, 0.00065\]/[0.000085, 0.001, 0.001881, 0.0012, 0.00065]/' \
  "$tmp/spec3_atm.json" > "$tmp/spec5_atm.json"
printf '{"atmosphere": "spec5_atm.json", "viewer_altitude_km": [0, 0], "view": "above_horizon", "sun_elevation_deg": [0, 90],
 "quantities": ["sky_radiance"], "error_budget": {"sky_radiance_rel_rmse": 10}}' > "$tmp/spec5.json"
"$bin" build "$tmp/spec5.json" "${tiny[@]}" --out "$tmp/spec5" > "$tmp/spec5.out" 2>&1
rc=$?
echo "5-wavelength sky: exit $rc; $(grep -o 'Not eligible: [^.]*' "$tmp/spec5/report.md" | head -1)"
[ $rc -eq 0 ] && grep -q "headers: none emitted" "$tmp/spec5.out" &&
  grep -q "preetham: it cannot be emitted as code; hosek: it cannot be emitted as code" "$tmp/spec5/report.md" ||
  { echo "FAIL a 5-wavelength sky"; cat "$tmp/spec5.out"; fail=1; }

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
for limit in -1 1.5 lots; do
  "$bin" build --cache-limit "$limit" --out "$tmp/bad-limit" --quiet > /dev/null 2> "$tmp/err"
  rc=$?
  echo "--cache-limit $limit: exit $rc: $(head -1 "$tmp/err")"
  [ $rc -eq 2 ] && grep -q -- "--cache-limit" "$tmp/err" && [ ! -e "$tmp/bad-limit" ] ||
    { echo "FAIL --cache-limit $limit should exit 2 naming the option and write nothing"; fail=1; }
done

# The scene's outputs, exactly as named (relative to the scene's folder),
# written as a pair; the model chosen is always one the build can emit (a
# loose budget on the ground picked Leenman's flat model, which had no
# emitter in the build: nothing was emitted, exit 0). A missing folder, a
# folder as the file, or one path for both files exits 2 before any
# fitting and leaves the previous outputs as they were.
mkdir -p "$tmp/named/ext"
cat > "$tmp/named/scene.json" <<'EOF'
{"viewer_altitude_km": [0, 0], "view": "above_horizon", "sun_elevation_deg": [0, 90], "quantities": ["transmittance"],
 "error_budget": {"transmittance_rmse": 1e-2}, "outputs": {"c": "ext/sky.hpp", "glsl": "ext/sky.frag"}}
EOF
"$bin" build "$tmp/named/scene.json" "${tiny[@]}" --out "$tmp/named/out" > "$tmp/named.out" 2>&1
rc=$?
grep -E "chose|headers" "$tmp/named.out"
[ $rc -eq 0 ] && [ -s "$tmp/named/ext/sky.hpp" ] && [ -s "$tmp/named/ext/sky.frag" ] && [ ! -e "$tmp/named/ext/sky.h" ] &&
  [ ! -e "$tmp/named/ext/sky.glsl" ] && [ ! -e "$tmp/named/out/sky.h" ] &&
  grep -Eq "SKYFIT_GENERATED_SKY_[0-9a-f]{16}_H" "$tmp/named/ext/sky.hpp" &&
  grep -Eq "SKYFIT_GENERATED_SKY_[0-9a-f]{16}_GLSL" "$tmp/named/ext/sky.frag" ||
  { echo "FAIL scene outputs ext/sky.hpp and ext/sky.frag not written as named"; cat "$tmp/named.out"; fail=1; }
python3 - "$tmp/named" <<'PY' || fail=1
import json, re, sys
d = sys.argv[1]
sel = json.load(open(f"{d}/out/metrics.json"))["selection"]["transmittance"]
chosen = sel["model"]
# the report names the headers from its folder, as its views (they had
# been named from where skyfit ran): outside it, absolute
import os
want = {"c_header": os.path.realpath(f"{d}/ext/sky.hpp"), "glsl": os.path.realpath(f"{d}/ext/sky.frag")}
assert all(sel[k] == v for k, v in want.items()), f"FAIL the report's header paths: {sel}, want {want}"
prefix = {"naive16": "naive", "mlp-transmittance": "mlp"}.get(chosen, chosen)
header = open(f"{d}/ext/sky.hpp").read()
assert re.search(rf"skyfit_{prefix}_transmittance\(", header), f"FAIL chose {chosen}: no skyfit_{prefix}_transmittance"
print(f"named outputs: chose {chosen}, emitted as skyfit_{prefix}_transmittance")
PY
# A flying scene's sky is the network; a loose transmittance budget selects
# another transmittance model. skyfit_sky_radiance_segment (eq. 44) takes
# the transmittance network's, which the build then emits beside the
# selection (it had been emitted only when the network was selected for
# transmittance too, and a renderer's call did not compile).
cat > "$tmp/seg-scene.json" <<'EOF'
{"viewer_altitude_km": [0, 10], "view": "all", "sun_elevation_deg": [0, 90], "quantities": ["sky_radiance", "transmittance"],
 "error_budget": {"transmittance_rmse": 0.5, "sky_radiance_rel_rmse": 10}}
EOF
"$bin" build "$tmp/seg-scene.json" "${tiny[@]}" "${no_single[@]}" --out "$tmp/seg" > "$tmp/seg.out" 2>&1 ||
  { echo "FAIL build of the segment scene"; cat "$tmp/seg.out"; fail=1; }
# --exclude: the models named are neither built nor measured, the report's
# notes say so; a name that is not a model a build can leave out exits 2
python3 - "$tmp/seg" <<'PY' || fail=1
import json, sys
names = [m["name"] for m in json.load(open(f"{sys.argv[1]}/metrics.json"))["models"]]
out = open(f"{sys.argv[1]}/report.md").read()
left = ["naive-sky", "raymarched-sky", "flat-sky", "schuler-sky"]
assert not set(left) & set(names) and "mlp-scattering" in names, f"FAIL --exclude: models measured: {names}"
assert all(f"{n}: left out (--exclude)" in out for n in left), f"FAIL --exclude: the build did not say so: {out}"
print("--exclude: the four single-scattering skies left out, and said so")
PY
for bad in naive16 reference flat-skies; do
  "$bin" build "$tmp/seg-scene.json" "${tiny[@]}" --exclude "$bad" --out "$tmp/seg-bad" > "$tmp/bad.out" 2>&1
  rc=$?
  if [ $rc -eq 2 ] && grep -q "exclude: '$bad' is not a model a build can leave out" "$tmp/bad.out" && [ ! -e "$tmp/seg-bad" ]; then
    echo "--exclude $bad: exit 2, nothing written"
  else echo "FAIL --exclude $bad: exit $rc: $(cat "$tmp/bad.out")"; fail=1; fi
done
grep "chose" "$tmp/seg.out"
python3 - "$tmp/seg" <<'PY' || fail=1
import json, sys
d = sys.argv[1]
sel = json.load(open(f"{d}/metrics.json"))["selection"]
t, s = sel["transmittance"]["model"], sel["sky_radiance"]["model"]
assert s == "mlp-scattering" and t != "mlp-transmittance", f"FAIL the scene should select the sky network and another transmittance model: {t}, {s}"
paths = [sel[q][k] for q in sel for k in ("c_header", "glsl")]
assert paths == ["sky.h", "sky.glsl"] * 2, f"FAIL the report's header paths, from its folder: {paths}"
# the weights files too (they had been named from where skyfit ran)
import os
weights = [m["weights"] for m in json.load(open(f"{d}/metrics.json"))["models"] if "weights" in m]
assert weights and all(w.startswith("weights/") and os.path.isfile(f"{d}/{w}") for w in weights), \
    f"FAIL the report's weights paths, from its folder: {weights}"
for f in ("sky.h", "sky.glsl"):
    text = open(f"{d}/{f}").read()
    assert "skyfit_sky_radiance_segment(" in text, f"FAIL {f}: no skyfit_sky_radiance_segment with {t} selected"
print(f"segment scene: chose {t} and {s}; skyfit_sky_radiance_segment emitted")
PY
printf '#include "sky.h"\nint main(void) {\n  skyfit_vec3 v = skyfit_sky_radiance_segment(1.0f, 0.3f, 0.5f, 0.2f, 10.0f);\n  skyfit_vec3 w = skyfit_sky_radiance(1.0f, 0.3f, 0.5f, 0.2f);\n  return !(v.x > 0.0f && v.x < w.x);\n}\n' > "$tmp/seg/main.c"
cc -std=c99 -Wall -Wextra -Werror -pedantic -I "$tmp/seg" "$tmp/seg/main.c" -o "$tmp/seg/main" -lm && "$tmp/seg/main" ||
  { echo "FAIL skyfit_sky_radiance_segment: does not compile, or the first 10 km are not part of the ray's radiance"; fail=1; }
# The build writes the errors it measured into each weights file
# (metrics.build_error), so a header that skyfit codegen makes from the
# sky network's file states the build header's figures (it had stated the
# training loss on brightness-normalised targets).
mkdir -p "$tmp/seg/codegen"
"$bin" codegen --weights "$tmp/seg/weights/mlp-scattering.json" --lang c --out "$tmp/seg/codegen" --quiet ||
  { echo "FAIL codegen from the build's sky network"; fail=1; }
python3 - "$tmp/seg" <<'PY' || fail=1
import json, re, sys
d = sys.argv[1]
for name in ("mlp-scattering", "mlp-transmittance"):
    e = json.load(open(f"{d}/weights/{name}.json"))["metrics"].get("build_error")
    assert e and e["values"] > 0 and e["rmse"] > 0, f"FAIL {name}.json: no metrics.build_error"
figures = r"RMSE ([0-9.e+-]+), max abs ([0-9.e+-]+), mean rel ([0-9.e+-]+), rel RMSE ([0-9.e+-]+) over (\d+)"
build = re.search(r"sky radiance: " + figures, open(f"{d}/sky.h").read())
codegen = re.search(r"measured error: " + figures + r" values of the scene's domain", open(f"{d}/codegen/skyfit.h").read())
assert build and codegen, "FAIL the measured-error lines of sky.h and of codegen's header"
assert build.groups() == codegen.groups(), f"FAIL codegen states {codegen.groups()}, the build {build.groups()}"
print(f"codegen from the build's weights states the build's error: RMSE {codegen.group(1)}")
PY
cc -std=c99 -Wall -Wextra -Werror -pedantic -fsyntax-only -x c "$tmp/named/ext/sky.hpp" ||
  { echo "FAIL ext/sky.hpp does not compile as C99"; fail=1; }
listing() { (cd "$tmp/named" && find out ext -type f ! -path "out/cache/*" -exec sha256sum {} + | sort -k2); }
listing > "$tmp/named-before"
for outputs in '{"c": "nodir/sky.h"}' '{"glsl": "nodir/sky.glsl"}' '{"c": "same.txt", "glsl": "same.txt"}' '{"c": "ext"}'; do
  sed "s|\"outputs\": {[^}]*}|\"outputs\": $outputs|" "$tmp/named/scene.json" > "$tmp/named/bad.json"
  "$bin" build "$tmp/named/bad.json" "${tiny[@]}" --out "$tmp/named/out" > "$tmp/named-bad.out" 2> "$tmp/err"
  rc=$?
  echo "outputs $outputs: exit $rc: $(head -1 "$tmp/err")"
  listing > "$tmp/named-after"
  # the message names the scene's file and key (a missing folder's had named
  # neither, then the key alone)
  [ $rc -eq 2 ] && ! grep -q "chose" "$tmp/named-bad.out" && cmp -s "$tmp/named-before" "$tmp/named-after" &&
    grep -qF "$tmp/named/bad.json: the scene's outputs" "$tmp/err" ||
    { echo "FAIL outputs $outputs: should exit 2 before fitting naming the key, the previous outputs untouched"; fail=1; }
done
# Into a new folder: refused before anything is written (it had left
# DIR/cache and DIR/weights behind).
sed "s|\"outputs\": {[^}]*}|\"outputs\": {\"c\": \"nodir/sky.h\"}|" "$tmp/named/scene.json" > "$tmp/named/bad.json"
"$bin" build "$tmp/named/bad.json" "${tiny[@]}" --out "$tmp/named/fresh" > /dev/null 2>&1
rc=$?
[ $rc -eq 2 ] && [ ! -e "$tmp/named/fresh" ] ||
  { echo "FAIL outputs in a missing folder, --out a new folder: exit $rc, $(ls -R "$tmp/named/fresh" 2>&1 | head -3)"; fail=1; }

# An impossible budget is not an error: the best available, said so.
printf '{"quantities": ["transmittance"], "error_budget": {"transmittance_rmse": 1e-12}}' > "$tmp/tight.json"
"$bin" build "$tmp/tight.json" "${small[@]}" --no-views --out "$tmp/tight" > "$tmp/tight.out" 2>&1
rc=$?
cat "$tmp/tight.out"
[ $rc -eq 0 ] && grep -q "NO model meets the budget" "$tmp/tight.out" && grep -q "NO MODEL MEETS THE BUDGET" "$tmp/tight/report.md" \
  || { echo "FAIL impossible budget"; fail=1; }
# --quick trains one network per quantity; --mlp-restarts 3 trains the
# seed's restarts 2 and 3 while the budget is missed, each a candidate of
# its own on the same data, and the best available is still the one emitted.
grep -q "mlp-transmittance-2" "$tmp/tight/metrics.json" && { echo "FAIL --quick trained a restart"; fail=1; }
"$bin" build "$tmp/tight.json" "${small[@]}" --no-views --mlp-restarts 3 --out "$tmp/tight" > "$tmp/tight3.out" 2>&1
rc=$?
grep "chose" "$tmp/tight3.out"
[ $rc -eq 0 ] || { echo "FAIL --mlp-restarts 3 build exited $rc"; cat "$tmp/tight3.out"; fail=1; }
python3 - "$tmp/tight" <<'PY' || fail=1
import json, sys
out = sys.argv[1]
doc = json.load(open(f"{out}/metrics.json"))
nets = ["mlp-transmittance", "mlp-transmittance-2", "mlp-transmittance-3"]
by = {m["name"]: m for m in doc["models"]}
assert all(n in by for n in nets), f"FAIL restarts missing: {sorted(by)}"
sel = doc["selection"]["transmittance"]
fitted = [m for m in doc["models"] if m["quantity"] == "transmittance" and m["role"] in ("fitted", "baseline")]
best = min(fitted, key=lambda m: m["errors"]["rmse"])
assert sel["model"] == best["name"], f"FAIL chose {sel['model']}, smallest RMSE is {best['name']}"
w = [json.load(open(f"{out}/weights/{n}.json")) for n in nets]
for k, x in enumerate(w):
    assert x["training"].get("restart", 0) == k, (nets[k], x["training"])
    assert x["training"]["seed"] == w[0]["training"]["seed"]
    assert x["training"]["training_samples"] == w[0]["training"]["training_samples"]
    assert x["training"]["validation_samples"] == w[0]["training"]["validation_samples"]
assert w[0]["params"] != w[1]["params"] and w[1]["params"] != w[2]["params"], "FAIL the restarts are the same network"
rmse = [by[n]["errors"]["rmse"] for n in nets]
assert len(set(rmse)) == 3, rmse
assert "trained restart 3 of the seed's network (mlp-transmittance-3)" in doc["notes"], doc["notes"]
print("restarts: RMSE " + ", ".join(f"{n} {r:.4g}" for n, r in zip(nets, rmse)) + f"; chose {sel['model']}")
PY
# The next run there (one network) removes the restarts' weights files the
# last one left (fit/build_stale_weights.h), and nothing else.
echo '{}' > "$tmp/tight/weights/notes.json"
"$bin" build "$tmp/tight.json" "${small[@]}" --no-views --out "$tmp/tight" > "$tmp/tight1.out" 2>&1
rc=$?
"$bin" build "$tmp/tight.json" "${small[@]}" --no-views --out "$tmp/tight" > "$tmp/tight2.out" 2>&1
rc2=$?
grep "weights: removed" "$tmp/tight1.out"
echo "left in weights/: $(ls "$tmp/tight/weights" | tr '\n' ' ')"
[ $rc -eq 0 ] && [ $rc2 -eq 0 ] && grep -q "weights: removed 2 file(s)" "$tmp/tight1.out" &&
  ! grep -q "weights: removed" "$tmp/tight2.out" &&
  [ ! -e "$tmp/tight/weights/mlp-transmittance-2.json" ] && [ ! -e "$tmp/tight/weights/mlp-transmittance-3.json" ] &&
  [ -s "$tmp/tight/weights/mlp-transmittance.json" ] && [ -s "$tmp/tight/weights/sigmoid.json" ] &&
  [ -s "$tmp/tight/weights/notes.json" ] ||
  { echo "FAIL stale restart weights not removed, or too much removed"; cat "$tmp/tight1.out"; fail=1; }
"$bin" build "$tmp/tight.json" --mlp-restarts 0 --out "$tmp/bad-restarts" --quiet > /dev/null 2> "$tmp/err"
rc=$?
echo "--mlp-restarts 0: exit $rc: $(head -1 "$tmp/err")"
[ $rc -eq 2 ] && grep -q -- "--mlp-restarts" "$tmp/err" && [ ! -e "$tmp/bad-restarts" ] ||
  { echo "FAIL --mlp-restarts 0 should exit 2 naming the option and write nothing"; fail=1; }
# Without --quick or --mlp-restarts a build trains restarts (up to 3
# networks) only while its networks miss the budget by at most the seeds'
# spread (3x, SF_BUILD_RESTART_MAX_MISS): none for 1e-12, and a note says
# so; for half the first network's RMSE, the restarts.
nq=(--resolution 32x16,8x16x8x4 --no-views --samples 2000 --timing-points 20000 --repetitions 3 --quiet)
"$bin" build "$tmp/tight.json" "${nq[@]}" --out "$tmp/far" > "$tmp/far.out" 2>&1 ||
  { echo "FAIL default build with an impossible budget exited non-zero"; cat "$tmp/far.out"; fail=1; }
python3 - "$tmp" <<'PY' || fail=1
import json, sys
t = sys.argv[1]
doc = json.load(open(f"{t}/far/metrics.json"))
names = [m["name"] for m in doc["models"]]
assert "mlp-transmittance" in names and "mlp-transmittance-2" not in names, f"FAIL far miss: {names}"
assert "no restart trained" in doc["notes"] and "--mlp-restarts N trains them anyway" in doc["notes"], doc["notes"]
r = next(m for m in doc["models"] if m["name"] == "mlp-transmittance")["errors"]["rmse"]
json.dump({"quantities": ["transmittance"], "error_budget": {"transmittance_rmse": r / 2}}, open(f"{t}/near.json", "w"))
print(f"budget 1e-12: no restart trained; the network's RMSE {r:.4g}, so the next budget is {r / 2:.4g}")
PY
"$bin" build "$tmp/near.json" "${nq[@]}" --out "$tmp/far" > "$tmp/near.out" 2>&1 ||
  { echo "FAIL default build with a near budget exited non-zero"; cat "$tmp/near.out"; fail=1; }
python3 - "$tmp/far" <<'PY' || fail=1
import json, sys
doc = json.load(open(f"{sys.argv[1]}/metrics.json"))
by = {m["name"]: m for m in doc["models"]}
assert "mlp-transmittance-2" in by, f"FAIL near miss trained no restart: {sorted(by)}"
assert "trained restart 2 of the seed's network" in doc["notes"] and "no restart trained" not in doc["notes"], doc["notes"]
met = doc["selection"]["transmittance"]["meets_budget"]
assert met or "mlp-transmittance-3" in by, f"FAIL budget still missed after restart 2 and no restart 3: {sorted(by)}"
print("budget RMSE/2: restarts " + ", ".join(f"{n} {by[n]['errors']['rmse']:.4g}" for n in sorted(by) if n.startswith("mlp-")))
PY
# Headers that would replace an input or a file the build writes itself
# are refused before any work, exit 2, the inputs untouched: they had
# overwritten the scene (exit 0), or been lost under the report; a header
# deeper in a folder the build replaces whole (out/views/new/deeper/) had
# been accepted, the check looking at its own folder only; a header named
# as one of those folders itself (out/views) had been written, and the run
# then refused to publish, exit 2, with the old report beside the new header.
mkdir -p "$tmp/clash"
cp "$src/examples/scenes/ground.json" "$tmp/clash/scene.json"
cp "$tmp/clash/scene.json" "$tmp/clash/scene.orig"
printf '{"base": "default"}\n' > "$tmp/clash/air.json"
sed 's/"view"/"atmosphere": "air.json", "outputs": {"c": "air.json", "glsl": "sky.glsl"}, "view"/' \
  "$tmp/clash/scene.json" > "$tmp/clash/scene-air.json"
for args in "scene.json --header-c scene.json" "scene.json --header-glsl ./scene.json" \
            "scene.json --header-c out/report.md" "scene.json --header-glsl out/metrics.json" \
            "scene.json --header-c out/weights/sky.h" "scene.json --header-c out/x.h --header-glsl ./out//x.h" \
            "scene.json --header-c $tmp/clash/out/report.md" "scene.json --header-c out/../out/metrics.json" \
            "scene.json --header-glsl ../clash/scene.json" "scene-air.json" \
            "scene.json --header-c out/views/new/deeper/sky.h" "scene.json --header-glsl out/cache/x/../y/sky.glsl" \
            "scene.json --header-glsl out/views" "scene.json --header-c out/plots/" "scene.json --header-c ./out/cache" \
            "scene.json --header-glsl out/x/../weights" "scene.json --header-c ." "scene.json --header-glsl /tmp"; do
  read -r -a a <<<"$args"
  (cd "$tmp/clash" && "$bin" build "${a[@]}" "${tiny[@]}" --out out > /dev/null 2> err)
  rc=$?
  [ $rc -eq 2 ] && grep -Eq "give another path|is a folder; give the header's file path" "$tmp/clash/err" && [ ! -e "$tmp/clash/out" ] &&
    cmp -s "$tmp/clash/scene.json" "$tmp/clash/scene.orig" && grep -q base "$tmp/clash/air.json" ||
    { echo "FAIL build $args: exit $rc, or something written"; cat "$tmp/clash/err"; fail=1; }
done
# An atmosphere that only absorbs (ozone alone) has a black sky: the build
# says so, for the sky models and on its summary line, instead of "the
# tables were not made" (they were); each skipped baseline is named; the
# reference check names no worst point (it had printed "channel .").
mkdir -p "$tmp/black"
cat > "$tmp/black/atmosphere.json" <<'EOF'
{"name": "absorber-only", "bottom_radius_km": 6360, "top_radius_km": 6460, "channels": "rgb",
 "constituents": [{"name": "ozone", "scattering": [0, 0, 0], "absorption": [0.650e-3, 1.881e-3, 0.085e-3],
   "density": [{"width_km": 25, "linear_per_km": 0.0666667, "constant": -0.6666667},
               {"width_km": 0, "linear_per_km": -0.0666667, "constant": 2.6666667}]}]}
EOF
cat > "$tmp/black/scene.json" <<'EOF'
{"name": "black-sky", "atmosphere": "atmosphere.json", "viewer_altitude_km": [0, 15], "view": "all",
 "sun_elevation_deg": [-10, 90], "quantities": ["sky_radiance", "transmittance"], "color": "rgb",
 "error_budget": {"transmittance_rmse": 1e-2, "sky_radiance_rel_rmse": 0.1}}
EOF
loud=()
for a in "${tiny[@]}"; do [ "$a" = --quiet ] || loud+=("$a"); done
"$bin" build "$tmp/black/scene.json" "${loud[@]}" --out "$tmp/black/out" > "$tmp/black.out" 2>&1 ||
  { echo "FAIL black-sky build exited non-zero"; cat "$tmp/black.out"; fail=1; }
grep -q "sky_radiance: no model available (no constituent of the atmosphere scatters light: its sky is black)" "$tmp/black.out" &&
  [ "$(grep -c "not fitted: no constituent of absorber-only scatters light" "$tmp/black.out")" -eq 5 ] &&
  ! grep -q "which this build has not made" "$tmp/black.out" &&
  grep -q "baseline skipped: chapman (" "$tmp/black.out" && grep -q "baseline skipped: spline (" "$tmp/black.out" &&
  grep -q "Reference check: .*equal at every point" "$tmp/black/out/report.md" &&
  ! grep -q "channel \." "$tmp/black/out/report.md" ||
  { echo "FAIL black-sky build: its messages"; cat "$tmp/black.out"; grep "Reference check" "$tmp/black/out/report.md"; fail=1; }
[ $fail -eq 0 ] && echo "all checks passed"
exit $fail
