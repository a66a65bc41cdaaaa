#!/bin/bash
# skyfit's hand-written Adam against PyTorch (CPU), same architecture, data,
# batch size, epochs and initial weights, in one run (issue: neural sky):
#   bench/mlp_vs_torch.sh [--tables DIR] [--epochs-batch N] [--epochs-full N]
#                         [--scattering-epochs BATCHED FULL]   (default 2 10)
# Data: the transmittance (2-4-3) and scattering (4-8-8-9) training sets,
# dumped with --dump-dataset from the tables in DIR (computed there if
# missing; minutes). Installs Debian's python3-torch if it is missing.
# Prints, per data set and batch size (1024 and full batch), seconds per
# epoch and final training MSE for PyTorch (1 and 2 threads) and skyfit
# (1 and 2 threads), and the per-epoch speed-up, in wall-clock and in
# process CPU time (the CPU time is the fairer figure on a loaded machine).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$here/build-bench}
tables=/tmp/skyfit-bench-tables
epochs_batch=20
epochs_full=200
s_epochs_batch=2
s_epochs_full=10
while [ $# -gt 0 ]; do
  case "$1" in
    --tables) tables=$2; shift 2 ;;
    --epochs-batch) epochs_batch=$2; shift 2 ;;
    --epochs-full) epochs_full=$2; shift 2 ;;
    --scattering-epochs) s_epochs_batch=$2; s_epochs_full=$3; shift 3 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
if ! /usr/bin/python3 -c "import torch, numpy" 2>/dev/null; then
  echo "installing python3-torch (Debian) ..." >&2
  apt-get install -y python3-torch python3-numpy >/dev/null
fi
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target skyfit >/dev/null
skyfit=$build/skyfit
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$tables"
echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg); timings are noisy on a shared machine"
"$skyfit" fit mlp-transmittance --tables "$tables" --dump-dataset "$work/t.csv" --quiet
"$skyfit" fit mlp-scattering --tables "$tables" --dump-dataset "$work/s.csv" --quiet
printf "%-14s %-6s %-6s %-10s %-8s %12s %12s %14s\n" data batch epochs trainer threads s/epoch cpu_s/epoch final_mse
for set in "t 2 2,4,3 $epochs_batch $epochs_full" "s 4 4,8,8,9 $s_epochs_batch $s_epochs_full"; do
  read -r name inputs layers e_batch e_full <<<"$set"
  "$skyfit" fit mlp --data "$work/$name.csv" --inputs "$inputs" --layers "$layers" --seed 1 --write-init "$work/$name-init.json"
  for batch in 1024 0; do
    epochs=$([ "$batch" = 0 ] && echo "$e_full" || echo "$e_batch")
    declare -A spe=() cpu=()
    for threads in 1 2; do
      out=$(/usr/bin/python3 "$here/bench/mlp_vs_torch.py" --data "$work/$name.csv" --inputs "$inputs" \
        --init "$work/$name-init.json" --epochs "$epochs" --batch "$batch" --threads "$threads")
      spe[torch$threads]=$(echo "$out" | /usr/bin/python3 -c 'import json,sys; print(json.load(sys.stdin)["seconds_per_epoch"])')
      cpu[torch$threads]=$(echo "$out" | /usr/bin/python3 -c 'import json,sys; print(json.load(sys.stdin)["cpu_seconds_per_epoch"])')
      mse=$(echo "$out" | /usr/bin/python3 -c 'import json,sys; print(json.load(sys.stdin)["final_train_mse"])')
      printf "%-14s %-6s %-6s %-10s %-8s %12.5g %12.5g %14.6g\n" "$name($layers)" "$batch" "$epochs" pytorch "$threads" "${spe[torch$threads]}" "${cpu[torch$threads]}" "$mse"
    done
    for threads in 1 2; do
      out=$("$skyfit" fit mlp --data "$work/$name.csv" --inputs "$inputs" --layers "$layers" --seed 1 \
        --init-weights "$work/$name-init.json" --epochs "$epochs" --batch "$batch" --threads "$threads" --quiet)
      spe[sky$threads]=$(echo "$out" | /usr/bin/python3 -c 'import json,sys; print(json.load(sys.stdin)["seconds_per_epoch"])')
      cpu[sky$threads]=$(echo "$out" | /usr/bin/python3 -c 'import json,sys; print(json.load(sys.stdin)["cpu_seconds_per_epoch"])')
      mse=$(echo "$out" | /usr/bin/python3 -c 'import json,sys; print(json.load(sys.stdin)["final_train_mse"])')
      printf "%-14s %-6s %-6s %-10s %-8s %12.5g %12.5g %14.6g\n" "$name($layers)" "$batch" "$epochs" skyfit "$threads" "${spe[sky$threads]}" "${cpu[sky$threads]}" "$mse"
    done
    for threads in 1 2; do
      /usr/bin/python3 -c "print('  speed-up per epoch, %s threads: wall %.1fx, cpu %.1fx' % ($threads, ${spe[torch$threads]} / ${spe[sky$threads]}, ${cpu[torch$threads]} / ${cpu[sky$threads]}))"
    done
  done
done
