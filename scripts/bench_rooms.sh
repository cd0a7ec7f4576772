#!/usr/bin/env bash
# Room segmentation on the ipa_room_segmentation test maps (Bormann et al., ICRA 2016): recall, precision
# and seconds per map and mean, for every method, on the plain and the furnished maps; then the means on
# the R2V plans rasterised as maps (plain, and with fixtures as obstacles) when ../shared/data/r2v exists.
# Extra arguments go to rooms_bench (e.g. --method distance --brief, or an option: --saddle_ratio 0.6).
#   SEMVOX_BUILD_DIR  build directory (default build)
#   SEMVOX_IPA_MAPS   map directory (default ../shared/data/ipa_room_seg/test_maps)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${SEMVOX_BUILD_DIR:-build}
DATA=${SEMVOX_IPA_MAPS:-../shared/data/ipa_room_seg/test_maps}
R2V=${SEMVOX_R2V:-../shared/data/r2v}
if [ ! -d "$DATA" ]; then
  echo "bench_rooms.sh: no ipa maps in $DATA (hint: set SEMVOX_IPA_MAPS)" >&2
  exit 2
fi
[ -f "$BUILD_DIR/build.ninja" ] || cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
ninja -C "$BUILD_DIR" rooms_bench rooms_r2v_bench >/dev/null
"$BUILD_DIR/bin/rooms_bench" --data "$DATA" "$@"
if [ -d "$R2V" ]; then
  "$BUILD_DIR/bin/rooms_r2v_bench" --data "$R2V"
  "$BUILD_DIR/bin/rooms_r2v_bench" --data "$R2V" --fixtures
fi
