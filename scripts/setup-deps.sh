#!/usr/bin/env bash
# Installs the Debian 12 packages semvox needs, only those missing (idempotent). Runs as root or via sudo.
set -euo pipefail
PACKAGES=(build-essential cmake ninja-build ccache lld pkg-config git
  libpcl-dev liboctomap-dev libceres-dev libopencv-dev libopencv-contrib-dev libassimp-dev libeigen3-dev
  libembree-dev libtbb-dev libnanoflann-dev libsvm-dev libcli11-dev libyaml-cpp-dev nlohmann-json3-dev
  libgtest-dev libbenchmark-dev libboost-dev
  python3-onnx python3-numpy  # python3-onnx: the ONNX backend tests write tiny networks (Debian python3).
  libjs-three)  # three.js, inlined into report.html's 3D view when a report is written (src/report/view3d.h).
# Test-only packages, added with --test (scripts/test.sh; the demo does not need them): chromium loads
# report.html headless in tests/report (its 3D view with software WebGL).
TEST_PACKAGES=(chromium)
if [ "${1:-}" = "--test" ]; then PACKAGES+=("${TEST_PACKAGES[@]}"); fi
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "semvox: installing ${#missing[@]} Debian packages: ${missing[*]}" >&2
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
