#!/usr/bin/env bash
# Build integration (SPEC §9): install skyfit into a temporary prefix, build
# examples/consumer (find_package(skyfit) + skyfit_generate) against it, and
# check that the headers are regenerated when the scene or the atmosphere
# file changes, and not when nothing changed.
set -euo pipefail
: "${SKYFIT_BIN:?}" "${SKYFIT_SOURCE_DIR:?}"
build_dir=$(dirname "$SKYFIT_BIN")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

cmake --install "$build_dir" --prefix "$tmp/prefix" >/dev/null
test -x "$tmp/prefix/bin/skyfit"
test -f "$tmp/prefix/share/skyfit/physical/hosek2012_rgb.json"
test -f "$tmp/prefix/lib/cmake/skyfit/skyfitConfig.cmake"
echo "ok   installed bin/skyfit, share/skyfit/physical, lib/cmake/skyfit"

# A moved installation reads its own share/skyfit/physical (the paths built
# in are the configure-time prefix and the source tree): its copy of the
# Rayleigh table, made unreadable as CSV here, is the one it reports.
cp -r "$tmp/prefix" "$tmp/moved"
echo "not a table" >"$tmp/moved/share/skyfit/physical/rayleigh_bucholtz.csv"
cat >"$tmp/recipe.json" <<'JSON'
{"name": "recipe", "bottom_radius_km": 6360, "top_radius_km": 6460, "channels": {"wavelengths_nm": [400, 500, 600]},
 "constituents": [{"name": "rayleigh", "scattering": {"recipe": "rayleigh_bucholtz"}, "absorption": 0,
                   "phase": {"kind": "rayleigh"}, "density": [{"exp_term": 1, "exp_scale_per_km": -0.125}]}]}
JSON
moved_err=$(printf 'h_km,mu\n0,1\n' | env -u SKYFIT_DATA_DIR "$tmp/moved/bin/skyfit" eval transmittance \
  --atmosphere "$tmp/recipe.json" 2>&1 >/dev/null || true)
grep -q "$tmp/moved/bin/../share/skyfit/physical/rayleigh_bucholtz.csv" <<<"$moved_err" ||
  { echo "FAIL the moved installation did not read its own data: $moved_err"; exit 1; }
printf 'h_km,mu\n0,1\n' | env -u SKYFIT_DATA_DIR "$tmp/prefix/bin/skyfit" eval transmittance \
  --atmosphere "$tmp/recipe.json" >/dev/null
echo "ok   a moved installation reads its own share/skyfit/physical"

cp -r "$SKYFIT_SOURCE_DIR/examples/consumer" "$tmp/consumer"
# small tables and short fits: each regeneration is a whole `skyfit build`
cmake -S "$tmp/consumer" -B "$tmp/consumer/build" -DCMAKE_PREFIX_PATH="$tmp/prefix" \
  "-DSKY_BUILD_OPTIONS=--quick --resolution 32x16,8x16x8x4 --samples 2000 --timing-points 20000 --repetitions 1 --mlp-epochs 10,1" \
  >/dev/null
header="$tmp/consumer/build/generated/skyfit.h"
glsl="$tmp/consumer/build/generated/skyfit.glsl"

build() { cmake --build "$tmp/consumer/build" 2>&1; }
generated() { grep -c "skyfit: generating" <<<"$1" || true; }

out=$(build)
[ "$(generated "$out")" -ge 1 ] || { echo "FAIL first build did not generate"; echo "$out"; exit 1; }
test -f "$header" && test -f "$glsl"
grep -q "earth-consumer-example" "$header"
"$tmp/consumer/build/sky_demo" | tee "$tmp/demo.txt"
grep -q "^mu 1.0000" "$tmp/demo.txt"
echo "ok   first build generated skyfit.h and skyfit.glsl and the demo ran"
grep -q "baseline_chapman_transmittance(float h_km, float mu)" "$tmp/consumer/build/generated/sky_baselines.h" ||
  { echo "FAIL the second skyfit_generate (BASELINES, PREFIX baseline) wrote no sky_baselines.h"; exit 1; }
