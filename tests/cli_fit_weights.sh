#!/bin/bash
# skyfit fit sigmoid|preetham|hosek: weights files (SPEC §8) are written and
# validated (--check), bad ones (wrong shape, non-finite number, atmosphere
# hash mismatch, wrong model) exit 2 with a message naming the file and key;
# --samples refits the published Hosek / Preetham skies (computed here in
# Python from the data notes) and prints the coefficients A..I / A..E.
set -u
bin=${SKYFIT_BIN:?}
src=${SKYFIT_SOURCE_DIR:?}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
expect() {  # expect CODE DESCRIPTION PATTERN -- command...
  local want=$1 what=$2 pattern=$3
  shift 4
  "$@" >"$tmp/out" 2>"$tmp/err"
  local got=$?
  if [ "$got" = "$want" ] && grep -q -- "$pattern" "$tmp/out" "$tmp/err"; then
    echo "ok   $what (exit $got): $(head -c 200 "$tmp/err" | tr '\n' ' ')"
  else
    echo "FAIL $what: exit $got, want $want, pattern '$pattern'"; cat "$tmp/err"; fail=1
  fi
}

expect 0 "sigmoid fit" "wrote" -- "$bin" fit sigmoid --grid 12x24 --out "$tmp/s.json"
# SIGTERM while `fit preetham --tables T` writes a table (polled for its
# temporary): the command ends by the signal and leaves no temporary in T
# (cli/interrupt_cleanup.h: only sample and build had cleaned up; one had
# stayed in T for good, under a cache key no later run writes).
source "$(dirname "$0")/lib/term_while_writing.sh"
read -r rc left < <(term_while_writing "$tmp/term" "$bin" fit preetham --tables "$tmp/term" \
  --resolution 64x16,16x64x16x8 --elevations 6 --grid 8x8 --out "$tmp/term-w.json" --quiet)
if { [ $rc -eq 143 ] || [ $rc -eq 0 ]; } && [ "$left" -eq 0 ]; then
  echo "ok   SIGTERM while fit preetham writes a table: exit $rc (143, or 0 had it finished), no temporary left"
else
  echo "FAIL SIGTERM while fit preetham writes a table: exit $rc, $left temporaries left"; fail=1
fi

# --out is checked before any work: an input file of the run (the
# atmosphere, the scene, the scene's atmosphere, the training data) is
# refused and stays as it was (it had been replaced by the weights), and
# an unwritable path fails at once (hosek had fitted for 35 s first).
cp "$src/examples/atmospheres/mars_dusty.json" "$tmp/a.json"
cp "$tmp/a.json" "$tmp/a0.json"
printf '{"atmosphere": "a.json", "viewer_altitude_km": [0, 0], "sun_elevation_deg": [0, 90]}\n' >"$tmp/sc.json"
printf 'x,y,t\n0,0,1\n1,1,0.5\n0.5,0.2,0.7\n' >"$tmp/t.csv"
cp "$tmp/t.csv" "$tmp/t0.csv"
small=(--resolution 32x16,4x8x4x4 --quiet)
expect 2 "sigmoid --out = --atmosphere" "would overwrite" -- "$bin" fit sigmoid --grid 8x16 --atmosphere "$tmp/a.json" --out "$tmp/a.json"
expect 2 "hosek --out = the scene's atmosphere" "would overwrite" -- "$bin" fit hosek --scene "$tmp/sc.json" --out "$tmp/a.json" "${small[@]}"
expect 2 "preetham --out = --scene" "would overwrite" -- "$bin" fit preetham --scene "$tmp/sc.json" --out "$tmp/sc.json" "${small[@]}"
expect 2 "spectral4 --out = --atmosphere" "would overwrite" -- "$bin" fit spectral4 --atmosphere "$tmp/a.json" --out "$tmp/a.json" "${small[@]}"
expect 2 "mlp-transmittance --dump-dataset = --atmosphere" "would overwrite" -- "$bin" fit mlp-transmittance --atmosphere "$tmp/a.json" --dump-dataset "$tmp/a.json" "${small[@]}"
expect 2 "mlp-scattering --out = the scene's atmosphere" "would overwrite" -- "$bin" fit mlp-scattering --scene "$tmp/sc.json" --out "$tmp/a.json" "${small[@]}"
expect 2 "mlp-transmittance --out ./D = --dump-dataset D, neither there yet" "would overwrite" -- bash -c "cd '$tmp' && '$bin' fit mlp-transmittance --dump-dataset new.csv --out ./new.csv ${small[*]}"
expect 2 "fit mlp --out = --data" "would overwrite" -- "$bin" fit mlp --data "$tmp/t.csv" --inputs 2 --layers 2,4,1 --epochs 2 --out "$tmp/t.csv"
cmp -s "$tmp/a.json" "$tmp/a0.json" && cmp -s "$tmp/t.csv" "$tmp/t0.csv" && cmp -s "$tmp/sc.json" <(printf '{"atmosphere": "a.json", "viewer_altitude_km": [0, 0], "sun_elevation_deg": [0, 90]}\n') ||
  { echo "FAIL an input file was changed"; fail=1; }
