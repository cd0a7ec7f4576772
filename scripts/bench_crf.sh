#!/usr/bin/env bash
# CRF solver benchmark: Potts grid CRFs (640x480 4-connected, 100^3 6-connected, 21 labels, seeded random
# unaries) minimised by semvox alpha-expansion (own BK max-flow), the same alpha-expansion on Boost's
# boykov_kolmogorov_max_flow, and ICM: energy, seconds, peak memory side by side (docs/crf.md).
# Builds only the benchmark into build-crf/ (or $SEMVOX_BUILD_DIR). Extra arguments go to crf_bench, e.g.
#   scripts/bench_crf.sh --problems grid2d --potts 0.05
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup-deps.sh
BUILD_DIR=${SEMVOX_BUILD_DIR:-build-crf}
if [ ! -f "$BUILD_DIR/build.ninja" ]; then
  cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
ninja -C "$BUILD_DIR" crf_bench >/dev/null
echo "load: $(cat /proc/loadavg)  ($(nproc) cores)"
"$BUILD_DIR/bin/crf_bench" "$@"
echo "load: $(cat /proc/loadavg)"
