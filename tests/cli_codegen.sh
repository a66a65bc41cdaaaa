#!/usr/bin/env bash
# skyfit codegen on the command line (SPEC §9, §11): byte-identical output
# for identical input, only what is asked is emitted, bad input exits 2 and
# writes nothing, previous outputs are left untouched.
set -uo pipefail
: "${SKYFIT_BIN:?}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
check() { if eval "$2"; then echo "ok   $1"; else echo "FAIL $1"; fail=1; fi; }

"$SKYFIT_BIN" codegen --help | grep -q "usage: skyfit codegen"
check "--help prints the usage" "[ \${PIPESTATUS[0]} -eq 0 ]"

mkdir -p "$tmp/a" "$tmp/b"
"$SKYFIT_BIN" codegen --baselines naive,chapman,taylor --lang both --out "$tmp/a" --quiet
check "first run exits 0" "[ $? -eq 0 ]"
"$SKYFIT_BIN" codegen --baselines naive,chapman,taylor --lang both --out "$tmp/b" --quiet
check "C header byte-identical across runs" "cmp -s $tmp/a/skyfit.h $tmp/b/skyfit.h"
check "GLSL byte-identical across runs" "cmp -s $tmp/a/skyfit.glsl $tmp/b/skyfit.glsl"
check "header names atmosphere, hash, domain, error" \
  "grep -q 'atmosphere: earth-hillaire2020, hash [0-9a-f]\{16\}' $tmp/a/skyfit.h && grep -q 'domain: h_km' $tmp/a/skyfit.h && grep -q 'measured error: transmittance' $tmp/a/skyfit.h"
check "same function names in C and GLSL" \
  "[ \"\$(grep -o 'skyfit_[a-z_]*transmittance[a-z_]*(' $tmp/a/skyfit.h | sort -u)\" = \"\$(grep -o 'skyfit_[a-z_]*transmittance[a-z_]*(' $tmp/a/skyfit.glsl | sort -u)\" ]"

# The naive sky beside the naive raymarch (both named naive): one header
# that compiles as -Wall -Wextra -Werror -pedantic C99 and as GLSL, with a
# plausible sky (tests/test_sky_naive.c checks its values against the
# reference single scattering)
mkdir -p "$tmp/sky"
"$SKYFIT_BIN" codegen --baselines naive,naive-sky --lang both --out "$tmp/sky" --quiet
check "naive,naive-sky: exits 0, the header says where its error is" \
  "[ $? -eq 0 ] && grep -q 'skyfit_naive_sky_radiance(float h_km, float mu, float mu_s, float nu)' $tmp/sky/skyfit.h && grep -q \"skyfit report's naive-sky row\" $tmp/sky/skyfit.h"
printf '#include "skyfit.h"\n#include <stdio.h>\nint main(void) {\n  skyfit_vec3 L = skyfit_naive_sky_radiance(0.0f, 0.3f, 0.5f, 0.2f);\n  skyfit_vec3 T = skyfit_naive_transmittance(0.0f, 0.5f);\n  printf("%%.9g %%.9g %%.9g %%.9g\\n", L.x, L.y, L.z, T.x);\n  return 0;\n}\n' >"$tmp/sky/use.c"
check "naive,naive-sky: the C compiles with -Werror and runs" \
  "cc -std=c99 -Wall -Wextra -Werror -pedantic -I$tmp/sky -o $tmp/sky/use $tmp/sky/use.c -lm && $tmp/sky/use > $tmp/sky/out.txt"
check "naive,naive-sky: a sky brighter in blue than red, a transmittance in (0, 1)" \
  "awk '{ exit !(\$1 > 0 && \$3 > \$1 && \$4 > 0 && \$4 < 1) }' $tmp/sky/out.txt"
if command -v glslangValidator >/dev/null; then
  { echo '#version 330'; cat "$tmp/sky/skyfit.glsl"
    echo 'out vec4 c; void main() { c = vec4(skyfit_naive_sky_radiance(0.0, 0.3, 0.5, 0.2) + skyfit_naive_transmittance(0.0, 0.5), 1.0); }'; } >"$tmp/sky/use.frag"
  check "naive,naive-sky: the GLSL compiles" "glslangValidator $tmp/sky/use.frag > $tmp/sky/glsl.log 2>&1"