# A single sun elevation is refused before the tables, naming the scene and
# its key (the fit had said "sun elevation range [30, 30]" after them).
printf '{"viewer_altitude_km": [0, 0], "sun_elevation_deg": [30, 30]}\n' >"$tmp/one-sun.json"
expect 2 "hosek, a single sun elevation" "one-sun.json: sun_elevation_deg: \[30, 30\] is a single elevation" -- \
  "$bin" fit hosek --scene "$tmp/one-sun.json" --out "$tmp/one-sun-w.json" "${small[@]}"
start=$(date +%s%N)
expect 2 "hosek, unwritable --out" "cannot write here" -- "$bin" fit hosek --out "$tmp/missing/w.json" "${small[@]}"
expect 2 "spectral4, unwritable --out" "cannot write here" -- "$bin" fit spectral4 --out "$tmp/missing/deeper/w.json" "${small[@]}"
elapsed_ms=$(( ($(date +%s%N) - start) / 1000000 ))
if [ $elapsed_ms -lt 5000 ] && [ ! -e "$tmp/missing" ]; then echo "ok   unwritable --out refused before any work (${elapsed_ms} ms), no folder made"
else echo "FAIL unwritable --out: ${elapsed_ms} ms, $(ls -d "$tmp/missing" 2>&1)"; fail=1; fi
expect 0 "sigmoid --check" "valid sigmoid" -- "$bin" fit sigmoid --check "$tmp/s.json"
python3 - "$tmp" <<'PY'
import json, math, sys, copy
d = sys.argv[1]
w = json.load(open(d + "/s.json"))
def dump(name, doc, text=None):
    with open(d + "/" + name, "w") as f: f.write(text if text is not None else json.dumps(doc))
bad = copy.deepcopy(w); bad["params"]["a"] = [row[:2] for row in w["params"]["a"]]; dump("shape.json", bad)
dump("nan.json", None, json.dumps(w).replace(json.dumps(w["params"]["a"][0][0][0]), "1e999", 1))
bad = copy.deepcopy(w); bad["atmosphere_hash"] = "0123456789abcdef"; dump("hash.json", bad)
bad = copy.deepcopy(w); bad["atmosphere"]["constituents"][0]["scattering"][0] *= 2; dump("atm.json", bad)
# a hosek weights file: same header, hosek params
h = copy.deepcopy(w); h["model"] = "hosek"; h["quantity"] = "sky_radiance"
h["inputs"] = [{"name": "sun_elevation_rad", "offset": 0, "scale": 2 / math.pi}]
h["params"] = {"coefficients": [[[-1, -0.1, 1, 0.5, -2, 0.3, 0.2, 0.6, 1] for j in range(6)] for k in range(3)],
               "radiance": [[1] * 6 for k in range(3)], "sun_elevation_rad": [0, 1.5]}
dump("h.json", h)
bad = copy.deepcopy(h); bad["params"]["coefficients"][1] = bad["params"]["coefficients"][1][:5]; dump("hshape.json", bad)
bad = copy.deepcopy(h); del bad["params"]["radiance"]; dump("hmissing.json", bad)
bad = copy.deepcopy(h); bad["params"]["sun_elevation_rad"] = [0, 2.5]; dump("hrange.json", bad)
# inputs that are not the model's own normalisation (they had been ignored)
bad = copy.deepcopy(h); bad["inputs"] = w["inputs"]; dump("hinputs.json", bad)
bad = copy.deepcopy(w); bad["inputs"][0]["scale"] = 2; dump("sinputs.json", bad)
# a parameter the model does not take (it had been ignored): a misspelling, another model's
bad = copy.deepcopy(w); bad["params"]["b"] = [1.0]; dump("sextra.json", bad)
bad = copy.deepcopy(h); bad["params"]["scale"] = h["params"]["radiance"]; dump("hextra.json", bad)
PY
# --grid and --views take digits 'x' digits and nothing else (cli/size_pair_option.h)
for g in 8x16x3 8x16abc 8x16,3 +8x+16 " 8x16" 1x16; do
  expect 2 "sigmoid --grid '$g'" "expected NHxNMU" -- "$bin" fit sigmoid --grid "$g" --out "$tmp/g.json"
