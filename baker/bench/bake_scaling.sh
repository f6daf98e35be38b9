#!/usr/bin/env bash
# Bake time and peak memory against patch count, hierarchical and dense
# solvers, as timed CLI runs of relight-bake (one process per run, so peak
# memory is that run's own). Prints a Markdown table for docs/performance.md;
# every figure also appears as a ratio against a baseline of the same run:
# the dense solver at the same patch count where it is feasible, and the
# hierarchical solver's smallest mesh (with the patch-count ratio beside it,
# so near-linear scaling reads as time ratio ~ patch ratio).
#
#   baker/bench/bake_scaling.sh [BUILD_DIR] [SCENE]
#   BUILD_DIR defaults to build/, SCENE to fixtures/living_room.toml.
#   SIZES="0.38 0.19 0.092 0.046" (patch edges, m) and DENSE_MAX=6000 (largest
#   patch count the dense solver is run at) may be set in the environment.
set -euo pipefail
cd "$(dirname "$0")/../.."

BUILD_DIR=${1:-build}
SCENE=${2:-fixtures/living_room.toml}
SIZES=${SIZES:-"0.38 0.19 0.092 0.046"}
DENSE_MAX=${DENSE_MAX:-6000}
BAKE="$BUILD_DIR/baker/relight-bake"
TIME=/usr/bin/time
[ -x "$BAKE" ] || { echo "bake_scaling: no $BAKE (build first)" >&2; exit 2; }
[ -x "$TIME" ] || { echo "bake_scaling: needs GNU time at $TIME (apt-get install time)" >&2; exit 2; }
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT

# run SOLVER SIZE -> "patches links sweeps wall_s cpu_s peak_mb"
run() {
  local solver=$1 size=$2 log="$OUT/$1-$2.log"
  "$TIME" -f "TIME %e %U %S %M" "$BAKE" "$SCENE" -o "$OUT/bake.rlb" --solver "$solver" \
    --patch-size "$size" > "$log" 2>&1
  awk '
    /^relight-bake:/ {
      for (i = 1; i <= NF; ++i) {
        if ($(i + 1) ~ /^patches,?$/) patches = $i
        if ($(i + 1) ~ /^links,?$/) links = $i
        if ($(i + 1) ~ /^sweeps/) sweeps = $i
      }
      sub(/^\(/, "", patches)
    }
    /^TIME / { wall = $2; cpu = $3 + $4; mb = $5 / 1024 }
    END {
      if (links == "") links = "-"
      if (sweeps == "") sweeps = "-"
      printf "%s %s %s %.2f %.2f %.0f\n", patches, links, sweeps, wall, cpu, mb
    }' "$log"
}

echo "| patches | solver | links | sweeps | wall s | CPU s | peak MB | time / dense | memory / dense | time / smallest | patches / smallest |"
echo "| ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
base_wall="" base_patches=""
for size in $SIZES; do
  read -r patches links sweeps wall cpu mb < <(run hierarchical "$size")
  if [ -z "$base_wall" ]; then base_wall=$wall; base_patches=$patches; fi
  dense_time="-" dense_mem="-"
  if [ "$patches" -le "$DENSE_MAX" ]; then
    read -r dp _ _ dwall dcpu dmb < <(run dense "$size")
    echo "| $dp | dense | - | - | $dwall | $dcpu | $dmb | 1 | 1 | - | - |"
    dense_time=$(awk -v a="$wall" -v b="$dwall" 'BEGIN { printf "%.3f", a / b }')
    dense_mem=$(awk -v a="$mb" -v b="$dmb" 'BEGIN { printf "%.3f", a / b }')
  fi
  scale_t=$(awk -v a="$wall" -v b="$base_wall" 'BEGIN { printf "%.2f", a / b }')
  scale_n=$(awk -v a="$patches" -v b="$base_patches" 'BEGIN { printf "%.2f", a / b }')
  echo "| $patches | hierarchical | $links | $sweeps | $wall | $cpu | $mb | $dense_time | $dense_mem | $scale_t | $scale_n |"
done
