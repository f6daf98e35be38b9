#!/usr/bin/env bash
# Issue 17 fault: the disk fills up while relight-bake writes its bake.
#   bake_disk_full.sh RELIGHT_BAKE SCENE fsize   a file size limit (setrlimit
#       RLIMIT_FSIZE in the baker's shell before exec, SIGXFSZ ignored: the
#       write fails with EFBIG, "File too large")
#   bake_disk_full.sh RELIGHT_BAKE SCENE tmpfs   a tmpfs with room for the old
#       bake and 64 KiB more, in a private mount namespace (root only: exit 77,
#       ctest "skipped", when unshare or mount is not permitted): ENOSPC
# What must survive: the previous bake at that path, byte for byte, and no
# temporary file may be left; the baker exits non-zero naming the file and
# the reason.
set -uo pipefail
BAKER=$(realpath "$1") SCENE=$(realpath "$2") MODE=$3

if [ "$MODE" = tmpfs ] && [ -z "${RELIGHT_IN_MOUNT_NS:-}" ]; then
  if ! unshare --mount --propagation private true 2> /dev/null; then
    echo "skipped: no private mount namespace here (needs root)"
    exit 77
  fi
  RELIGHT_IN_MOUNT_NS=1 exec unshare --mount --propagation private "$0" "$@"
fi

work=$(mktemp -d)
trap 'umount "$work/disk" 2> /dev/null; rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

"$BAKER" "$SCENE" -o "$work/old.rlb" -q || fail "the previous bake could not be made"
old_size=$(stat -c %s "$work/old.rlb")
mkdir "$work/disk"
case "$MODE" in
  fsize)
    # 64 KiB: the new bake (as large as the old) cannot be written.
    limit_kib=64
    expect="File too large"
    ;;
  tmpfs)
    size_kib=$(( (old_size + 1023) / 1024 + 64 ))
    mount -t tmpfs -o "size=${size_kib}k" tmpfs "$work/disk" || { echo "skipped: cannot mount a tmpfs"; exit 77; }
    limit_kib=unlimited
    expect="No space left on device"
    ;;
  *) fail "mode must be fsize or tmpfs" ;;
esac
target="$work/disk/room.rlb"
cp "$work/old.rlb" "$target"
(( old_size > 64 * 1024 )) || fail "the bake ($old_size bytes) is smaller than the room left"

( trap '' XFSZ; ulimit -f "$limit_kib"; exec "$BAKER" "$SCENE" -o "$target" -q ) 2> "$work/err.txt"
rc=$?
cat "$work/err.txt"
(( rc != 0 )) || fail "relight-bake exited 0 on a full disk"
(( rc < 128 )) || fail "relight-bake died of signal $((rc - 128))"
grep -q "$target" "$work/err.txt" || fail "the message does not name $target"
grep -q "$expect" "$work/err.txt" || fail "the message does not say '$expect'"
cmp "$work/old.rlb" "$target" || fail "the previous bake changed"
left=$(find "$work/disk" -name 'room.rlb.tmp.*')
[ -z "$left" ] || fail "temporary file left behind: $left"
echo "ok ($MODE): exit $rc, previous bake ($old_size bytes) intact, no temporary file"
