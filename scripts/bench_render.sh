#!/usr/bin/env bash
# Render throughput: the full view render (RGB, depth, normal, primitive id, voxel key per pixel) against a
# bare rtcIntersect16 loop over the same Embree scene, camera (640x480, 90 degrees) and poses, in the same
# run, on the demo apartment subdivided to about 10 k and about 1 M triangles. Prints M rays/s of both and
# their ratio (target: full >= 70% of bare). Reference on this kind of machine: bare Embree about 77 M rays/s
# (10 k triangles) and 17 M rays/s (1 M triangles) on 2 threads; shared machines are noisy (+-20-30%),
# so bare and full alternate pose by pose and the best of several rounds is reported.
# Extra arguments go to render_bench (e.g. --rounds 5 --threads 1 --faces 50000).
#   SEMVOX_BUILD_DIR  build directory (default build)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${SEMVOX_BUILD_DIR:-build}
[ -f "$BUILD_DIR/build.ninja" ] || cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
ninja -C "$BUILD_DIR" render_bench >/dev/null
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'), load $(cut -d' ' -f1-3 /proc/loadavg)"
"$BUILD_DIR/bin/render_bench" "$@"
