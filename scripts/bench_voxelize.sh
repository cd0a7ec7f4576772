#!/usr/bin/env bash
# Voxelisation throughput: semvox's parallel frame integration vs OctoMap's insertPointCloud on the same
# 640x480 frame (5 cm and 2 cm), checking identical free/occupied voxels. Prints a table.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh >/dev/null
./build/bin/voxelize_bench "$@"
