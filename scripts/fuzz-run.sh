#!/usr/bin/env bash
# Runs every libFuzzer target of tests/fuzz for a fixed time (issue 17,
# docs/security.md "Fuzzing"). Installs clang and its runtime libraries if
# missing, builds the fuzz targets of the `asan` preset (clang, ASan + UBSan,
# libFuzzer; the tree scripts/sanitize-test.sh tests) into build-asan/, then
# runs the targets two at a time from their checked-in corpora. New inputs go
# to a scratch folder, never into the tree. A crash, leak, timeout (> 10 s)
# or out-of-memory (> 2 GB) fails the run and leaves the input in
# out/fuzz/<target>/: fix the bug, then add that file to
# tests/fuzz/corpus/<target>/ as a regression case.
#
#   scripts/fuzz-run.sh [SECONDS_PER_TARGET] [TARGET...]   (default 30 s, all)
#   scripts/fuzz-run.sh --campaign [TARGET...]
#       issue 17's bar: each target until 10 million executions or an hour,
#       whichever comes first, with an input slower than 1 s counted as a
#       failure; results in out/fuzz-campaign/ (summary.txt: one line a target
#       with executions, coverage and seconds), kept apart from CI's out/fuzz/.
#
# RELIGHT_JOBS=N builds on N cores and runs N targets at once (default: all cores).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
RUNS=-1        # -runs=-1: no limit on executions, only on time
TIMEOUT_S=10   # an input slower than this is a finding
OUT_NAME=fuzz
if [ "${1:-}" = "--campaign" ]; then
  shift
  RUNS=10000000 TIMEOUT_S=1 OUT_NAME=fuzz-campaign
  SECONDS_EACH=3600
else
  SECONDS_EACH=${1:-30}
  shift || true
fi
JOBS=${RELIGHT_JOBS:-$(nproc)}
start=$(date +%s)

source scripts/need-clang.sh
need_clang

LAUNCHER=()
command -v ccache > /dev/null && LAUNCHER=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
cmake --preset asan "${LAUNCHER[@]}" > /dev/null
cmake --build build-asan -j"$JOBS" --target fuzzers
built=$(date +%s)
echo "fuzz-run: built in $((built - start)) s; ${SECONDS_EACH} s per target, $JOBS at a time"

OUT="$ROOT/out/$OUT_NAME"
# CI's short runs start clean; a campaign keeps the other targets' results
# (it is often run a few targets at a time) and its history.txt.
[ "$OUT_NAME" = fuzz ] && rm -rf "$OUT"
mkdir -p "$OUT"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"

run_one() {  # name|binary|corpus dirs (colon-separated)|dictionary
  local name bin corpus dict
  IFS='|' read -r name bin corpus dict <<< "$1"
  local dir="$OUT/$name"
  rm -rf "$dir"
  mkdir -p "$dir/new"
  local args=(-max_total_time="$SECONDS_EACH" -runs="$RUNS" -timeout="$TIMEOUT_S" -rss_limit_mb=2048 -max_len=65536
              -print_final_stats=1 -artifact_prefix="$dir/")
  [ -n "$dict" ] && args+=(-dict="$dict")
  IFS=':' read -r -a seeds <<< "$corpus"
  local t0=$SECONDS
  if "$bin" "${args[@]}" "$dir/new" "${seeds[@]}" > "$dir/log" 2>&1; then
    local execs cov
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$dir/log" | tail -1)
    cov=$(grep -o 'cov: [0-9]*' "$dir/log" | tail -1 | cut -d' ' -f2)
    echo "fuzz-run: $name ok: ${execs:-?} executions, coverage ${cov:-?} edges, $((SECONDS - t0)) s"
  else
    echo "fuzz-run: $name FAILED (log and input in $dir):"
    grep -E 'ERROR|SUMMARY|runtime error|Test unit written' "$dir/log" | head -8
    return 1
  fi
}
export -f run_one
export OUT SECONDS_EACH RUNS TIMEOUT_S

list="$ROOT/build-asan/fuzzers.txt"
if [ $# -gt 0 ]; then
  pattern=$(printf '^%s|\|' "$@")
  grep -e "${pattern%\\|}" "$list" > "$OUT/selected.txt"
  list="$OUT/selected.txt"
fi
status=0
grep -v '^$' "$list" | xargs -d '\n' -P "$JOBS" -I{} bash -c 'run_one "$1"' _ {} | tee "$OUT/summary.txt" || status=1
sed "s/^/$(date -u +%FT%TZ) /" "$OUT/summary.txt" >> "$OUT/history.txt"
passed=$(grep -c ' ok: ' "$OUT/summary.txt" || true)
failed=$(grep -c ' FAILED ' "$OUT/summary.txt" || true)
echo "fuzz-run: done in $(( $(date +%s) - start )) s"
echo "fuzz: $passed passed, $failed failed"
exit $status