echo "ok   a second skyfit_generate on the target (another NAME and PREFIX, BASELINES): both headers in main.c"
# The selected model (the report in the work folder names it) behind the
# stable names: the demo's zenith transmittance is the reference's within
# the scene's budget (1e-3 RMSE; 0.01 here, a single ray).
chosen=$(sed -n 's/^- \*\*transmittance: \([a-z0-9-]*\)\*\*.*/\1/p' "$tmp/consumer/build/skyfit/sky_demo/skyfit/report.md")
emitted=$(sed -n 's/.*return skyfit_\([a-z0-9]*\)_transmittance(h_km, mu);.*/\1/p' "$header")
# a candidate's name less its variant (naive16, mlp-transmittance-2) is its functions' prefix
[ -n "$chosen" ] && [ "${chosen%%[-0-9]*}" = "$emitted" ] || { echo "FAIL selected '$chosen', the header calls '$emitted'"; exit 1; }
printf 'h_km,mu\n0,1\n' | "$tmp/prefix/bin/skyfit" eval transmittance --atmosphere "$tmp/consumer/earth.json" >"$tmp/ref.csv"
python3 - "$tmp/demo.txt" "$tmp/ref.csv" <<'PY'
import sys
demo = [l.split() for l in open(sys.argv[1]) if l.startswith("mu 1.0000")][0]
got = [float(x) for x in demo[3:6]]
want = [float(x) for x in open(sys.argv[2]).read().splitlines()[1].split(",")[2:5]]
print("zenith transmittance: header", got, "reference", want)
assert all(abs(g - w) < 0.01 for g, w in zip(got, want)), "FAIL the selected model's zenith transmittance"
PY
echo "ok   skyfit_transmittance calls the selected model ($chosen)"

sleep 1; touch "$tmp/marker"
out=$(build)
[ "$(generated "$out")" -eq 0 ] || { echo "FAIL regenerated although nothing changed"; exit 1; }
[ ! "$header" -nt "$tmp/marker" ] || { echo "FAIL header rewritten although nothing changed"; exit 1; }
echo "ok   nothing changed: no regeneration"

sleep 1; touch "$tmp/consumer/sky.json"; sleep 1; touch "$tmp/marker"
out=$(build)
[ "$(generated "$out")" -ge 1 ] || { echo "FAIL touching the scene did not regenerate"; exit 1; }
[ "$header" -nt "$tmp/marker" ] && [ "$glsl" -nt "$tmp/marker" ]
echo "ok   touched sky.json: headers regenerated"

sleep 1; touch "$tmp/marker"
out=$(build)
[ "$(generated "$out")" -eq 0 ] || { echo "FAIL regenerated twice"; exit 1; }
echo "ok   and not again"

# A changed atmosphere: new name, regenerated, and the header says so.
sed -i 's/earth-consumer-example/earth-consumer-hazier/' "$tmp/consumer/earth.json"
sleep 1; touch "$tmp/marker"
out=$(build)
[ "$(generated "$out")" -ge 1 ] || { echo "FAIL editing the atmosphere did not regenerate"; exit 1; }
grep -q "earth-consumer-hazier" "$header"
echo "ok   edited earth.json: headers regenerated with the new atmosphere"

# Mistakes in a consumer's call stop its configure with skyfit_generate's
# message: a misspelt keyword (PREFX had been dropped silently, the build
# failing in the compiler on unprefixed names), and a scene whose
# atmosphere is missing (the generator's "no rule to make target").
bad_configure() {   # bad_configure NAME EXPECTED -- the skyfit_generate arguments
  local name=$1 want=$2
  shift 3
  mkdir -p "$tmp/$name"
  cp "$tmp/consumer/main.c" "$tmp/consumer/sky.json" "$tmp/$name/"
  printf 'cmake_minimum_required(VERSION 3.19)\nproject(bad C)\nfind_package(skyfit 0.1 REQUIRED)\nadd_executable(app main.c)\nskyfit_generate(%s)\n' "$*" \
    >"$tmp/$name/CMakeLists.txt"
  # (CMake wraps its messages: the log's lines joined before the search)
  if cmake -S "$tmp/$name" -B "$tmp/$name/build" -DCMAKE_PREFIX_PATH="$tmp/prefix" >"$tmp/$name.log" 2>&1 ||
     ! tr -s ' \n' '  ' <"$tmp/$name.log" | grep -q "$want"; then
    echo "FAIL $name: configure did not stop with '$want'"; cat "$tmp/$name.log"; exit 1
  fi
  echo "ok   $name: configure stops with '$want'"
}
bad_configure misspelt "unknown arguments: PREFX;p" -- TARGET app PREFX p SCENE sky.json OUTPUT_DIR gen LANG c BASELINES naive
bad_configure misspelt_after_baselines "unknown argument PREFX after BASELINES" -- \
  TARGET app SCENE sky.json OUTPUT_DIR gen LANG c BASELINES naive chapman PREFX p
