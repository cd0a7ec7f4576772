#!/usr/bin/env bash
# Installs what is missing, builds, and runs semvox on the bundled demo apartment.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh >/dev/null
OUT=${1:-out/demo}
./build/bin/semvox run scenes/demo_apartment.ply -o "$OUT"
echo
echo "semvox demo: outputs are in $(cd "$OUT" && pwd):"
ls -1 "$OUT" | sed 's/^/  /'
