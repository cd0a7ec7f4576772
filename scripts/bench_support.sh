#!/usr/bin/env bash
# Support / clutter / other: the dense CRF's fast filters (separable smoothness, cubic height grid,
# permutohedral 5-D lattice; the pipeline's DenseCrfOptions{}, which the test uses too) vs brute-force
# mean-field on the test's 40x30 image and on a 64x48 view (marginal difference, times), at 640x480
# (speed-up, brute force extrapolated from sampled pixels), and the per-view cost of the classifier.
# Override the filters with --exact-smoothness, --height-grid[-position], --refinement[-5d], --small-refinement[-5d].
# Usage: scripts/bench_support.sh [build dir] [extra support_bench args]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-${SEMVOX_BUILD_DIR:-build}}
shift || true
ninja -C "$BUILD_DIR" -j2 support_bench >/dev/null
echo "load: $(cut -d' ' -f1-3 /proc/loadavg) on $(nproc) cores"
"$BUILD_DIR/bin/support_bench" --model models/support_clutter.svm "$@"
