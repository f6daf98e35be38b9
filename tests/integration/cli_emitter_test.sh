#!/usr/bin/env bash
# relight-render's run-time emitters from the command line, end to end: a
# hierarchical bake of the Cornell box, --list naming the surfaces, a floor
# panel that changes the frame, and the errors a user meets (off the plane,
# a bake without the hierarchy). Usage: cli_emitter_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bake="$build/baker/relight-bake" render="$build/runtime/relight-render"

"$bake" "$src/fixtures/cornell_box.toml" -o "$tmp/hier.rlb" --solver hierarchical -q
"$bake" "$src/fixtures/cornell_box.toml" -o "$tmp/dense.rlb" --solver dense -q

list=$("$render" "$tmp/hier.rlb" --list)
grep -q "places light sources on them" <<<"$list" || { echo "--list: no emitter line"; exit 1; }
grep -Eq "^  floor +x" <<<"$list" || { echo "--list: no floor surface"; exit 1; }

panel="floor:500:0.30,-0.20,0;0.50,-0.20,0;0.50,-0.05,0;0.30,-0.05,0"
"$render" "$tmp/hier.rlb" --width 160 --height 120 -o "$tmp/plain.png"
"$render" "$tmp/hier.rlb" --width 160 --height 120 --emitter "$panel" -o "$tmp/panel.png"
if cmp -s "$tmp/plain.png" "$tmp/panel.png"; then echo "the panel did not change the frame"; exit 1; fi

expect_error() {  # expect_error WHAT_IN_MESSAGE ARGS...
  local what=$1; shift
  local out rc=0
  out=$("$render" "$@" -o "$tmp/bad.png" 2>&1) || rc=$?
  [ "$rc" -eq 2 ] || { echo "expected exit 2, got $rc for: $*"; echo "$out"; exit 1; }
  grep -qi "$what" <<<"$out" || { echo "expected '$what' in: $out"; exit 1; }
}
expect_error "plane" "$tmp/hier.rlb" --emitter "floor:500:0.30,-0.20,0.05;0.50,-0.20,0.05;0.50,-0.05,0.05"
expect_error "hierarch" "$tmp/dense.rlb" --emitter "$panel"
expect_error "surface" "$tmp/hier.rlb" --emitter "no_such_surface:500:0,0,0;1,0,0;0,1,0"
echo "cli_emitter_test: ok"
