#!/usr/bin/env bash
# The sanitizer build (issue 17, docs/security.md): configures the `asan`
# preset (CMakePresets.json: clang, ASan + UBSan, -fno-sanitize-recover=all,
# the fuzz targets as libFuzzer binaries) into build-asan/, builds it and runs
# tests there with the suppressions in tests/sanitizers/ (system libraries
# only, each with its reason). Installs clang if it is missing.
#
#   scripts/sanitize-test.sh             the whole suite but the accuracy bars of
#                                        tests/sanitizers/normal-build-only.txt (what CI runs)
#   scripts/sanitize-test.sh --all       the whole suite, those too (an hour more on 2 cores)
#   scripts/sanitize-test.sh --inputs    the readers of outside input (bake file,
#                                        patches, fixture types, replay, Modbus,
#                                        DMX, and the baker's: IES, LDT, OBJ,
#                                        scene) and their fuzz corpora: a quick check
#   scripts/sanitize-test.sh [--inputs] -R REGEX   ... only tests matching REGEX
#
# RELIGHT_JOBS=N builds and tests on N cores (default: all).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
JOBS=${RELIGHT_JOBS:-$(nproc)}
start=$(date +%s)
source scripts/need-clang.sh
need_clang

# Test binaries (and fuzz corpus replays) of --inputs.
INPUT_TARGETS=(bake_io_test replay_plan_test hal_core_test hal_replay_test hal_modbus_test hal_modbus_abuse_test hal_dmx_test
               hal_config_file_test bounded_read_test
               bake_fuzz bake_sections_fuzz patch_fuzz dmx_patch_fuzz qxf_fuzz fixture_type_toml_fuzz
               replay_fuzz param_text_fuzz modbus_request_fuzz dmx_frame_fuzz ies_fuzz ldt_fuzz obj_fuzz scene_fuzz)
BUILD_ARGS=()
CTEST_ARGS=()
EXCLUDE_LIST=tests/sanitizers/normal-build-only.txt
if [ "${1:-}" = "--all" ]; then
  shift
  EXCLUDE_LIST=
elif [ "${1:-}" = "--inputs" ]; then
  EXCLUDE_LIST=
  shift
  BUILD_ARGS=(--target "${INPUT_TARGETS[@]}")
  labels=$(IFS='|'; echo "${INPUT_TARGETS[*]}")
  CTEST_ARGS=(-L "^($labels)\$")
fi

LAUNCHER=()
command -v ccache > /dev/null && LAUNCHER=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
cmake --preset asan "${LAUNCHER[@]}" > /dev/null

# The same options the preset gives ctest, for the build step too:
# gtest_discover_tests runs every test binary once while building.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1"
export LSAN_OPTIONS="suppressions=$ROOT/tests/sanitizers/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="suppressions=$ROOT/tests/sanitizers/ubsan.supp:print_stacktrace=1:halt_on_error=1"
cmake --build build-asan -j"$JOBS" "${BUILD_ARGS[@]}"
built=$(date +%s)
echo "sanitize-test: built in $((built - start)) s"

# The whole suite leaves the list's tests to the normal build; each line must
# still name a test, or the list has gone stale.
if [ -n "$EXCLUDE_LIST" ]; then
  patterns=()
  while IFS= read -r line; do
    re=$(printf '%s' "${line%%#*}" | tr -d '[:space:]')
    [ -z "$re" ] && continue
    # (ctest's listing captured first: grep -q closing the pipe early would
    # fail ctest with SIGPIPE under pipefail.)
    listing=$(cd build-asan && ctest -N -R "$re")
    if ! grep -q 'Test *#' <<< "$listing"; then
      echo "sanitize-test: $EXCLUDE_LIST: '$re' matches no test (renamed? update the list)" >&2
      exit 1
    fi
    patterns+=("$re")
  done < "$EXCLUDE_LIST"
  exclude=$(IFS='|'; echo "${patterns[*]}")
  CTEST_ARGS+=(-E "$exclude")
  echo "sanitize-test: ${#patterns[@]} accuracy-bar patterns of $EXCLUDE_LIST run in the normal build only"
fi

ctest --preset asan -j"$JOBS" "${CTEST_ARGS[@]}" "$@"
echo "sanitize-test: tests ran in $(( $(date +%s) - built )) s"
