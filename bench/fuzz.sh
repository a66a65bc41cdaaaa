#!/usr/bin/env bash
# Runs every libFuzzer target of tests/fuzz/ (one per loader of user input:
# atmosphere, scene, weights, the eval CSV reader, EXR tables) for a bounded
# time and reports, per target, executions, executions per second, corpus
# size and findings (crashes, leaks, timeouts, out-of-memory). Each target
# is ASan+UBSan instrumented (cmake/SkyfitFuzz.cmake).
#
#   bench/fuzz.sh [--seconds N] [--only LOADER]... [--build DIR] [--no-install]
#
#   --seconds N   time per target (default 600)
#   --only L      run only fuzz_L (repeatable), e.g. --only scene
#   --build DIR   build folder (default build-fuzz next to this folder)
#   --deadline T  finish within T seconds of starting, build included: the
#                 time per target is cut to fit, and the report says so
#   --no-install  do not apt-get install clang if it is missing (exit 77)
#
# Exit status: 0 no findings, 1 a finding (its input is kept under
# DIR/fuzz-artifacts/LOADER/; copy it to tests/fuzz/regressions/LOADER/ once
# the loader is fixed), 2 bad usage, 77 clang with libFuzzer unavailable.
# The working corpus grows across runs in DIR/fuzz-corpus/LOADER/ (seeded
# from tests/fuzz/corpus/LOADER/). Runs with nice -n 10, one target at a
# time: the machine is shared.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
seconds=600
build=$here/build-fuzz
install=1
deadline=0
only=()
script_start=$(date +%s)
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds=${2:?--seconds needs a value}; shift 2 ;;
    --only) only+=("${2:?--only needs a loader name}"); shift 2 ;;
    --build) build=${2:?--build needs a folder}; shift 2 ;;
    --deadline) deadline=${2:?--deadline needs a value}; shift 2 ;;
    --no-install) install=0; shift ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "bench/fuzz.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
if ! [[ $seconds =~ ^[0-9]+$ ]] || [ "$seconds" -lt 1 ]; then
  echo "bench/fuzz.sh: --seconds: expected a whole number >= 1, got '$seconds'" >&2
  exit 2
fi
if ! [[ $deadline =~ ^[0-9]+$ ]]; then
  echo "bench/fuzz.sh: --deadline: expected a whole number of seconds, got '$deadline'" >&2
  exit 2
fi

# clang with libFuzzer: link a one-line fuzz target to be sure the runtime
# (libclang-rt-*-dev) is there, not just the compiler.
probe_libfuzzer() {
  command -v clang >/dev/null 2>&1 && command -v clang++ >/dev/null 2>&1 || return 1
  local dir
  dir=$(mktemp -d)
  printf '#include <stddef.h>\n#include <stdint.h>\nint LLVMFuzzerTestOneInput(const uint8_t *d, size_t n) { (void)d; (void)n; return 0; }\n' >"$dir/probe.c"
  local ok=0
  clang -fsanitize=fuzzer,address,undefined "$dir/probe.c" -o "$dir/probe" >/dev/null 2>&1 || ok=1
  rm -rf "$dir"
  return $ok
}
if ! probe_libfuzzer; then
  if [ $install -eq 0 ]; then
    echo "bench/fuzz.sh: clang with libFuzzer is not available (Debian: apt-get install clang libclang-rt-14-dev libomp-dev)" >&2
    exit 77
  fi
  echo "bench/fuzz.sh: installing clang, libclang-rt-14-dev, libomp-dev" >&2
  if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; else SUDO=; fi
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends \
    clang libclang-rt-14-dev libomp-dev >/dev/null
  probe_libfuzzer || { echo "bench/fuzz.sh: clang still cannot link a libFuzzer target" >&2; exit 77; }
fi

CC=clang CXX=clang++ nice -n 10 cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DSKYFIT_FUZZ=ON >/dev/null
nice -n 10 cmake --build "$build" -j2 --target fuzz_targets >/dev/null

if [ ${#only[@]} -eq 0 ]; then
  for src in "$here"/tests/fuzz/fuzz_*.c; do
    name=$(basename "$src" .c)
    only+=("${name#fuzz_}")
  done
fi

dict_for() {
  case "$1" in
    csv_points) echo "$here/tests/fuzz/csv.dict" ;;
    table_exr) echo "$here/tests/fuzz/exr.dict" ;;
    *) echo "$here/tests/fuzz/json.dict" ;;
  esac
}

if [ "$deadline" -gt 0 ]; then
  left=$(( deadline - ($(date +%s) - script_start) ))
  fit=$(( left / ${#only[@]} - 5 ))   # 5 s per target for start-up and merge
  if [ $fit -lt $seconds ]; then
    [ $fit -lt 5 ] && fit=5
    echo "bench/fuzz.sh: $left s left of the $deadline s deadline after the build: $fit s per target instead of $seconds"
    seconds=$fit
  fi
fi
echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg); $seconds s per target"
printf '%-18s %8s %12s %9s %7s %8s %6s %9s %5s\n' target seconds executions exec/s corpus crashes leaks timeouts ooms
findings=0
for loader in "${only[@]}"; do
  bin="$build/fuzz_$loader"
  if [ ! -x "$bin" ]; then echo "bench/fuzz.sh: no fuzz target fuzz_$loader" >&2; exit 2; fi
  seeds="$here/tests/fuzz/corpus/$loader"
  corpus="$build/fuzz-corpus/$loader"
  artifacts="$build/fuzz-artifacts/$loader"
  log="$build/fuzz-logs/$loader.log"
  mkdir -p "$corpus" "$artifacts" "$(dirname "$log")"
  rm -f "$artifacts"/*
  start=$(date +%s)
  status=0
  # stdin from /dev/null: an input naming /dev/stdin as a file reads EOF
  # instead of waiting. -timeout: one input running 10 s is a hang.
  ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=1" UBSAN_OPTIONS="print_stacktrace=1" \
    nice -n 10 "$bin" -max_total_time="$seconds" -timeout=10 -error_exitcode=1 -rss_limit_mb=2048 \
      -print_final_stats=1 -dict="$(dict_for "$loader")" -artifact_prefix="$artifacts/" \
      "$corpus" "$seeds" </dev/null >"$log" 2>&1 || status=$?
  elapsed=$(( $(date +%s) - start ))
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  n_corpus=$(find "$corpus" -type f | wc -l)
  count() { find "$artifacts" -type f -name "$1-*" | wc -l; }
  crashes=$(( $(count crash) + $(count deadly-signal) ))
  leaks=$(count leak)
  timeouts=$(count timeout)
  ooms=$(count oom)
  if [ $status -ne 0 ] && [ $((crashes + leaks + timeouts + ooms)) -eq 0 ]; then crashes=1; fi
  printf '%-18s %8s %12s %9s %7s %8s %6s %9s %5s\n' "fuzz_$loader" "$elapsed" "${execs:-?}" "${rate:-?}" \
    "$n_corpus" "$crashes" "$leaks" "$timeouts" "$ooms"
  if [ $status -ne 0 ]; then
    findings=1
    echo "  finding: exit $status; input(s): $(ls "$artifacts" | tr '\n' ' ')" 
    echo "  log: $log"
    grep -m 5 -E "ERROR|runtime error|fuzz invariant|SUMMARY" "$log" | sed 's/^/  /' || true
  fi
done
exit $findings