fi
"$SKYFIT_BIN" codegen --baselines naive-sky,naive-sky --lang c --out "$tmp/sky" --name twice 2>"$tmp/err.txt"
check "naive-sky given twice exits 2, nothing written" "[ $? -eq 2 ] && [ ! -e $tmp/sky/twice.h ] && grep -q 'given twice' $tmp/err.txt"
# An empty list or item (skipped by the split) had replaced the header with
# an empty one, exit 0.
cp "$tmp/sky/skyfit.h" "$tmp/sky/skyfit.h.before"
for list in "" "," "naive,,chapman" "naive,"; do
  "$SKYFIT_BIN" codegen --baselines "$list" --lang c --out "$tmp/sky" 2>"$tmp/err.txt"
  check "--baselines '$list' exits 2, the header as it was" \
    "[ $? -eq 2 ] && cmp -s $tmp/sky/skyfit.h $tmp/sky/skyfit.h.before && grep -q 'empty item' $tmp/err.txt"
done

# Schuler's sky beside the naive sky and the Chapman transmittance (whose
# columns its sun columns are): one header, -Werror C99 and GLSL; within
# 10 % of the naive sky in blue looking up at noon (the approximation is
# 3.4 % low straight up, tests/test_sky_naive.c checks it against eq. 24)
mkdir -p "$tmp/schuler"
"$SKYFIT_BIN" codegen --baselines chapman,naive-sky,schuler-sky --lang both --out "$tmp/schuler" --quiet
check "chapman,naive-sky,schuler-sky: exits 0, the header says where its error is" \
  "[ $? -eq 0 ] && grep -q 'skyfit_schuler_sky_radiance(float h_km, float mu, float mu_s, float nu)' $tmp/schuler/skyfit.h && grep -q \"skyfit report's schuler-sky row\" $tmp/schuler/skyfit.h"
printf '#include "skyfit.h"\n#include <stdio.h>\nint main(void) {\n  skyfit_vec3 S = skyfit_schuler_sky_radiance(0.0f, 0.3f, 0.5f, 0.2f);\n  skyfit_vec3 N = skyfit_naive_sky_radiance(0.0f, 0.3f, 0.5f, 0.2f);\n  printf("%%.9g %%.9g %%.9g\\n", S.x, S.z, N.z);\n  return 0;\n}\n' >"$tmp/schuler/use.c"
check "schuler-sky: the C compiles with -Werror, bluer than red, within 10 % of the naive sky in blue" \
  "cc -std=c99 -Wall -Wextra -Werror -pedantic -I$tmp/schuler -o $tmp/schuler/use $tmp/schuler/use.c -lm && $tmp/schuler/use > $tmp/schuler/out.txt && awk '{ exit !(\$1 > 0 && \$2 > \$1 && \$2 > 0.9 * \$3 && \$2 < 1.1 * \$3) }' $tmp/schuler/out.txt"
if command -v glslangValidator >/dev/null; then
  { echo '#version 330'; cat "$tmp/schuler/skyfit.glsl"
    echo 'out vec4 c; void main() { c = vec4(skyfit_schuler_sky_radiance(0.0, 0.3, 0.5, 0.2) + skyfit_chapman_transmittance(0.0, 0.5), 1.0); }'; } >"$tmp/schuler/use.frag"
  check "chapman,schuler-sky: the GLSL compiles" "glslangValidator $tmp/schuler/use.frag > $tmp/schuler/glsl.log 2>&1"
fi

# Leenman's raymarched and flat skies beside the flat transmittance (they
# share the flat model's helpers and the skies their columns, behind
# guards) and the naive sky: one header that compiles as -Werror C99 and
# as GLSL; the skies agree to within the raymarched and flat models' own
# error (tests/test_sky_raymarched.c checks their values against the
# reference single scattering and seed 000 eq. 52)
mkdir -p "$tmp/rm"
"$SKYFIT_BIN" codegen --baselines flat,raymarched-sky,naive-sky,flat-sky --lang both --out "$tmp/rm" --quiet
check "flat,raymarched-sky,naive-sky,flat-sky: exits 0, the header says where their errors are" \
  "[ $? -eq 0 ] && grep -q 'skyfit_raymarched_sky_radiance(float h_km, float mu, float mu_s, float nu)' $tmp/rm/skyfit.h && grep -q \"skyfit report's raymarched-sky row\" $tmp/rm/skyfit.h && grep -q 'skyfit_flat_sky_radiance(float h_km, float mu, float mu_s, float nu)' $tmp/rm/skyfit.h && grep -q \"skyfit report's flat-sky row\" $tmp/rm/skyfit.h"
