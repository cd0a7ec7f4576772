#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + UBSan) into build-fuzz/ and runs each for a bounded time.
# Usage: scripts/fuzz.sh [SECONDS_PER_TARGET=60] [TARGET...]
# Crashing inputs are copied to tests/fuzz_regressions/<target>/, where the fuzz_regression_test replays them.
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_PER_TARGET=${1:-60}
shift || true
TARGETS=("$@")
[ ${#TARGETS[@]} -eq 0 ] && TARGETS=(ply obj pcd text_cloud map_image config)
./scripts/setup-deps.sh
if [ ! -f build-fuzz/build.ninja ]; then
  CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSEMVOX_FUZZ=ON \
    -DSEMVOX_BUILD_TESTS=OFF -DSEMVOX_BUILD_BENCH=OFF >/dev/null
fi
ninja -C build-fuzz $(printf 'fuzz_%s ' "${TARGETS[@]}")
export ASAN_OPTIONS=detect_leaks=0:allocator_may_return_null=1
for t in "${TARGETS[@]}"; do
  corpus=build-fuzz/corpus/$t
  artifacts=build-fuzz/artifacts/$t
  rm -rf "$artifacts"
  mkdir -p "$corpus" "$artifacts"
  echo "== fuzz_$t for ${SECONDS_PER_TARGET}s"
  set +e
  ./build-fuzz/bin/fuzz_$t "$corpus" "fuzz/corpus/$t" -max_total_time="$SECONDS_PER_TARGET" -max_len=65536 \
    -rss_limit_mb=4096 -timeout=20 -artifact_prefix="$artifacts/" -print_final_stats=1 2>&1 |
    grep -E "stat::number_of_executed_units|stat::new_units_added|ERROR|SUMMARY|crash-|timeout-|oom-" || true
  set -e
  if compgen -G "$artifacts/*" >/dev/null; then
    mkdir -p "tests/fuzz_regressions/$t"
    cp "$artifacts"/* "tests/fuzz_regressions/$t/"
    echo "   findings copied to tests/fuzz_regressions/$t/"
  fi
done
