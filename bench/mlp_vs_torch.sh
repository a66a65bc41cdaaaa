#!/bin/bash
# skyfit's hand-written Adam against PyTorch (CPU), same architecture, data,
# batch size, epochs and initial weights, in one run (issue: neural sky):
#   bench/mlp_vs_torch.sh [--tables DIR] [--epochs-batch N] [--epochs-full N]
#                                        (transmittance; default 200 2000)
#                         [--scattering-epochs BATCHED FULL]   (default 2 10)
#                         [--csv-dir DIR]   (keep the dumped data sets there and
#                                            reuse them on the next run)
#                         [--repeat R]      (run each trainer R times, alternating,
#                                            and keep its fastest epoch time)
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
# An epoch of skyfit's transmittance network takes 0.1-0.4 ms, and one
# stall of the 2-core virtual machine's host (3-8 ms, measured in the first
# split batches) was a large part of a run of 20 epochs (7 ms) or of 200
# full-batch ones (25 ms). 200 and 2000 epochs make its runs 70-500 ms.
epochs_batch=200
epochs_full=2000
s_epochs_batch=2
s_epochs_full=10
csv_dir=
repeat=1
while [ $# -gt 0 ]; do
  case "$1" in
    --tables) tables=$2; shift 2 ;;
    --epochs-batch) epochs_batch=$2; shift 2 ;;
    --epochs-full) epochs_full=$2; shift 2 ;;
    --scattering-epochs) s_epochs_batch=$2; s_epochs_full=$3; shift 3 ;;
    --csv-dir) csv_dir=$2; shift 2 ;;
    --repeat) repeat=$2; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
if ! /usr/bin/python3 -c "import torch, numpy" 2>/dev/null; then
  echo "installing python3-torch (Debian) ..." >&2
  apt-get install -y python3-torch python3-numpy >/dev/null
fi
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target skyfit >"$build/bench-build.log" 2>&1 ||
  { cat "$build/bench-build.log" >&2; echo "build failed" >&2; exit 1; }
skyfit=$build/skyfit
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$tables"
echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg); timings are noisy on a shared machine"
if [ -n "$csv_dir" ]; then mkdir -p "$csv_dir"; data=$csv_dir; else data=$work; fi
[ -s "$data/t.csv" ] || "$skyfit" fit mlp-transmittance --tables "$tables" --dump-dataset "$data/t.csv" --quiet
[ -s "$data/s.csv" ] || "$skyfit" fit mlp-scattering --tables "$tables" --dump-dataset "$data/s.csv" --quiet
printf "%-14s %-6s %-6s %-10s %-8s %12s %12s %14s\n" data batch epochs trainer threads s/epoch cpu_s/epoch final_mse
field() { /usr/bin/python3 -c "import json,sys; print(json.load(sys.stdin)['$1'])"; }
smaller() { /usr/bin/python3 -c "print(min(float('$1'), float('$2')))"; }
for set in "t 2 2,4,3 $epochs_batch $epochs_full" "s 4 4,8,8,9 $s_epochs_batch $s_epochs_full"; do
  read -r name inputs layers e_batch e_full <<<"$set"
  "$skyfit" fit mlp --data "$data/$name.csv" --inputs "$inputs" --layers "$layers" --seed 1 --write-init "$work/$name-init.json"
  for batch in 1024 0; do
    epochs=$([ "$batch" = 0 ] && echo "$e_full" || echo "$e_batch")
    declare -A spe=() cpu=() mse=()
    # Repeats alternate the trainers; the fastest of each is kept (the
    # least disturbed by the other jobs of a shared machine).
    for rep in $(seq "$repeat"); do
      for threads in 1 2; do
        for trainer in torch sky; do
          if [ "$trainer" = torch ]; then
            out=$(/usr/bin/python3 "$here/bench/mlp_vs_torch.py" --data "$data/$name.csv" --inputs "$inputs" \
              --init "$work/$name-init.json" --epochs "$epochs" --batch "$batch" --threads "$threads")
          else
            out=$("$skyfit" fit mlp --data "$data/$name.csv" --inputs "$inputs" --layers "$layers" --seed 1 \
              --init-weights "$work/$name-init.json" --epochs "$epochs" --batch "$batch" --threads "$threads" --quiet)
          fi
          key=$trainer$threads
          w=$(echo "$out" | field seconds_per_epoch)
          c=$(echo "$out" | field cpu_seconds_per_epoch)
          mse[$key]=$(echo "$out" | field final_train_mse)
          spe[$key]=$([ -n "${spe[$key]:-}" ] && smaller "${spe[$key]}" "$w" || echo "$w")
          cpu[$key]=$([ -n "${cpu[$key]:-}" ] && smaller "${cpu[$key]}" "$c" || echo "$c")
        done
      done
    done
    for trainer in torch sky; do
      for threads in 1 2; do
        key=$trainer$threads
        printf "%-14s %-6s %-6s %-10s %-8s %12.5g %12.5g %14.6g\n" "$name($layers)" "$batch" "$epochs" \
          "$([ $trainer = torch ] && echo pytorch || echo skyfit)" "$threads" "${spe[$key]}" "${cpu[$key]}" "${mse[$key]}"
      done
    done
    for threads in 1 2; do
      /usr/bin/python3 -c "print('  speed-up per epoch, %s threads: wall %.1fx, cpu %.1fx; final mse skyfit/pytorch %.4f' % ($threads, ${spe[torch$threads]} / ${spe[sky$threads]}, ${cpu[torch$threads]} / ${cpu[sky$threads]}, ${mse[sky$threads]} / ${mse[torch$threads]}))"
    done
  done
done
