#!/usr/bin/env bash
# Checks the unit files in runtime/daemon/systemd/ (docs/security.md): each
# passes `systemd-analyze verify` (with ExecStart pointed at a real relightd)
# and `systemd-analyze security --offline=true` rates it at most 2.0.
# Prints "UNIT exposure X.Y" per unit. Exit 77 (ctest: skipped) without
# systemd-analyze.
#   scripts/check-systemd-units.sh [RELIGHTD]   (default: build/runtime/daemon/relightd)
set -euo pipefail
cd "$(dirname "$0")/.."
RELIGHTD=$(realpath "${1:-build/runtime/daemon/relightd}")
MAX_EXPOSURE=2.0
command -v systemd-analyze > /dev/null || { echo "no systemd-analyze: skipped"; exit 77; }
[ -x "$RELIGHTD" ] || { echo "no relightd at $RELIGHTD"; exit 1; }

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
status=0
for unit in runtime/daemon/systemd/*.service; do
  name=$(basename "$unit")
  sed "s|/usr/local/bin/relightd|$RELIGHTD|g" "$unit" > "$tmp/$name"
  check="$tmp/$name"
  [[ "$name" == *@.service ]] && { cp "$check" "$tmp/${name%@.service}@test.service"; check="$tmp/${name%@.service}@test.service"; }
  # olad may be missing on a build machine: verify needs the binary to exist.
  if grep -q '^ExecStart=/usr/bin/olad' "$check" && [ ! -x /usr/bin/olad ]; then
    echo "$name: no /usr/bin/olad, verify skipped"
  elif ! out=$(systemd-analyze verify "$check" 2>&1) || [ -n "$out" ]; then
    echo "$name: systemd-analyze verify:"
    echo "$out"
    status=1
  fi
  exposure=$(systemd-analyze security --offline=true "$check" 2>&1 | sed -n 's/.*Overall exposure level for .*: \([0-9.]*\).*/\1/p')
  echo "$name exposure ${exposure:-?}"
  if [ -z "$exposure" ] || ! awk -v e="$exposure" -v m="$MAX_EXPOSURE" 'BEGIN { exit !(e <= m) }'; then
    echo "$name: exposure ${exposure:-unknown} above $MAX_EXPOSURE"
    status=1
  fi
done
exit $status
