#!/usr/bin/env bash
# Plays the living room's replay script through relight-replay-hash on every
# recombination path and target at hand and compares the per-frame hashes
# (vertex luminances before tone mapping, and 8-bit colours):
#   x86-64 AVX2 (if the CPU has it), x86-64 scalar (RELIGHT_FORCE_SCALAR=1),
#   aarch64 under qemu-aarch64 (if --cross-tool exists and qemu is installed).
# Last line: "N frames compared, D differ". Exit 0 when nothing differs, 1
# when something does, 77 (ctest's skip) when aarch64 could not be run but
# x86-64's paths agree.
#   scripts/compare-replay-hashes.sh --bake BAKE --host-tool build/runtime/relight-replay-hash \
#       [--cross-tool build-aarch64/runtime/relight-replay-hash] [--fps 10] [--keep DIR]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BAKE="" HOST_TOOL="" CROSS_TOOL="" FPS=10 KEEP=""
SCRIPT="$ROOT/fixtures/living_room.replay"
# A surface emitter on the ceiling (the fixed-point hierarchical solve is
# compared too; the bake must have a hierarchy).
EMITTER="room/+z:250,200,160:2.6,1.9,2.7;3.4,1.9,2.7;3.4,2.5,2.7;2.6,2.5,2.7"
while [ $# -gt 0 ]; do
  case $1 in
    --bake) BAKE=$2; shift 2 ;;
    --host-tool) HOST_TOOL=$2; shift 2 ;;
    --cross-tool) CROSS_TOOL=$2; shift 2 ;;
    --fps) FPS=$2; shift 2 ;;
    --script) SCRIPT=$2; shift 2 ;;
    --keep) KEEP=$2; shift 2 ;;
    *) echo "compare-replay-hashes: unknown argument $1" >&2; exit 2 ;;
  esac
done
[ -n "$BAKE" ] && [ -n "$HOST_TOOL" ] || { echo "usage: $0 --bake BAKE --host-tool TOOL [--cross-tool TOOL]" >&2; exit 2; }
[ -f "$BAKE" ] || { echo "compare-replay-hashes: no bake at $BAKE" >&2; exit 2; }

OUT=${KEEP:-$(mktemp -d)}
mkdir -p "$OUT"
[ -n "$KEEP" ] || trap 'rm -rf "$OUT"' EXIT
ARGS=("$BAKE" "$SCRIPT" --fps "$FPS" --emitter "$EMITTER")

run() {  # name, command...
  local name=$1; shift
  "$@" "${ARGS[@]}" > "$OUT/$name.txt" 2> "$OUT/$name.err" || { echo "$name: failed:"; cat "$OUT/$name.err"; exit 1; }
  echo "$name: $(tail -1 "$OUT/$name.txt")   ($(sed 's/^relight-replay-hash: //' "$OUT/$name.err"))"
}

variants=()
if grep -qw avx2 /proc/cpuinfo; then
  run x86-64-avx2 "$HOST_TOOL"; variants+=(x86-64-avx2)
fi
run x86-64-scalar env RELIGHT_FORCE_SCALAR=1 "$HOST_TOOL"; variants+=(x86-64-scalar)
cross_ran=0
if [ -n "$CROSS_TOOL" ] && [ -x "$CROSS_TOOL" ] && command -v qemu-aarch64 > /dev/null; then
  # One engine thread under qemu (scripts/cross-test.sh says why); the host runs keep their default two.
  run aarch64-qemu env RELIGHT_THREADS=1 qemu-aarch64 -L /usr/aarch64-linux-gnu "$CROSS_TOOL"; variants+=(aarch64-qemu)
  cross_ran=1
else
  echo "aarch64: skipped (no cross build at '${CROSS_TOOL:-}' or no qemu-aarch64; scripts/cross-test.sh makes both)"
fi

# Frame lines of every variant against the first.
first=${variants[0]}
frames=$(grep -c '^frame ' "$OUT/$first.txt")
differ=0
for v in "${variants[@]:1}"; do
  if [ "$(grep -c '^frame ' "$OUT/$v.txt")" != "$frames" ]; then
    echo "$v: $(grep -c '^frame ' "$OUT/$v.txt") frames, $first has $frames"
    differ=$frames
    continue
  fi
  d=$(paste -d'\n' <(grep '^frame ' "$OUT/$first.txt") <(grep '^frame ' "$OUT/$v.txt") | paste - - |
      awk -F'\t' '$1 != $2 { n++; if (n <= 5) print "  differs: " $1 "  vs  " $2 > "/dev/stderr" } END { print n + 0 }')
  echo "$v vs $first: $d of $frames frames differ"
  [ "$d" -gt "$differ" ] && differ=$d
done
echo "$frames frames compared across ${variants[*]}"
echo "$frames frames compared, $differ differ"
[ "$differ" -eq 0 ] || exit 1
[ $cross_ran -eq 1 ] || exit 77
