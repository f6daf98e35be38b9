#!/usr/bin/env bash
# relight-bake --reference --set X.zoom from the command line (issue 12): a
# zoom on a luminaire without one is an error naming the scene's line (exit
# 2, before any form factor); a zoom past the range says it is clamped.
# Usage: cli_reference_zoom_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bake="$build/baker/relight-bake"

rc=0
out=$("$bake" "$src/fixtures/cornell_box.toml" --reference --set spot.zoom=20 -o "$tmp/fixed" 2>&1) || rc=$?
[ "$rc" -eq 2 ] || { echo "expected exit 2, got $rc"; echo "$out"; exit 1; }
grep -q "cornell_box.toml:[0-9]*) has no zoom" <<<"$out" || { echo "no 'has no zoom' in: $out"; exit 1; }
[ ! -e "$tmp/fixed-vertices.csv" ] || { echo "a reference was written anyway"; exit 1; }

out=$("$bake" "$src/fixtures/cornell_zoom.toml" --reference --set spot.zoom=5 -o "$tmp/clamped" -q 2>&1)
grep -q "outside the zoom range 11..60 of 'spot'; the reference uses 11 degrees" <<<"$out" ||
  { echo "no clamp note in: $out"; exit 1; }
[ -s "$tmp/clamped-vertices.csv" ] || { echo "no reference written"; exit 1; }
echo "cli_reference_zoom_test: ok"
