#!/usr/bin/env bash
# Quick start, command 1: install what is needed, build, and run the main job.
# Until scene baking exists, the main job bakes the default DFG lookup table into out/.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/deps.sh
mkdir -p out
"$BUILD_DIR"/host/cli/brdfbake devices
"$BUILD_DIR"/host/cli/brdfbake lut --kind ggx --size 128 -o out/dfg_ggx_128.exr
"$BUILD_DIR"/host/cli/brdfbake lut --kind ggx-multiscatter --size 128 -o out/dfg_ggx_multiscatter_128.ktx2
"$BUILD_DIR"/host/cli/brdfbake lut --kind charlie --size 128 -o out/dfg_charlie_128.exr
ls -l out/
