#!/usr/bin/env bash
# Installs the Debian 12 packages brdfbake needs (those missing only), then configures and builds
# Release in build/. Sourced by run.sh and test.sh. BRDFBAKE_WITH_CLANG=1 also installs clang 14 and
# its sanitizer and libFuzzer runtimes (test.sh --sanitize); BRDFBAKE_DEPS_ONLY=1 stops after the
# packages.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

BRDFBAKE_PACKAGES=(
  build-essential cmake pkg-config
  pocl-opencl-icd ocl-icd-opencl-dev opencl-c-headers opencl-clhpp-headers clinfo
  libopenexr-dev libpng-dev zlib1g-dev libstb-dev
  libopenimageio-dev openimageio-tools
  libcxxopts-dev nlohmann-json3-dev libtinygltf-dev
  libcpp-httplib-dev libsqlite3-dev curl jq
  libpng-dev libastcenc-dev
  libgtest-dev libgmock-dev
  gnuplot-nox
  python3-venv python3-dev python3-pip
)
# Used only by the test suite: Filament's own KtxBundle and cmgen check the Filament target
# (tests/device/test_engine_filament.cpp), python3-jsonschema the glTF EXT_lights_image_based output
# (tests/engines/validate_gltf_ibl.py), oclgrind a second OpenCL implementation for the kernel
# build test. The tests skip with a message where these are missing. clang-format-14 is the formatter
# of scripts/check_format.sh (.clang-format; other versions format differently). chromium and
# chromium-driver: the web page's browser test (tests/python/test_web_page.py, driven by Selenium) and
# Babylon.js's render of the babylon and gltf targets (tests/python/test_engine_babylon.py: WebGL2 on
# chromium's SwiftShader). libvulkan1 and mesa-vulkan-drivers: Mesa's lavapipe, the Vulkan device that
# Filament 1.76 (the open3d-cpu wheel) renders the filament target on (tests/python/test_engine_filament.py);
# zstd unpacks Filament's built-in DFG table from that wheel's library (tests/engines/filament/filament_dfg.py).
BRDFBAKE_TEST_PACKAGES=(
  libfilament-dev libfilament-tools python3-jsonschema oclgrind clang-format-14
  chromium chromium-driver
  libvulkan1 mesa-vulkan-drivers zstd
)

# The sanitizer build and the fuzz harnesses (CMakePresets.json asan and fuzz).
BRDFBAKE_CLANG_PACKAGES=(clang-14 libclang-rt-14-dev)
if [[ ${BRDFBAKE_WITH_CLANG:-0} == 1 ]]; then BRDFBAKE_PACKAGES+=("${BRDFBAKE_CLANG_PACKAGES[@]}"); fi

missing=()
for p in "${BRDFBAKE_PACKAGES[@]}" "${BRDFBAKE_TEST_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "brdfbake: installing ${missing[*]}" >&2
  SUDO=""
  if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
fi

if [[ ${BRDFBAKE_DEPS_ONLY:-0} == 1 ]]; then return 0 2>/dev/null || exit 0; fi

BUILD_DIR=${BRDFBAKE_BUILD_DIR:-build}
# One build for both scripts, with the test command's settings: warnings are errors in run.sh's build
# too, so that test.sh after run.sh configures nothing new and compiles nothing (a different flag
# would recompile the whole tree). BRDFBAKE_WARNINGS_AS_ERRORS=OFF scripts/run.sh builds without
# (test.sh always sets ON).
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DBRDFBAKE_WARNINGS_AS_ERRORS="${BRDFBAKE_WARNINGS_AS_ERRORS:-ON}" >&2
cmake --build "$BUILD_DIR" -j "$(nproc)" >&2
