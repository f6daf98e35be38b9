#!/usr/bin/env bash
# The stage show (issue 12): builds relight if needed, bakes the 48-head
# theatre (fixtures/stage.toml) and plays its recorded console show
# (fixtures/stage.dmxrec, 44 DMX frames/s on two universes, patched by
# fixtures/stage.dmx.toml) through relightd in script time, writing every
# frame to out/stage_frames/. No console, olad or network needed: the
# recording is the console.
#
#   scripts/run-stage.sh                  # bake (if the scene changed) and play
#   STAGE_FPS=10 scripts/run-stage.sh     # fewer frames (default 44: one per DMX frame)
#   STAGE_PATCH_SIZE=0.2 scripts/run-stage.sh   # a finer mesh (>= 16k vertices)
#
# Exit status: relightd's, or 2 when this relightd cannot replay DMX yet.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${RELIGHT_BUILD_DIR:-build}
RELIGHTD="$BUILD_DIR"/runtime/daemon/relightd
# A fresh machine: install and build everything (as run-demo.sh). A configured
# build: bring just the two tools up to date.
if [ -f "$BUILD_DIR"/CMakeCache.txt ]; then
  cmake --build "$BUILD_DIR" -j"$(nproc)" --target relight-bake relightd > /dev/null
else
  scripts/setup.sh
fi
BAKE=out/stage.rlb
FPS=${STAGE_FPS:-44}

# Checked before the (minutes-long) bake, so a missing feature says so at once.
if ! "$RELIGHTD" --help 2>&1 | grep -q -- '--dmx-replay'; then
  echo "run-stage: $RELIGHTD has no --dmx-replay option yet: it cannot play the DMX recording" >&2
  echo "run-stage: fixtures/stage.dmxrec (needs relightd's DMX replay input, issue 12)" >&2
  exit 2
fi

mkdir -p out/stage_frames
# Rebake only when the bake is missing or older than the scene.
bake_args=()
[ -n "${STAGE_PATCH_SIZE:-}" ] && bake_args+=(--patch-size "$STAGE_PATCH_SIZE")
if [ ! -f "$BAKE" ] || [ fixtures/stage.toml -nt "$BAKE" ] || [ ${#bake_args[@]} -gt 0 ]; then
  "$BUILD_DIR"/baker/relight-bake fixtures/stage.toml -o "$BAKE" "${bake_args[@]}"
fi
rm -f out/stage_frames/f_*.png
"$RELIGHTD" "$BAKE" --dmx fixtures/stage.dmx.toml --dmx-replay fixtures/stage.dmxrec \
    --script-time --exit-when-replay-done --fps "$FPS" --png out/stage_frames/f_%05d.png
echo "run-stage: $(ls out/stage_frames | wc -l) frames in out/stage_frames/"
