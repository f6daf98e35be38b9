#!/usr/bin/env bash
# The sanitizer build (issue 17, docs/security.md): configures the `asan`
# preset (CMakePresets.json: ASan + UBSan, -fno-sanitize-recover=all) into
# build-asan/, builds it and runs the test suite there with the suppressions
# in tests/sanitizers/ (system libraries only, each with its reason).
#
#   scripts/sanitize-test.sh            the whole suite
#   scripts/sanitize-test.sh -R REGEX   only the matching tests (ctest -R)
#
# RELIGHT_JOBS=N builds and tests on N cores (default: all).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
JOBS=${RELIGHT_JOBS:-$(nproc)}
start=$(date +%s)

LAUNCHER=()
command -v ccache > /dev/null && LAUNCHER=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
cmake --preset asan "${LAUNCHER[@]}" > /dev/null

# The same options the preset gives ctest, for the build step too:
# gtest_discover_tests runs every test binary once while building.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1"
export LSAN_OPTIONS="suppressions=$ROOT/tests/sanitizers/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="suppressions=$ROOT/tests/sanitizers/ubsan.supp:print_stacktrace=1:halt_on_error=1"
cmake --build build-asan -j"$JOBS"
built=$(date +%s)
echo "sanitize-test: built in $((built - start)) s"

ctest --preset asan -j"$JOBS" "$@"
echo "sanitize-test: tests ran in $(( $(date +%s) - built )) s"
