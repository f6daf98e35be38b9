#!/usr/bin/env bash
# Installs, builds and runs the whole test suite (GoogleTest under ctest).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
BUILD_DIR=${RELIGHT_BUILD_DIR:-build}
cd "$BUILD_DIR"
ctest --output-on-failure -j"$(nproc)"