printf '#include "skyfit.h"\n#include <stdio.h>\nint main(void) {\n  skyfit_vec3 L = skyfit_raymarched_sky_radiance(0.0f, 0.3f, 0.5f, 0.2f);\n  skyfit_vec3 N = skyfit_naive_sky_radiance(0.0f, 0.3f, 0.5f, 0.2f);\n  skyfit_vec3 T = skyfit_flat_transmittance(0.0f, 0.5f);\n  skyfit_vec3 F = skyfit_flat_sky_radiance(0.0f, 0.3f, 0.5f, 0.2f);\n  printf("%%.9g %%.9g %%.9g %%.9g %%.9g %%.9g %%.9g\\n", L.x, L.y, L.z, N.z, T.x, F.x, F.z);\n  return 0;\n}\n' >"$tmp/rm/use.c"
check "flat,raymarched-sky,naive-sky,flat-sky: the C compiles with -Werror and runs" \
  "cc -std=c99 -Wall -Wextra -Werror -pedantic -I$tmp/rm -o $tmp/rm/use $tmp/rm/use.c -lm && $tmp/rm/use > $tmp/rm/out.txt"
check "raymarched-sky: bluer than red, within 10 % of the naive sky in blue, a transmittance in (0, 1)" \
  "awk '{ exit !(\$1 > 0 && \$3 > \$1 && \$3 > 0.9 * \$4 && \$3 < 1.1 * \$4 && \$5 > 0 && \$5 < 1) }' $tmp/rm/out.txt"
check "flat-sky: bluer than red, within 10 % of the naive sky in blue" \
  "awk '{ exit !(\$6 > 0 && \$7 > \$6 && \$7 > 0.9 * \$4 && \$7 < 1.1 * \$4) }' $tmp/rm/out.txt"
if command -v glslangValidator >/dev/null; then
  { echo '#version 330'; cat "$tmp/rm/skyfit.glsl"
    echo 'out vec4 c; void main() { c = vec4(skyfit_raymarched_sky_radiance(0.0, 0.3, 0.5, 0.2) + skyfit_flat_sky_radiance(0.0, 0.3, 0.5, 0.2) + skyfit_flat_transmittance(0.0, 0.5), 1.0); }'; } >"$tmp/rm/use.frag"
  check "flat,raymarched-sky,flat-sky: the GLSL compiles" "glslangValidator $tmp/rm/use.frag > $tmp/rm/glsl.log 2>&1"
fi
# Their shared column helpers hold the atmosphere's numbers, so their guard
# names it: two headers of one atmosphere share them, two of two
# atmospheres (one prefix) fail to compile on the names. One guard had
# compiled Earth's raymarched sky with Mars's flat sky, which then ran on
# Earth's air.
"$SKYFIT_BIN" codegen --baselines raymarched-sky --lang c --out "$tmp/rm" --name earth_raymarched --quiet
"$SKYFIT_BIN" codegen --baselines flat-sky --lang c --out "$tmp/rm" --name earth_flat --quiet
"$SKYFIT_BIN" codegen --baselines flat-sky --atmosphere "$SKYFIT_SOURCE_DIR/examples/atmospheres/mars_dusty.json" \
  --lang c --out "$tmp/rm" --name mars_flat --quiet
printf '#include "earth_raymarched.h"\n#include "%s.h"\n#include <stdio.h>\nint main(void) {\n  skyfit_vec3 F = skyfit_flat_sky_radiance(0.0f, 0.3f, 0.5f, 0.2f);\n  printf("%%.9g\\n", F.z);\n  return 0;\n}\n' earth_flat >"$tmp/rm/same.c"
sed 's/earth_flat/mars_flat/' "$tmp/rm/same.c" >"$tmp/rm/other.c"
check "raymarched-sky and flat-sky headers of one atmosphere share their columns: compiles, the same sky" \
  "cc -std=c99 -Wall -Wextra -Werror -pedantic -I$tmp/rm -o $tmp/rm/same $tmp/rm/same.c -lm && [ \"\$($tmp/rm/same)\" = \"\$(awk '{ print \$7 }' $tmp/rm/out.txt)\" ]"
check "raymarched-sky and flat-sky headers of two atmospheres, one prefix: the C does not compile" \
  "! cc -std=c99 -Wall -Wextra -Werror -pedantic -I$tmp/rm -o $tmp/rm/other $tmp/rm/other.c -lm 2>/dev/null"