bad_configure misspelt_after_options "unknown argument PREFX after BUILD_OPTIONS" -- \
  TARGET app SCENE sky.json OUTPUT_DIR gen LANG c BUILD_OPTIONS --quick PREFX p
bad_configure unknown_baseline "BASELINES: unknown baseline 'bogus'" -- \
  TARGET app SCENE sky.json OUTPUT_DIR gen LANG c BASELINES naive,bogus
bad_configure empty_baselines "BASELINES needs a value" -- TARGET app SCENE sky.json OUTPUT_DIR gen LANG c BASELINES
sed -i 's/"atmosphere": *"[^"]*"/"atmosphere": "nope.json"/' "$tmp/consumer/sky.json"
grep -q '"nope.json"' "$tmp/consumer/sky.json" || { echo "FAIL the test could not point sky.json at nope.json"; exit 1; }
bad_configure missing_atmosphere "nope.json, which does not exist" -- \
  TARGET app SCENE sky.json OUTPUT_DIR gen LANG c BASELINES naive
bad_configure bad_name "NAME 'sky/x' must be letters, digits" -- \
  TARGET app SCENE sky.json OUTPUT_DIR gen LANG c NAME sky/x BASELINES naive
bad_configure no_target "TARGET nothing is not a target of this project" -- \
  TARGET nothing SCENE sky.json OUTPUT_DIR gen LANG c BASELINES naive
sed -i 's/"atmosphere": *"[^"]*"/"atmosphere": 5/' "$tmp/consumer/sky.json"
bad_configure atmosphere_number "atmosphere: expected a file path (a string), got NUMBER" -- \
  TARGET app SCENE sky.json OUTPUT_DIR gen LANG c BASELINES naive

# An INTERFACE library (the headers shared by everything linking it) and a
# custom target (a shader step) as targets: both had stopped configure
# with CMake's error. A shader step that uses the GLSL through
# OUTPUTS_VARIABLE and add_dependencies: one generation per build, also
# with -j4 on Makefiles (a command DEPENDing on the files alone had run
# the step twice at once).
mkdir -p "$tmp/kinds"
printf '{"viewer_altitude_km": [0, 2]}\n' >"$tmp/kinds/sky.json"
printf '#include "shared.h"\nint main(void) { return !(shared_naive_transmittance(0.0f, 1.0f).x > 0.5f); }\n' >"$tmp/kinds/main.c"
cat >"$tmp/kinds/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.19)
project(kinds C)
find_package(skyfit 0.1 REQUIRED)
add_library(sky_headers INTERFACE)
skyfit_generate(TARGET sky_headers SCENE sky.json OUTPUT_DIR gen NAME shared PREFIX shared LANG c BASELINES naive)
add_executable(app main.c)
target_link_libraries(app PRIVATE sky_headers m)
add_custom_target(shaders ALL)
skyfit_generate(TARGET shaders SCENE sky.json OUTPUT_DIR gen NAME shader LANG glsl BASELINES naive
                OUTPUTS_VARIABLE shader_files)
add_custom_command(OUTPUT shader.stamp COMMAND ${CMAKE_COMMAND} -E copy ${shader_files} shader.copy
                   COMMAND ${CMAKE_COMMAND} -E touch shader.stamp DEPENDS ${shader_files})
add_custom_target(shader_copy ALL DEPENDS shader.stamp)
add_dependencies(shader_copy shaders_skyfit_shader)
CMAKE
cmake -S "$tmp/kinds" -B "$tmp/kinds/build" -DCMAKE_PREFIX_PATH="$tmp/prefix" >"$tmp/kinds.log" 2>&1 ||
  { echo "FAIL INTERFACE library and custom target: configure failed"; cat "$tmp/kinds.log"; exit 1; }
out=$(cmake --build "$tmp/kinds/build" -j4 2>&1) || { echo "FAIL INTERFACE library and custom target: build failed"; echo "$out"; exit 1; }
"$tmp/kinds/build/app" && test -s "$tmp/kinds/build/shader.copy" ||
  { echo "FAIL the app through the INTERFACE library, or the shader step's copy"; exit 1; }
sleep 1; touch "$tmp/kinds/sky.json"
out=$(cmake --build "$tmp/kinds/build" -j4 2>&1)
[ "$(grep -c "skyfit: generating shader headers" <<<"$out")" -eq 1 ] ||
  { echo "FAIL the shader step's headers generated other than once"; echo "$out"; exit 1; }
echo "ok   an INTERFACE library and a custom target: headers on the linking app's path, the shader step's files once"
echo "cli_consumer: all checks passed"
