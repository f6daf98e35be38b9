#!/usr/bin/env bash
# relight-probe --emitter end to end (issue 15 item 4): a ceiling panel in
# the Cornell box, the spot off, lights the floor grid (E_total rises, the
# luminaires' E_direct stays 0), the SVG plan is written, and a dense bake
# (no hierarchy) is refused. Usage: cli_probe_emitter_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bake="$build/baker/relight-bake" probe="$build/runtime/relight-probe"

"$bake" "$src/fixtures/cornell_box.toml" -o "$tmp/hier.rlb" --solver hierarchical -q
"$bake" "$src/fixtures/cornell_box.toml" -o "$tmp/dense.rlb" --solver dense -q

panel="ceiling:2000:0.20,-0.22,0.5488;0.36,-0.20,0.5488;0.35,-0.36,0.5488;0.21,-0.34,0.5488"
"$probe" "$tmp/hier.rlb" --set spot.dimmer=0 -o "$tmp/dark.csv" >/dev/null
"$probe" "$tmp/hier.rlb" --set spot.dimmer=0 --emitter "$panel" -o "$tmp/panel.csv" --svg "$tmp/panel.svg" >/dev/null
grep -q "emitter ceiling:2000" "$tmp/panel.svg" || { echo "the SVG does not name the emitter"; exit 1; }
# Columns: grid,point,x_m,y_m,z_m,E_total_lux,E_direct_lux
dark_max=$(awk -F, 'NR > 1 && $6 > m { m = $6 } END { print m + 0 }' "$tmp/dark.csv")
panel_max=$(awk -F, 'NR > 1 && $6 > m { m = $6 } END { print m + 0 }' "$tmp/panel.csv")
direct_max=$(awk -F, 'NR > 1 && $7 > m { m = $7 } END { print m + 0 }' "$tmp/panel.csv")
awk -v d="$dark_max" -v p="$panel_max" -v x="$direct_max" 'BEGIN { exit !(d == 0 && p > 10 && x == 0) }' ||
  { echo "expected dark 0, panel > 10 lux, direct 0: got $dark_max, $panel_max, $direct_max"; exit 1; }

out=$("$probe" "$tmp/dense.rlb" --emitter "$panel" 2>&1) && { echo "a dense bake took an emitter"; exit 1; }
grep -qi "hierarch" <<<"$out" || { echo "expected 'hierarchy' in: $out"; exit 1; }
echo "cli_probe_emitter_test: ok (floor grid peak $panel_max lux from the panel)"
