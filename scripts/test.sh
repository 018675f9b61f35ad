#!/usr/bin/env bash
# Quick start, command 2: install what is needed, build, and run the whole test suite.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
export BRDFBAKE_WARNINGS_AS_ERRORS=ON
source scripts/deps.sh
# What a fresh machine sees (issue 18): private, empty kernel caches, PoCL's and ours, removed
# afterwards. BRDFBAKE_TEST_WARM_CACHE=1 keeps the user's caches (faster, but not a first run).
if [[ ${BRDFBAKE_TEST_WARM_CACHE:-0} != 1 ]]; then
  BRDFBAKE_TEST_CACHE=$(mktemp -d -t brdfbake-test-cache.XXXXXX)
  trap 'rm -rf "$BRDFBAKE_TEST_CACHE"' EXIT
  export POCL_CACHE_DIR=$BRDFBAKE_TEST_CACHE/pocl BRDFBAKE_CACHE_DIR=$BRDFBAKE_TEST_CACHE/brdfbake
  mkdir -p "$POCL_CACHE_DIR" "$BRDFBAKE_CACHE_DIR"
fi
cd "$BUILD_DIR"
ctest --output-on-failure -j "$(nproc)" --timeout 600
