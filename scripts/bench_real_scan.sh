#!/usr/bin/env bash
# Real scans end to end: `semvox run` on the ScanNet studio (scene0000_00 in
# ../shared/data, a sparse fused colour point cloud), timed, then `semvox eval --boxes` against its 27
# furniture boxes: the per-box table (voxels inside, recall, top three labels), per-class recall, mean box
# recall, floor recall, wall share, room types and the run's seconds per stage (docs/metrics.md,
# "Real scans: box scores"). Then the same for the SUN RGB-D bedroom view (sunrgbd_000017: one RGB-D frame,
# a bed and a night stand as yawed boxes in gt_boxes.tsv) when it is there. Exits 0 with a message when the
# studio is absent.
# Usage: scripts/bench_real_scan.sh [build dir]
#   SEMVOX_BUILD_DIR  build directory when none is given (default build)
#   SEMVOX_STUDIO     data directory (default ../shared/data/scannet_scene0000_00)
#   SEMVOX_SUN        SUN RGB-D view directory (default ../shared/data/sunrgbd_000017)
#   SEMVOX_BENCH_OUT  output directory of the studio's run (default: a temporary directory, removed at exit);
#                     the SUN view's run goes to SEMVOX_BENCH_OUT/../sunrgbd_000017
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-${SEMVOX_BUILD_DIR:-build}}
DATA=${SEMVOX_STUDIO:-../shared/data/scannet_scene0000_00}
if [ ! -f "$DATA/scene0000_00.ply" ] || [ ! -f "$DATA/gt.json" ]; then
  echo "bench_real_scan.sh: skipped: no scene0000_00.ply and gt.json in $DATA (hint: set SEMVOX_STUDIO)"
  exit 0
fi
[ -f "$BUILD_DIR/build.ninja" ] || cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
ninja -C "$BUILD_DIR" -j2 semvox >/dev/null
if [ -n "${SEMVOX_BENCH_OUT:-}" ]; then
  OUT=$SEMVOX_BENCH_OUT
else
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
  OUT=$tmp/studio
fi
echo "load: $(cut -d' ' -f1-3 /proc/loadavg) on $(nproc) cores"
start=$(date +%s.%N)
"$BUILD_DIR/bin/semvox" run "$DATA/scene0000_00.ply" -o "$OUT" -q
end=$(date +%s.%N)
echo "semvox run: $(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f", b - a }') s wall clock"
"$BUILD_DIR/bin/semvox" eval --pred "$OUT" --boxes "$DATA/gt.json" -q
SUN=${SEMVOX_SUN:-../shared/data/sunrgbd_000017}
if [ -f "$SUN/000017_points.ply" ] && [ -f "$SUN/gt_boxes.tsv" ]; then
  SUN_OUT=$(dirname "$OUT")/sunrgbd_000017
  start=$(date +%s.%N)
  "$BUILD_DIR/bin/semvox" run "$SUN/000017_points.ply" -o "$SUN_OUT" -q
  end=$(date +%s.%N)
  echo "semvox run (SUN RGB-D 000017): $(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f", b - a }') s wall clock"
  "$BUILD_DIR/bin/semvox" eval --pred "$SUN_OUT" --boxes "$SUN/gt_boxes.tsv" -q
else
  echo "bench_real_scan.sh: SUN RGB-D view skipped: no 000017_points.ply and gt_boxes.tsv in $SUN"
fi