"$SKYFIT_BIN" codegen --baselines raymarched-sky,raymarched-sky --lang c --out "$tmp/rm" --name twice 2>"$tmp/err.txt"
check "raymarched-sky given twice exits 2, nothing written" "[ $? -eq 2 ] && [ ! -e $tmp/rm/twice.h ] && grep -q 'given twice' $tmp/err.txt"

# An atmosphere with no exponential constituent (one scattering tent):
# the Chapman, Taylor, flat and spline approximations (and Schuler's sky)
# need one and are refused (their emitted code had failed -Werror on unread variables);
# the naive raymarch and the skies compile
mkdir -p "$tmp/tent"
cat >"$tmp/tent/atm.json" <<'JSON'
{"name": "tent-only", "bottom_radius_km": 6360, "top_radius_km": 6460, "channels": "rgb",
 "constituents": [{"name": "haze", "scattering": [1e-3, 1e-3, 1e-3], "absorption": [0, 0, 0],
  "phase": {"kind": "isotropic"},
  "density": [{"width_km": 25, "linear_per_km": 0.0666666, "constant": -0.6666667},
              {"width_km": 0, "linear_per_km": -0.0666666, "constant": 2.6666667}]}]}
JSON
for b in chapman taylor flat spline schuler-sky; do
  "$SKYFIT_BIN" codegen --baselines "$b" --atmosphere "$tmp/tent/atm.json" --lang c --out "$tmp/tent" --name "$b" 2>"$tmp/err.txt"
  check "no exponential constituent: $b exits 2 and says why, nothing written" \
    "[ $? -eq 2 ] && [ ! -e $tmp/tent/$b.h ] && grep -q 'needs\\? an exponential constituent' $tmp/err.txt"
done
"$SKYFIT_BIN" codegen --baselines naive,naive-sky,raymarched-sky,flat-sky --atmosphere "$tmp/tent/atm.json" --lang c --out "$tmp/tent" --quiet
printf '#include "skyfit.h"\nint main(void) { return skyfit_raymarched_sky_radiance(0.0f, 0.3f, 0.5f, 0.2f).x > 0.0f && skyfit_flat_sky_radiance(0.0f, 0.3f, 0.5f, 0.2f).x > 0.0f ? 0 : 1; }\n' >"$tmp/tent/use.c"
check "no exponential constituent: naive, naive-sky, raymarched-sky, flat-sky compile with -Werror, a sky" \
  "cc -std=c99 -Wall -Wextra -Werror -pedantic -I$tmp/tent -o $tmp/tent/use $tmp/tent/use.c -lm && $tmp/tent/use"

# An exponential constituent that neither scatters nor absorbs: its column
# is in no channel's sum, and the analytic transmittances' headers had
# failed -Werror on it (set but unused); with every baseline, C and C++
mkdir -p "$tmp/clear"
cat >"$tmp/clear/atm.json" <<'JSON'
{"base": "default", "constituents": [{"name": "rayleigh"}, {"name": "mie"}, {"name": "ozone"},
 {"name": "nothing", "scattering": [0, 0, 0], "absorption": [0, 0, 0], "phase": {"kind": "isotropic"},
  "density": [{"width_km": 0, "exp_term": 1, "exp_scale_per_km": -0.125, "linear_per_km": 0, "constant": 0}]}]}
JSON
"$SKYFIT_BIN" codegen --baselines naive,chapman,taylor,flat,spline,naive-sky,raymarched-sky,flat-sky,schuler-sky \
  --atmosphere "$tmp/clear/atm.json" --lang c --out "$tmp/clear" --quiet
printf '#include "skyfit.h"\nint main(void) { return skyfit_chapman_transmittance(0.0f, 0.5f).x > 0.0f ? 0 : 1; }\n' \
  >"$tmp/clear/use.c"
check "a transparent constituent: every baseline compiles with -Werror as C99 and C++" \
  "cc -std=c99 -Wall -Wextra -Werror -pedantic -I$tmp/clear -o $tmp/clear/use $tmp/clear/use.c -lm && $tmp/clear/use && c++ -x c++ -std=c++11 -Wall -Wextra -Werror -pedantic -I$tmp/clear -o $tmp/clear/use_cpp $tmp/clear/use.c"

