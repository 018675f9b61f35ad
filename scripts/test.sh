#!/usr/bin/env bash
# Quick start, command 2: install what is needed, build, and run the whole test suite.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
export BRDFBAKE_WARNINGS_AS_ERRORS=ON
source scripts/deps.sh
cd "$BUILD_DIR"
ctest --output-on-failure -j "$(nproc)" --timeout 600