done
expect 2 "hosek --grid 4x4junk" "expected NTxNP" -- "$bin" fit hosek --grid 4x4junk --check "$tmp/s.json"
expect 2 "build --views 10x10x" "expected WxH" -- "$bin" build --views 10x10x --out "$tmp/views"
[ ! -e "$tmp/g.json" ] && [ ! -e "$tmp/views" ] || { echo "FAIL a refused option wrote output"; fail=1; }
# --check and --samples take none of the options of a fit (they had been accepted and ignored)
expect 2 "sigmoid --check with --grid" "do not apply" -- "$bin" fit sigmoid --check "$tmp/s.json" --grid 8x8
expect 2 "sigmoid --check with --atmosphere" "do not apply" -- "$bin" fit sigmoid --check "$tmp/s.json" \
  --atmosphere "$src/examples/atmospheres/mars_dusty.json"
expect 2 "hosek --check with --out" "do not apply" -- "$bin" fit hosek --check "$tmp/h.json" --out "$tmp/h2.json"
for o in "--elevations 10" "--grid 4x4" "--orders 3" "--resolution 8x8,4x4x4x4" "--threads 1" "--atmosphere x.json"; do
  expect 2 "hosek --check with $o" "${o%% *} applies to the fit over the reference tables" -- \
    "$bin" fit hosek --check "$tmp/s.json" $o
  expect 2 "preetham --samples with $o" "${o%% *} applies to the fit over the reference tables" -- \
    "$bin" fit preetham --samples "$tmp/none.csv" $o
done
expect 2 "sigmoid wrong shape" "params.a" -- "$bin" fit sigmoid --check "$tmp/shape.json"
expect 2 "sigmoid non-finite" "nan.json" -- "$bin" fit sigmoid --check "$tmp/nan.json"
expect 2 "sigmoid hash mismatch" "hash" -- "$bin" fit sigmoid --check "$tmp/hash.json"
expect 2 "sigmoid atmosphere edited" "hash" -- "$bin" fit sigmoid --check "$tmp/atm.json"
expect 2 "sigmoid file as hosek" "model" -- "$bin" fit hosek --check "$tmp/s.json"
expect 0 "hosek --check" "valid hosek" -- "$bin" fit hosek --check "$tmp/h.json"
expect 2 "hosek with another model's inputs" "inputs" -- "$bin" fit hosek --check "$tmp/hinputs.json"
expect 2 "sigmoid inputs rescaled" "inputs\[0\]" -- "$bin" fit sigmoid --check "$tmp/sinputs.json"
expect 2 "hosek wrong shape" "params.coefficients" -- "$bin" fit hosek --check "$tmp/hshape.json"
expect 2 "hosek missing radiance" "params.radiance" -- "$bin" fit hosek --check "$tmp/hmissing.json"
expect 2 "hosek elevation range" "sun_elevation_rad" -- "$bin" fit hosek --check "$tmp/hrange.json"
expect 2 "hosek as preetham" "model" -- "$bin" fit preetham --check "$tmp/h.json"
expect 2 "sigmoid with a parameter it does not take" "params.b: not a parameter of this sigmoid model" -- "$bin" fit sigmoid --check "$tmp/sextra.json"
expect 2 "hosek with preetham's scale" "params.scale: not a parameter of this hosek model" -- "$bin" fit hosek --check "$tmp/hextra.json"
expect 2 "sigmoid --tables refused" "exact optical depth" -- "$bin" fit sigmoid --tables "$tmp" --out "$tmp/x.json"
expect 2 "hosek scene without ground viewer" "ground" -- bash -c "echo '{\"viewer_altitude_km\": [5, 10]}' > '$tmp/sc.json' && '$bin' fit hosek --scene '$tmp/sc.json' --out '$tmp/x.json'"
[ -e "$tmp/x.json" ] && { echo "FAIL: a failed fit wrote its output"; fail=1; }

# --samples: published Hosek (T=4, albedo 0.3, elevation 0.5 rad, green) and Preetham Y (T=3)
python3 - "$tmp" "$src/data/physical/hosek2012_rgb.json" <<'PY'
import json, math, sys
d, path = sys.argv[1], sys.argv[2]
ds = json.load(open(path))
T, alb, elev, ch = 4.0, 0.3, 0.5, 1
x = (elev / (math.pi / 2)) ** (1 / 3)
def bez(p): return sum(math.comb(5, j) * (1 - x) ** (5 - j) * x ** j * p[j] for j in range(6))
t = int(T) - 1
st = [(1 - alb) * bez([ds["coefficients"][ch][0][t][j][k] for j in range(6)]) +
      alb * bez([ds["coefficients"][ch][1][t][j][k] for j in range(6)]) for k in range(9)]
R = (1 - alb) * bez(ds["radiances"][ch][0][t]) + alb * bez(ds["radiances"][ch][1][t])
paper = st[:7] + [st[8], st[7]]
json.dump({"coefficients": paper, "R": R}, open(d + "/hosek_truth.json", "w"))
def hosek(th, g):
    chi = (1 + math.cos(g) ** 2) / (1 + st[8] ** 2 - 2 * st[8] * math.cos(g)) ** 1.5
    return (1 + st[0] * math.exp(st[1] / (math.cos(th) + 0.01))) * (st[2] + st[3] * math.exp(st[4] * g) + st[5] * math.cos(g) ** 2 + st[6] * chi + st[7] * math.sqrt(math.cos(th))) * R
