#!/usr/bin/env bash
# Installs the pinned npm senders of the wire test (package-lock.json) into
# DEST (the build tree; the source tree stays clean): npm ci from the cache
# when it has them, else from the registry. Without npm or the registry it
# says so and exits 0: the wire test then skips with that reason.
#   npm_install.sh SRC_DIR DEST_DIR
set -u
src=$1 dest=$2
mkdir -p "$dest"
cp "$src/package.json" "$src/package-lock.json" "$src/send.js" "$dest/"
if ! command -v npm > /dev/null; then
  echo "wire: npm not installed (scripts/setup.sh installs it); the wire test will skip"
  exit 0
fi
cd "$dest"
if [ -f node_modules/.package-lock.json ] && cmp -s package-lock.json .installed-lock.json; then
  echo "wire: npm packages already installed in $dest"
  exit 0
fi
if npm ci --prefer-offline --no-audit --no-fund --loglevel=error; then
  cp package-lock.json .installed-lock.json
  echo "wire: installed $(ls node_modules | tr '\n' ' ')in $dest"
else
  rm -rf node_modules
  echo "wire: npm ci failed (no registry and no cache?); the wire test will skip"
fi
exit 0
