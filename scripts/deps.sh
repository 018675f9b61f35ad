#!/usr/bin/env bash
# Installs the Debian 12 packages brdfbake needs (those missing only), then configures and builds
# Release in build/. Sourced by run.sh and test.sh.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

BRDFBAKE_PACKAGES=(
  build-essential cmake pkg-config
  pocl-opencl-icd ocl-icd-opencl-dev opencl-c-headers opencl-clhpp-headers clinfo
  libopenimageio-dev openimageio-tools
  libcxxopts-dev nlohmann-json3-dev libtinygltf-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  gnuplot-nox
  python3-venv python3-dev python3-pip
)

missing=()
for p in "${BRDFBAKE_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "brdfbake: installing ${missing[*]}" >&2
  SUDO=""
  if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
fi

BUILD_DIR=${BRDFBAKE_BUILD_DIR:-build}
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release >&2
cmake --build "$BUILD_DIR" -j "$(nproc)" >&2