Tp = 3.0
c = [0.1787 * Tp - 1.4630, -0.3554 * Tp + 0.4275, -0.0227 * Tp + 5.3251, 0.1206 * Tp - 2.5771, -0.0670 * Tp + 0.3703]
K = 2.5
json.dump({"coefficients": c, "K": K}, open(d + "/perez_truth.json", "w"))
def perez(th, g):
    return K * (1 + c[0] * math.exp(c[1] / math.cos(th))) * (1 + c[2] * math.exp(c[3] * g) + c[4] * math.cos(g) ** 2)
with open(d + "/hosek.csv", "w") as fh, open(d + "/perez.csv", "w") as fp:
    fh.write("theta,gamma,radiance\n"); fp.write("theta,gamma,radiance\n")
    for i in range(10):
        for j in range(14):
            th = (i + 0.5) / 10 * math.pi / 2; ph = j / 13 * math.pi
            cg = math.cos(th) * math.sin(elev) + math.sin(th) * math.cos(elev) * math.cos(ph)
            g = math.acos(max(-1, min(1, cg)))
            fh.write("%.17g,%.17g,%.17g\n" % (th, g, hosek(th, g)))
            fp.write("%.17g,%.17g,%.17g\n" % (th, g, perez(th, g)))
PY
R=$(python3 -c "import json;print(repr(json.load(open('$tmp/hosek_truth.json'))['R']))")
expect 0 "hosek --samples" "coefficients" -- "$bin" fit hosek --samples "$tmp/hosek.csv" --scale "$R" --unbounded
cp "$tmp/out" "$tmp/hosek_fit.json"
expect 0 "preetham --samples" "coefficients" -- "$bin" fit preetham --samples "$tmp/perez.csv"
cp "$tmp/out" "$tmp/perez_fit.json"
# A radiance below 0 had been fitted silently, and one of 1e300 had ended
# as a "converged" fit of rmse null, exit 0; a result lost on a full disk
# had exited 0.
{ cat "$tmp/perez.csv"; echo "0.5,0.5,-1"; } >"$tmp/negative.csv"
{ cat "$tmp/perez.csv"; echo "0.5,0.5,1e300"; } >"$tmp/huge.csv"
expect 2 "preetham --samples, a negative radiance" "radiance >= 0, got 0.5, 0.5, -1" -- "$bin" fit preetham --samples "$tmp/negative.csv"
# The row named is the file's line: blank lines are skipped, so it is not
# the sample's index + 2 (two blank lines had made line L "row L-2").
{ echo; echo; } >"$tmp/blanks.csv"
{ head -1 "$tmp/perez.csv"; cat "$tmp/blanks.csv"; tail -n +2 "$tmp/perez.csv"; echo "0.5,0.5,-1"; } >"$tmp/negative_blank.csv"
expect 2 "preetham --samples, the line after blank lines" "negative_blank.csv: row $(wc -l <"$tmp/negative_blank.csv"): need" -- \
  "$bin" fit preetham --samples "$tmp/negative_blank.csv"
expect 2 "preetham --samples, radiances whose squares overflow" "huge.csv: radiance: the squares overflow" -- \
  "$bin" fit preetham --samples "$tmp/huge.csv"
if [ -w /dev/full ]; then
  expect 1 "preetham --samples, stdout on a full disk" "writing to stdout failed" -- \
    bash -c '"$0" fit preetham --samples "$1" >/dev/full' "$bin" "$tmp/perez.csv"
fi
python3 - "$tmp" <<'PY' || fail=1
import json, sys
d = sys.argv[1]; bad = 0
for name, letters, scale_key in (("hosek", "ABCDEFGHI", "R"), ("perez", "ABCDE", "K")):
    fit = json.load(open(d + "/%s_fit.json" % name)); truth = json.load(open(d + "/%s_truth.json" % name))
    worst = max(abs(fit["coefficients"][l] - t) / abs(t) for l, t in zip(letters, truth["coefficients"]))
    sc = abs(fit["scale"] - truth[scale_key]) / truth[scale_key]
    ok = worst <= 1e-3 and sc <= 1e-3 and fit["rel_rmse"] <= 1e-6
    print("%s %s --samples: worst coefficient rel.err %.3g, scale rel.err %.3g, rel_rmse %.3g (bounds 1e-3, 1e-3, 1e-6), winning start: %s"
          % ("ok  " if ok else "FAIL", name, worst, sc, fit["rel_rmse"], fit["winning_start"]))
    bad |= not ok
sys.exit(bad)
PY
exit $fail
