#!/usr/bin/env bash
# The README's main job: set up, build, then `skyfit build` on the built-in
# default atmosphere and scene (SPEC §11): sample the reference tables
# (cached in skyfit-out/cache), fit and measure every model, select the
# cheapest within budget per quantity, emit skyfit-out/sky.h and sky.glsl,
# and write skyfit-out/report.html (+ report.md, metrics.json, views/).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
build/skyfit build --out skyfit-out "$@"
