#!/usr/bin/env bash
# Configures (Ninja, ccache, lld, Release) and builds semvox into build/ (or $SEMVOX_BUILD_DIR).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup-deps.sh
BUILD_DIR=${SEMVOX_BUILD_DIR:-build}
if [ ! -f "$BUILD_DIR/build.ninja" ]; then
  cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
fi
ninja -C "$BUILD_DIR" -j"$(nproc)"
