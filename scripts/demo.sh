#!/usr/bin/env bash
# Installs what is missing, builds the semvox binary only (not the tests or benchmarks: scripts/test.sh
# builds everything), runs it on the bundled demo apartment and prints where the outputs are and the seconds.
# The build's progress is one line rewritten in place when stdout is a terminal; its full log is kept in
# BUILD_DIR/demo-build.log and its last lines are shown if it fails.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-out/demo}
BUILD_DIR=${SEMVOX_BUILD_DIR:-build}
start=$SECONDS

./scripts/setup-deps.sh
if [ ! -f "$BUILD_DIR/build.ninja" ]; then
  echo "semvox demo: configuring $BUILD_DIR (CMake, Ninja, Release)"
  cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
fi

# Reads ninja's output and, on a terminal, rewrites one line with its latest "[done/total] step" status.
one_line_progress() {
  if [ -t 1 ]; then
    local line cols
    cols=$(tput cols 2>/dev/null || echo 80)
    while IFS= read -r line; do
      case $line in
        '['*) printf '\r\033[Kbuilding %s' "${line:0:cols-10}" ;;
      esac
    done
    printf '\r\033[K'
  else
    cat >/dev/null
  fi
}

log="$BUILD_DIR/demo-build.log"
if ! ninja -C "$BUILD_DIR" -j"$(nproc)" semvox 2>&1 | tee "$log" | one_line_progress; then
  echo "semvox demo: the build failed; the last lines of $log:" >&2
  tail -n 40 "$log" >&2
  exit 1
fi
built=$SECONDS
echo "semvox demo: built $BUILD_DIR/bin/semvox in $((built - start)) s"

"$BUILD_DIR/bin/semvox" run scenes/demo_apartment.ply -o "$OUT"
echo
echo "semvox demo: outputs are in $(cd "$OUT" && pwd):"
for f in "$OUT"/*; do echo "  ${f##*/}"; done
echo "semvox demo: $((SECONDS - start)) s in all ($((built - start)) s set-up and build, $((SECONDS - built)) s run)"
