#!/usr/bin/env bash
# The main job, no hardware needed: installs and builds relight, bakes the
# living-room fixture, runs relightd on the replay script (the simulated
# console) to render relit frames and probes the floor grid. Everything lands in out/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
BUILD_DIR=${RELIGHT_BUILD_DIR:-build}
mkdir -p out/frames
# One bake, hierarchical: it also carries the quadtrees and links that
# run-time light sources need (docs/hierarchy.md "In relightd": accuracy,
# time and size against the dense solver's bake).
"$BUILD_DIR"/baker/relight-bake fixtures/living_room.toml -o out/living_room.rlb --solver hierarchical
"$BUILD_DIR"/runtime/relight-render out/living_room.rlb --list
# relightd, the real-time daemon, driven by the replay backend (the simulated
# console): 2 frames/s for the script's 12 s, then it exits. The patch adds a
# light panel on the wall ([[emitter]]) that the script switches on, moves and
# switches off again.
"$BUILD_DIR"/runtime/daemon/relightd out/living_room.rlb --patch fixtures/living_room_patch.toml \
    --replay fixtures/living_room_panel.replay --fps 2 \
    --exit-when-replay-done --png out/frames/living_room_%04d.png --sheet out/living_room_sheet.png
"$BUILD_DIR"/runtime/relight-probe out/living_room.rlb -o out/living_room_floor.csv --svg out/living_room_floor.svg
# A light source that appears on a surface at run time (Chandran & Srivastava's
# fractional emissivity): a 1 m x 1 m panel of 3000 cd/m^2 in the ceiling, the
# fixtures off, on the same bake.
"$BUILD_DIR"/runtime/relight-render out/living_room.rlb \
    --emitter "room/+z:3000:2.5,1.5,2.7;3.5,1.5,2.7;3.5,2.5,2.7;2.5,2.5,2.7" \
    --set ceiling_wide.dimmer=0 --set ceiling_spot.dimmer=0 --set corner_uplight.dimmer=0 \
    -o out/living_room_ceiling_panel.png
echo "relight: frames in out/frames/ (all of them on one page: out/living_room_sheet.png; a light panel on the wall from 8 s), floor illuminance in out/living_room_floor.csv and, as a false-colour plan, out/living_room_floor.svg; a run-time ceiling panel in out/living_room_ceiling_panel.png"