mkdir -p "$tmp/c"
"$SKYFIT_BIN" codegen --baselines chapman --lang c --out "$tmp/c" --quiet
check "only chapman asked: no naive/taylor functions or helpers" \
  "! grep -q 'skyfit_naive_\|skyfit_taylor_' $tmp/c/skyfit.h && grep -q skyfit_chapman_transmittance $tmp/c/skyfit.h"
check "only C asked: no GLSL written" "[ ! -e $tmp/c/skyfit.glsl ]"

cp "$tmp/a/skyfit.h" "$tmp/before.h"
"$SKYFIT_BIN" codegen --baselines naive,bogus --lang both --out "$tmp/a" 2>"$tmp/err.txt"
check "unknown baseline exits 2" "[ $? -eq 2 ]"
check "message names the baseline" "grep -q \"unknown baseline 'bogus'\" $tmp/err.txt"
check "previous output untouched" "cmp -s $tmp/a/skyfit.h $tmp/before.h"

echo '{"skyfit_weights": 1, "model": "sigmoid"' > "$tmp/broken.json"
"$SKYFIT_BIN" codegen --weights "$tmp/broken.json" --lang c --out "$tmp/a" 2>"$tmp/err.txt"
check "broken weights file exits 2" "[ $? -eq 2 ]"
check "message names the file" "grep -q broken.json $tmp/err.txt"
check "previous output untouched" "cmp -s $tmp/a/skyfit.h $tmp/before.h"

# The scattering network's segment function calls the transmittance
# network's: given in either order, the header declares them first (it
# did not compile with the scattering weights first).
command -v glslangValidator >/dev/null || { echo "FAIL glslangValidator is not installed (scripts/setup.sh installs it)"; fail=1; }
if [ -z "${SKYFIT_SOURCE_DIR:-}" ]; then echo "FAIL SKYFIT_SOURCE_DIR is not set (ctest sets it)"; fail=1; else
  w="$SKYFIT_SOURCE_DIR/weights/default"
  # The header's max abs is the larger of the build's sample and the fit's
  # search near the horizon (it had stated the sample's 0.505 for a sigmoid
  # whose file holds 0.661, found just below the horizon).
  mkdir -p "$tmp/maxabs"
  "$SKYFIT_BIN" codegen --weights "$w/sigmoid.json" --weights "$w/mlp-transmittance.json" --lang c \
    --out "$tmp/maxabs" --quiet
  check "the header states the fit's larger maximum, and the sample's" "python3 - $w $tmp/maxabs/skyfit.h <<'PY'
