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

cp -r "$SKYFIT_SOURCE_DIR/examples/consumer" "$tmp/consumer"
cmake -S "$tmp/consumer" -B "$tmp/consumer/build" -DCMAKE_PREFIX_PATH="$tmp/prefix" >/dev/null
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
echo "cli_consumer: all checks passed"
