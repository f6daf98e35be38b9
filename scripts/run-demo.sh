#!/usr/bin/env bash
# The main job, no hardware needed: installs and builds relight, bakes the
# living-room fixture, runs relightd on the replay script (the simulated
# console) to render relit frames and probes the floor grid. Everything lands in out/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
BUILD_DIR=${RELIGHT_BUILD_DIR:-build}
mkdir -p out/frames
"$BUILD_DIR"/baker/relight-bake fixtures/living_room.toml -o out/living_room.rlb
"$BUILD_DIR"/runtime/relight-render out/living_room.rlb --list
# relightd, the real-time daemon, driven by the replay backend (the simulated
# console): 2 frames/s for the script's 7 s, then it exits.
"$BUILD_DIR"/runtime/daemon/relightd out/living_room.rlb --replay fixtures/living_room.replay --fps 2 \
    --exit-when-replay-done --png out/frames/living_room_%04d.png --sheet out/living_room_sheet.png
"$BUILD_DIR"/runtime/relight-probe out/living_room.rlb -o out/living_room_floor.csv --svg out/living_room_floor.svg
echo "relight: frames in out/frames/ (all of them on one page: out/living_room_sheet.png), floor illuminance in out/living_room_floor.csv and, as a false-colour plan, out/living_room_floor.svg"
