#!/usr/bin/env bash
# Quick start, command 2: install what is needed, build, and run the whole test suite: the C++ suite
# (ctest), then the Python package in a fresh virtual environment (pip install ., pytest tests/python).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/deps.sh
(cd "$BUILD_DIR" && ctest --output-on-failure -j "$(nproc)" --timeout 600)

# The Python package: a fresh virtual environment each run; the extension's build folder is kept in
# $BUILD_DIR/python (like the C++ build), so a second run recompiles only what changed.
python_start=$SECONDS
VENV="$BUILD_DIR/python-venv"
rm -rf "$VENV"
"${PYTHON:-python3}" -m venv "$VENV"
export PIP_DISABLE_PIP_VERSION_CHECK=1 PIP_CONSTRAINT="$PWD/python/constraints.txt"
"$VENV/bin/pip" install -q -r python/requirements-test.txt
python_deps=$SECONDS
if command -v ccache > /dev/null; then export CMAKE_CXX_COMPILER_LAUNCHER=ccache; fi
CMAKE_BUILD_PARALLEL_LEVEL="$(nproc)" "$VENV/bin/pip" install -q . -C build-dir="$BUILD_DIR/python"
echo "brdfbake python: virtual environment and test packages in $((python_deps - python_start)) s," \
     "pip install . in $((SECONDS - python_deps)) s" >&2
status=0
BRDFBAKE_CLI="$PWD/$BUILD_DIR/host/cli/brdfbake" "$VENV/bin/python" -m pytest tests/python -q -p no:cacheprovider \
  || status=$?
if [[ $status -eq 5 ]]; then
  echo "brdfbake python: pytest collected no tests" >&2
  exit 1
fi
echo "brdfbake python: $((SECONDS - python_start)) s in all" >&2
exit $status
