#!/usr/bin/env bash
# A short fuzzing run as part of the test suite: every libFuzzer target of
# tests/fuzz/ (atmosphere, scene and weights JSON, the eval CSV reader, EXR
# tables; ASan+UBSan instrumented) runs for SKYFIT_FUZZ_SECONDS (default
# 30) seconds through bench/fuzz.sh, which must report no crash, leak, hang
# or out-of-memory. The fuzz build lives next to the build under test
# (BUILD/fuzz-short) and is incremental; within ctest's 900 s limit the
# time per target is cut (and the log says so) when the build took long.
# Skipped (exit 77, ctest SKIP_RETURN_CODE) only when clang with libFuzzer
# is missing; scripts/setup.sh installs it.
set -uo pipefail
src="${SKYFIT_SOURCE_DIR:?SKYFIT_SOURCE_DIR must name the source folder}"
bin="${SKYFIT_BIN:?SKYFIT_BIN must name the skyfit binary}"
seconds="${SKYFIT_FUZZ_SECONDS:-30}"
build="$(cd "$(dirname "$bin")" && pwd)/fuzz-short"

bash "$src/bench/fuzz.sh" --build "$build" --seconds "$seconds" --deadline 600 --no-install
rc=$?
case $rc in
  0) echo "ok    every fuzz target ran with no finding" ;;
  77) echo "SKIPPED: clang with libFuzzer is not installed (apt-get install clang libclang-rt-14-dev libomp-dev, or run scripts/setup.sh)" ;;
  *) echo "FAIL: fuzzing found a problem (see above; the input is kept under $build/fuzz-artifacts/)" ;;
esac
exit $rc
