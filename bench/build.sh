#!/bin/bash
# The main job's time budget (issue 8): `skyfit build` on the built-in
# atmosphere and scene from nothing (empty output folder: tables, fits,
# timings all computed), then again with nothing changed (everything from
# DIR/cache). Prints wall-clock and CPU seconds (user + sys, all threads) of
# each run, the build's own stage times, and whether the second run's
# metrics.json is byte-identical to the first's (timings come from the cache).
#
#   bash bench/build.sh [--mars] [--keep DIR] [extra skyfit build options]
#
# --mars builds examples/scenes/mars.json (the dusty Mars-like atmosphere of
# examples/atmospheres/) instead of the default scene. On a machine shared
# with other jobs, wall time exceeds CPU time / threads; say so with the
# figures. Needs a built skyfit (SKYFIT_BIN, or build/skyfit).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${SKYFIT_BIN:-$root/build/skyfit}
[ -x "$bin" ] || { echo "bench/build.sh: no skyfit binary at $bin (build first, or set SKYFIT_BIN)" >&2; exit 2; }
scene=()
out=""
extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --mars) scene=("$root/examples/scenes/mars.json"); shift ;;
    --keep) out=$2; shift 2 ;;
    *) extra+=("$1"); shift ;;
  esac
done
if [ -z "$out" ]; then
  out=$(mktemp -d)
  trap 'rm -rf "$out"' EXIT
fi
mkdir -p "$out"
rm -rf "$out/build"
echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo "scene: ${scene[*]:-built-in default}"
run() {
  local label=$1 log=$2
  local TIMEFORMAT="%R %U %S"
  { time "$bin" build "${scene[@]}" --out "$out/build" --quiet "${extra[@]}" > "$log" 2>&1; } 2> "$log.time" \
    || { cat "$log"; exit 1; }
  read -r wall user sys < "$log.time"
  echo "$label: wall $wall s, CPU $(awk -v u="$user" -v s="$sys" 'BEGIN {printf "%.2f", u + s}') s (user $user + sys $sys, all threads)"
  grep -E "tables .* from the cache|chose|no model" "$log" | sed 's/^/    /'
}
run "fresh build " "$out/fresh.log"
cp "$out/build/metrics.json" "$out/metrics-fresh.json"
run "cached build" "$out/cached.log"
if cmp -s "$out/metrics-fresh.json" "$out/build/metrics.json"; then
  echo "metrics.json: byte-identical between the two runs"
else
  echo "metrics.json: DIFFERS between the two runs"
fi