import json, sys
text = open(sys.argv[2]).read()
for name in ('sigmoid', 'mlp-transmittance'):
    m = json.load(open(sys.argv[1] + '/' + name + '.json'))['metrics']
    sample, fit = m['build_error']['max_abs'], m.get('max_abs', float('nan'))
    want = ('max abs %.3g (the fit' % fit + \"'s search near the horizon; %.3g over the values)\" % sample) if fit > sample else 'max abs %.3g,' % sample
    assert want in text, (name, want)
assert json.load(open(sys.argv[1] + '/sigmoid.json'))['metrics']['max_abs'] > 0.6
PY"
  # Without a transmittance network the segment is left out, and codegen says so.
  mkdir -p "$tmp/alone"
  "$SKYFIT_BIN" codegen --weights "$w/mlp-scattering.json" --lang c --out "$tmp/alone" 2> "$tmp/alone/err.txt"
  check "a sky network alone: no segment function, and a note naming it" \
    "! grep -q skyfit_mlp_sky_radiance_segment $tmp/alone/skyfit.h && grep -q 'skyfit_mlp_sky_radiance_segment (eq. 44) is not emitted' $tmp/alone/err.txt"
  # A transmittance network of another atmosphere (same radii, hazier air)
  # is not the one eq. 44 needs: not joined, and the same note.
  mkdir -p "$tmp/hazy"
  echo '{"base": "default", "name": "hazy", "constituents": [{"name": "mie", "scattering": [0.02, 0.02, 0.02]}]}' \
    > "$tmp/hazy/atm.json"
  "$SKYFIT_BIN" fit mlp-transmittance --atmosphere "$tmp/hazy/atm.json" --resolution 32x16,4x8x4x4 --epochs 2 \
    --polish 0 --out "$tmp/hazy/t.json" --quiet
  "$SKYFIT_BIN" codegen --weights "$tmp/hazy/t.json" --weights "$w/mlp-scattering.json" --lang c --out "$tmp/hazy" \
    2> "$tmp/hazy/err.txt"
  check "another atmosphere's transmittance network: no segment function, and the note" \
    "grep -q skyfit_mlp_transmittance $tmp/hazy/skyfit.h && ! grep -q skyfit_mlp_sky_radiance_segment $tmp/hazy/skyfit.h && grep -q 'skyfit_mlp_sky_radiance_segment (eq. 44) is not emitted' $tmp/hazy/err.txt"
  for order in "mlp-transmittance mlp-scattering" "mlp-scattering mlp-transmittance"; do
    set -- $order
    mkdir -p "$tmp/order"
    "$SKYFIT_BIN" codegen --weights "$w/$1.json" --weights "$w/$2.json" --lang both --out "$tmp/order" --quiet
    printf '#include "skyfit.h"\nint main(void) { return skyfit_mlp_sky_radiance_segment(1.0f, 0.3f, 0.5f, 0.2f, 10.0f).x < 0.0f; }\n' \
      > "$tmp/order/use.c"
    check "$1 then $2: the C compiles and its segment call runs" \
      "cc -std=c99 -Wall -Werror -I$tmp/order -o $tmp/order/use $tmp/order/use.c -lm && $tmp/order/use"
    if command -v glslangValidator >/dev/null; then
      printf '#version 450\n' > "$tmp/order/use.frag"
      cat "$tmp/order/skyfit.glsl" >> "$tmp/order/use.frag"
      printf 'layout(location = 0) out vec4 c;\nvoid main() { c = vec4(skyfit_mlp_sky_radiance_segment(1.0, 0.3, 0.5, 0.2, 10.0), 1.0); }\n' \
        >> "$tmp/order/use.frag"
      check "$1 then $2: the GLSL compiles" "glslangValidator $tmp/order/use.frag > $tmp/order/glsl.log 2>&1"
    fi
  done
fi

"$SKYFIT_BIN" codegen --baselines naive --lang c --out "$tmp/missing-dir" 2>"$tmp/err.txt"
check "missing output folder exits 2" "[ $? -eq 2 ]"
"$SKYFIT_BIN" codegen --baselines naive --out "$tmp/a" 2>/dev/null
check "missing --lang exits 2" "[ $? -eq 2 ]"
check "no temporary files left" "[ -z \"\$(ls $tmp/a | grep tmp)\" ]"
# The C header and the GLSL file are written as a pair: a GLSL path that
# cannot be written leaves the previous header as it was (the header was
# replaced before the GLSL failed). An empty --name exits 2.
mkdir -p "$tmp/pair/pair.glsl"
echo "previous" > "$tmp/pair/pair.h"
"$SKYFIT_BIN" codegen --baselines naive --lang both --out "$tmp/pair" --name pair 2>"$tmp/err.txt"
check "GLSL path a folder: exit 2, the previous header untouched" \
  "[ $? -eq 2 ] && [ \"\$(cat $tmp/pair/pair.h)\" = previous ] && [ -z \"\$(ls $tmp/pair | grep tmp)\" ]"
"$SKYFIT_BIN" codegen --baselines naive --lang c --out "$tmp/pair" --name "" 2>"$tmp/err.txt"
check "empty --name exits 2" "[ $? -eq 2 ] && [ ! -e $tmp/pair/.h ]"
# Names reach the header's comment: one that would close it or open a
# comment inside it (GCC's -Wcomment, an error under -Werror) is defused.
mkdir -p "$tmp/names"
printf '{"base": "default", "name": "evil */ #error injected /* x"}' > "$tmp/names/a.json"
"$SKYFIT_BIN" codegen --baselines naive,flat --atmosphere "$tmp/names/a.json" --lang c --out "$tmp/names" --name n \
  2>/dev/null
check "an atmosphere named with */ and /*: the header compiles with -Werror" \
  "cc -std=c99 -Wall -Wextra -Werror -pedantic -fsyntax-only $tmp/names/n.h"
# One source of the atmosphere, and only for the baselines.
printf '{}' > "$tmp/names/scene.json"
"$SKYFIT_BIN" codegen --baselines naive --atmosphere "$tmp/names/a.json" --scene "$tmp/names/scene.json" --lang c \
  --out "$tmp/names" --name twice 2>/dev/null
check "--atmosphere with --scene exits 2, nothing written" "[ $? -eq 2 ] && [ ! -e $tmp/names/twice.h ]"
if [ -n "${SKYFIT_SOURCE_DIR:-}" ]; then
  "$SKYFIT_BIN" codegen --weights "$SKYFIT_SOURCE_DIR/weights/default/sigmoid.json" --atmosphere "$tmp/names/a.json" \
    --lang c --out "$tmp/names" --name ignored 2>/dev/null
  check "--atmosphere without --baselines exits 2, nothing written" "[ $? -eq 2 ] && [ ! -e $tmp/names/ignored.h ]"
  "$SKYFIT_BIN" codegen --weights "$SKYFIT_SOURCE_DIR/weights/default/sigmoid.json" --naive-steps 8 \
    --lang c --out "$tmp/names" --name steps 2>"$tmp/err.txt"
  check "--naive-steps without the naive baseline exits 2, nothing written (it had been ignored)" \
    "[ $? -eq 2 ] && [ ! -e $tmp/names/steps.h ] && grep -q 'applies to the naive baseline' $tmp/err.txt"
  "$SKYFIT_BIN" codegen --baselines chapman,naive --naive-steps 8 --lang c --out "$tmp/names" --name steps8 2>/dev/null
  check "--naive-steps with --baselines chapman,naive: written, 8 steps" \
    "[ $? -eq 0 ] && grep -q '8-step midpoint raymarch' $tmp/names/steps8.h"
fi
# Two atmospheres in one program: --prefix renames every emitted name
# (functions, types, macros), so both headers compile in one translation
# unit and both GLSL files in one shader; without it they had clashed.
mkdir -p "$tmp/two"
printf '{"base": "default", "name": "hazy", "constituents": [{"name": "mie", "scattering": [0.02, 0.02, 0.02]}]}' \
  > "$tmp/two/hazy.json"
"$SKYFIT_BIN" codegen --baselines naive,chapman --lang both --out "$tmp/two" --name earth --prefix earth --quiet
"$SKYFIT_BIN" codegen --baselines naive,chapman --atmosphere "$tmp/two/hazy.json" --lang both --out "$tmp/two" \
  --name hazy --prefix hazy --quiet
printf '#include "earth.h"\n#include "hazy.h"\nfloat f(void) { return earth_naive_transmittance(0.0f, 0.5f).z - hazy_naive_transmittance(0.0f, 0.5f).z; }\n' \
  > "$tmp/two/both.c"
check "--prefix: two headers in one C99 translation unit, no name left as skyfit_" \
  "cc -std=c99 -Wall -Wextra -Werror -pedantic -c $tmp/two/both.c -I$tmp/two -o $tmp/two/both.o &&
   ! grep -q 'skyfit_\|SKYFIT_' $tmp/two/hazy.h"
if command -v glslangValidator >/dev/null; then
  { printf '#version 450\nlayout(location = 0) out vec4 c;\n'; cat "$tmp/two/earth.glsl" "$tmp/two/hazy.glsl";
    printf 'void main() { c = vec4(earth_chapman_transmittance(0.0, 0.5) - hazy_chapman_transmittance(0.0, 0.5), 1.0); }\n'; } \
    > "$tmp/two/both.frag"
  check "--prefix: two GLSL files in one shader" "glslangValidator $tmp/two/both.frag > $tmp/two/glsl.log 2>&1"
fi
"$SKYFIT_BIN" codegen --baselines naive --lang c --out "$tmp/two" --name bad --prefix 9x 2>/dev/null
check "--prefix 9x exits 2, nothing written" "[ $? -eq 2 ] && [ ! -e $tmp/two/bad.h ]"
# A header path that is a link to a --weights file: refused, the weights
# kept (outputs follow links; the header had replaced the weights, exit 0).
mkdir -p "$tmp/linked/gen"
"$SKYFIT_BIN" fit sigmoid --grid 8x16 --out "$tmp/linked/sig.json" --quiet
cp "$tmp/linked/sig.json" "$tmp/linked/sig.before"
ln -s ../sig.json "$tmp/linked/gen/skyfit.h"
"$SKYFIT_BIN" codegen --weights "$tmp/linked/sig.json" --lang c --out "$tmp/linked/gen" 2>"$tmp/linked/err"
rc=$?
check "a header linked to its --weights: exit $rc, the weights kept ($(cat "$tmp/linked/err"))" \
  "[ $rc -eq 2 ] && grep -q 'is the same file as the input' $tmp/linked/err && cmp -s $tmp/linked/sig.json $tmp/linked/sig.before"
exit $fail
