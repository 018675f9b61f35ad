#!/usr/bin/env bash
# Quick start, command 1: install what is needed, build, and run the main job.
# The main job: `brdfbake bake` on the default (no scene: the standard set for metallic-roughness
# materials on builtin:studio) into out/; it prints what it wrote.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/deps.sh
"$BUILD_DIR"/host/cli/brdfbake devices
"$BUILD_DIR"/host/cli/brdfbake bake -o out
