#!/usr/bin/env bash
# Room-type accuracy on the generated validation apartments (bench/room_types_bench.cc): raw scene evidence,
# majority voting, dense G-CRF and the Gibbs CRF variants, per-pixel global / average accuracy (Table II form).
# Needs the trained models (models/, written by `semvox train`). Usage: scripts/bench_room_types.sh [bench args]
#   --protocol loao [--ssvm-epochs 10] [--fold-models DIR]   also leave one validation apartment out
#   --pred-topview '/tmp/runs/{seed}'                         also score with `semvox run`'s semantic top view
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${SEMVOX_BUILD_DIR:-build}
ninja -C "$BUILD_DIR" -j2 room_types_bench >/dev/null
echo "load: $(cut -d' ' -f1-3 /proc/loadavg) on $(nproc) cores"
"$BUILD_DIR/bin/room_types_bench" "$@"
