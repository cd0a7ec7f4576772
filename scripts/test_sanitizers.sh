#!/usr/bin/env bash
# Builds the test suite with AddressSanitizer + UndefinedBehaviorSanitizer into build-asan/ and runs it.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup-deps.sh
if [ ! -f build-asan/build.ninja ]; then
  cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSEMVOX_SANITIZE=ON -DSEMVOX_BUILD_BENCH=OFF >/dev/null
fi
ninja -C build-asan -j"$(nproc)"
# Leak checking is off: Debian's TBB and Embree keep global pools alive at exit.
export ASAN_OPTIONS=detect_leaks=0:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
cd build-asan
# The headless-Chromium tests check the page's JavaScript, not the C++ that writes it (the other report
# tests cover that under the sanitizers too); they run in the Release stage (scripts/test.sh) only.
ctest --output-on-failure -j"$(nproc)" -E "InChromium|HeadlessChromium" "$@"
