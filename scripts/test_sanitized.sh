#!/usr/bin/env bash
# The whole ctest suite built with AddressSanitizer + UndefinedBehaviorSanitizer
# (cmake -DSKYFIT_SANITIZE=ON, cmake/SkyfitSanitize.cmake) in its own build
# folder. Any finding — memory error, leak, undefined behaviour — aborts the
# test that hit it, so the run passes only with zero findings. CI runs it
# after scripts/test.sh (which installs the packages).
#   scripts/test_sanitized.sh [ctest arguments, e.g. -R atmosphere]
# BUILD names the build folder (default build-asan); CC picks the compiler
# (default cc, i.e. gcc on Debian; clang works too); EXCLUDE, a regular
# expression, leaves more tests out (ctest keeps only the last -E given, so
# pass exclusions here, not as -E). JOBS: parallel builds and tests.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$here/build-asan}
jobs=${JOBS:-$(nproc)}

# RelWithDebInfo: optimised like the real build (so UB that only bites when
# optimised still shows) but with line numbers in the reports.
CC=${CC:-cc} CXX=${CXX:-c++} cmake -S "$here" -B "$build" \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSKYFIT_SANITIZE=ON >/dev/null
cmake --build "$build" -j"$jobs"

supp="$here/tests/sanitizer"
# detect_leaks: leaks are findings too. abort_on_error + halt_on_error: the
# first report ends the process with a nonzero status. The suppression
# files hold third-party code only; each entry says why.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:halt_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1:strict_init_order=1:detect_invalid_pointer_pairs=0:allocator_may_return_null=1"
export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$supp/ubsan.supp"

# The float32 sweep's 1e6 points per function (its accuracy contract) are
# checked by the normal suite; here the same code paths, every function,
# atmosphere and hard-case class, run at 1e5 points, which under ASan takes
# minutes instead of over the 900 s test timeout.
export SKYFIT_SWEEP_POINTS=${SKYFIT_SWEEP_POINTS:-100000}

start=$(date +%s)
status=0
# cli_fuzz_short is left out: its fuzz targets are ASan+UBSan builds of
# their own (cmake/SkyfitFuzz.cmake), already run by scripts/test.sh.
exclude='^cli_fuzz_short$'${EXCLUDE:+|$EXCLUDE}
ctest --test-dir "$build" --output-on-failure -j"$jobs" -E "$exclude" "$@" || status=$?
echo "sanitized suite: $(( $(date +%s) - start )) s (ASan+UBSan, $jobs jobs, $(nproc) cores)"
exit $status
