#!/usr/bin/env bash
# Installs what relight needs from Debian 12's packages (if missing) and
# builds it into build/. Sourced by run-demo.sh and run-tests.sh.
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(cmake g++ make pkg-config libembree-dev libzstd-dev zlib1g-dev libosmesa6-dev
          libpng-dev libtomlplusplus-dev libcli11-dev libeigen3-dev libgtest-dev
          libbenchmark-dev libmodbus-dev libgpiod-dev mbpoll socat
          qlcplus-data libpugixml-dev ola libola-dev python3 libsystemd-dev
          libopenmpi-dev openmpi-bin libopenblas-dev)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# node and npm for the wire test's independent senders (tests/wire): Debian's,
# unless a node with npm is already there (another packaging of node ships npm itself).
command -v npm > /dev/null || missing+=(nodejs npm)
if [ ${#missing[@]} -gt 0 ]; then
  echo "relight: installing ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q "${missing[@]}"
fi

BUILD_DIR=${RELIGHT_BUILD_DIR:-build}
WERROR=OFF
[ "${CI:-}" = "true" ] && WERROR=ON
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRELIGHT_WERROR=$WERROR > /dev/null
cmake --build "$BUILD_DIR" -j"$(nproc)"
