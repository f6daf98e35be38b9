#!/usr/bin/env bash
# Installs the build into a temporary DESTDIR (`cmake --install`) and checks
# what lands there: the tools in bin (executable), relightd's systemd units in
# lib/systemd/system with ExecStart naming the installed relightd, the docs;
# then `systemd-analyze verify` on each installed unit, its relightd taken
# from DESTDIR (skipped with a message when systemd-analyze is absent).
# Exit 0 ok, 1 a failure.
#   scripts/check-install.sh BUILD_DIR
set -euo pipefail
BUILD=$(realpath "${1:-build}")
prefix=$(sed -n 's/^CMAKE_INSTALL_PREFIX:PATH=//p' "$BUILD/CMakeCache.txt")
unitdir=$(sed -n 's/^RELIGHT_SYSTEMD_UNITDIR:STRING=//p' "$BUILD/CMakeCache.txt")
dest=$(mktemp -d)
trap 'rm -rf "$dest"' EXIT
status=0
fail() { echo "FAIL: $*"; status=1; }

DESTDIR="$dest" cmake --install "$BUILD" > "$dest.log" 2>&1 || { cat "$dest.log"; rm -f "$dest.log"; echo "FAIL: cmake --install"; exit 1; }
rm -f "$dest.log"
root="$dest$prefix"
for tool in relightd relight-bake relight-render relight-probe relight-lid relight-fixture-type; do
  [ -x "$root/bin/$tool" ] || fail "bin/$tool missing or not executable"
done
for unit in relightd.service relightd@.service olad.service; do
  [ -f "$root/$unitdir/$unit" ] || fail "$unitdir/$unit missing"
done
for doc in README.md security.md modbus.md dmx.md bake-format.md; do
  [ -f "$root/share/doc/relight/$doc" ] || fail "share/doc/relight/$doc missing"
done
for unit in "$root/$unitdir"/relightd*.service; do
  exec_path=$(sed -n 's/^ExecStart=\([^ ]*\).*/\1/p' "$unit")
  [ "$exec_path" = "$prefix/bin/relightd" ] || fail "$(basename "$unit"): ExecStart=$exec_path, not $prefix/bin/relightd"
done
echo "installed under $prefix: $(cd "$root" && find . -type f | wc -l) files"
(cd "$root" && find . -type f ! -path './share/doc/*' | sort)

if ! command -v systemd-analyze > /dev/null; then
  echo "no systemd-analyze: verify of the installed units skipped"
  exit $status
fi
# The installed units as they are, but for ExecStart's relightd looked up
# under DESTDIR (systemd-analyze checks that the command exists; --root would
# need a whole system in DESTDIR).
mkdir "$dest/verify"
for unit in "$root/$unitdir"/*.service; do
  name=$(basename "$unit")
  check="$dest/verify/$name"
  [[ "$name" == *@.service ]] && check="$dest/verify/${name%@.service}@test.service"
  sed "s|^ExecStart=$prefix/bin/|ExecStart=$root/bin/|" "$unit" > "$check"
  if grep -q '^ExecStart=/usr/bin/olad' "$unit" && [ ! -x /usr/bin/olad ]; then
    echo "$name: no /usr/bin/olad, verify skipped"
  elif ! out=$(systemd-analyze verify "$check" 2>&1) || [ -n "$out" ]; then
    echo "$name: systemd-analyze verify:"
    echo "$out"
    status=1
  else
    echo "$name: systemd-analyze verify passes"
  fi
done
exit $status
