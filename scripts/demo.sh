#!/usr/bin/env bash
# The README's main job. Until `skyfit build` exists (SPEC §11), it shows the
# reference quantities of the built-in atmosphere with `skyfit eval`.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
skyfit=build/skyfit

echo "== optical depth (km) and transmittance from the ground, built-in Earth atmosphere"
printf 'h_km,mu\n0,1\n0,0.5\n0,0.1\n0,0\n0,-0.001\n10,-0.05\n100,-0.2\n' | "$skyfit" eval optical_depth
printf 'h_km,mu\n0,1\n0,0.5\n0,0.1\n0,0\n10,-0.05\n100,-0.2\n' | "$skyfit" eval transmittance
echo
echo "== single scattering with phase functions: sun at noon and at sunset, viewer on the ground"
printf 'h_km,mu,mu_s,nu\n0,1,1,1\n0,0.5,1,0.5\n0,0.05,0.0,0.99\n0,0.05,0.0,-0.99\n' | "$skyfit" eval single_scattering --phase
