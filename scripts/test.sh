#!/usr/bin/env bash
# Quick start, command 2: install what is needed, build, and run the whole test suite.
#   scripts/test.sh             the Release build and every test (ctest, which replays the fuzz
#                               corpora); with BRDFBAKE_FUZZ_SECONDS=N also each libFuzzer harness for
#                               N seconds (scripts/fuzz.sh, clang 14)
#   scripts/test.sh --sanitize  the same tests built with AddressSanitizer and UndefinedBehavior-
#                               Sanitizer (CMakePresets.json "asan", in build-asan/; installs clang 14)
#   Beside ctest, the Python package in a fresh virtual environment (pip install ., pytest
#   tests/python; its output is printed after ctest's, from build/python-tests.log).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
export BRDFBAKE_WARNINGS_AS_ERRORS=ON
# The suite runs with a temporary folder of its own, $TMPDIR for every test and what it runs (issue
# 34): what a test or the product leaves there is listed afterwards and fails the run, then the
# folder is removed. BRDFBAKE_TEST_KEEP=1 keeps the tests' folders (they say where) and this one.
outer_tmp=${TMPDIR:-/tmp}
test_tmp=""
private_tmpdir() {
  test_tmp=$(mktemp -d "$outer_tmp/brdfbake-test-run.XXXXXX")
  export TMPDIR=$test_tmp
}
# What the suite left in $test_tmp: its names, and 1 (the run fails) when there is any.
check_leftovers() {
  local left=()
  mapfile -t left < <(find "$test_tmp" -mindepth 1 -maxdepth 1 -printf '%f\n' | sort)
  if ((${#left[@]} == 0)); then return 0; fi
  if [[ ${BRDFBAKE_TEST_KEEP:-0} == 1 ]]; then
    echo "scripts/test.sh: BRDFBAKE_TEST_KEEP=1: the tests' folders are kept in $test_tmp" >&2
    return 0
  fi
  echo "scripts/test.sh: the tests left ${#left[@]} entries in their temporary folder ($test_tmp," \
       "removed now); a test's folder is removed when the test ends (tests/support/temp_dir.hpp," \
       "tests/python/conftest.py):" >&2
  printf '  %s\n' "${left[@]}" >&2
  return 1
}
remove_test_tmp() {
  if [[ -n $test_tmp && ${BRDFBAKE_TEST_KEEP:-0} != 1 ]]; then rm -rf "$test_tmp"; fi
  export TMPDIR=$outer_tmp
}
case "${1:-}" in
  "") ;;
  --sanitize)
    BRDFBAKE_WITH_CLANG=1 BRDFBAKE_DEPS_ONLY=1 source scripts/deps.sh
    cmake --preset asan >&2
    cmake --build --preset asan -j "$(nproc)" >&2
    private_tmpdir
    trap remove_test_tmp EXIT
    asan_status=0
    ctest --preset asan -j "$(nproc)" --timeout 1800 || asan_status=$?
    check_leftovers || asan_status=1
    exit "$asan_status" ;;
  -h|--help) sed -n '2,7p' "$0"; exit 0 ;;
  *) echo "scripts/test.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
esac
source scripts/deps.sh
# What a fresh machine sees (issue 18): private, empty kernel caches, PoCL's and ours, removed
# afterwards. BRDFBAKE_TEST_WARM_CACHE=1 keeps the user's caches (faster, but not a first run).
python_pid=""
cleanup() {
  # an interrupted run: the Python part's commands (pip, pytest), then its shell
  if [[ -n $python_pid ]]; then
    pkill -TERM -P "$python_pid" 2> /dev/null || true
    kill "$python_pid" 2> /dev/null || true
  fi
  if [[ -n ${BRDFBAKE_TEST_CACHE:-} ]]; then rm -rf "$BRDFBAKE_TEST_CACHE"; fi
  remove_test_tmp
}
trap cleanup EXIT
if [[ ${BRDFBAKE_TEST_WARM_CACHE:-0} != 1 ]]; then
  BRDFBAKE_TEST_CACHE=$(mktemp -d -t brdfbake-test-cache.XXXXXX)
  export POCL_CACHE_DIR=$BRDFBAKE_TEST_CACHE/pocl BRDFBAKE_CACHE_DIR=$BRDFBAKE_TEST_CACHE/brdfbake
  mkdir -p "$POCL_CACHE_DIR" "$BRDFBAKE_CACHE_DIR"
fi
# PoCL compiles a kernel's work-group function once generically and again for every local size a
# launch uses (launches leave the local size to it, and their sizes follow the measured speed), ~30 %
# of the device tests' CPU (stop 31, docs/BENCHMARKS.md). The generic function alone computes the
# same values (the output digest is the same byte for byte), so the suite runs with it; set
# POCL_WORK_GROUP_SPECIALIZATION=1 to test PoCL's specialised functions as a user's run uses them.
export POCL_WORK_GROUP_SPECIALIZATION=${POCL_WORK_GROUP_SPECIALIZATION:-0}

# The engines that the engine tests render each target's files with (docs/ENGINES.md, "Engine truth"),
# pinned, fetched from PyPI once into $BUILD_DIR/engines/: Babylon.js 8.46.2 as the gradio 6.31.0 wheel
# ships it (its static chunks only; tests/engines/babylon/) and Filament 1.76 as the open3d-cpu 0.20.0
# wheel links it (a virtual environment of its own; tests/engines/filament/). Before ctest, which reads
# the Filament DFG table extracted from that wheel (tests/host/test_filament_dfg.cpp).
export BRDFBAKE_ENGINES_CACHE="$PWD/$BUILD_DIR/engines"
"${PYTHON:-python3}" tests/engines/babylon/setup_babylon.py > /dev/null
"${PYTHON:-python3}" tests/engines/filament/setup_open3d.py > /dev/null

# The Python package: a fresh virtual environment each run; the extension's build folder is kept in
# $BUILD_DIR/python (like the C++ build), so a second run recompiles only what changed.
python_part() {
  local python_start=$SECONDS python_deps status=0
  local VENV="$BUILD_DIR/python-venv"
  rm -rf "$VENV"
  "${PYTHON:-python3}" -m venv "$VENV"
  export PIP_DISABLE_PIP_VERSION_CHECK=1 PIP_CONSTRAINT="$PWD/python/constraints.txt"
  # pip's build folders are the set-up's, not the tests': in the user's temporary folder
  TMPDIR=$outer_tmp "$VENV/bin/pip" install -q -r python/requirements-test.txt
  python_deps=$SECONDS
  if command -v ccache > /dev/null; then export CMAKE_CXX_COMPILER_LAUNCHER=ccache; fi
  # `pip install .` as a user runs it, configuring the whole project as the wheel's build, but with
  # the library (and the OpenImageIO module) that ctest tests, from $BUILD_DIR: it was compiled from
  # the same sources with the same settings (python/CMakeLists.txt checks them), so only the four
  # files of the extension module compile here. BRDFBAKE_TEST_PYTHON_STANDALONE=1 compiles the
  # library in the wheel's build too, exactly as a user's `pip install .` does (a few minutes more).
  local wheel_library=(-C cmake.define.BRDFBAKE_PYTHON_LIBRARY_FROM="$(cd "$BUILD_DIR" && pwd)")
  if [[ ${BRDFBAKE_TEST_PYTHON_STANDALONE:-0} == 1 ]]; then wheel_library=(-C cmake.define.BRDFBAKE_PYTHON_LIBRARY_FROM=); fi
  TMPDIR=$outer_tmp CMAKE_BUILD_PARALLEL_LEVEL="$(nproc)" "$VENV/bin/pip" install -q . -C build-dir="$BUILD_DIR/python" \
    -C cmake.define.BRDFBAKE_WARNINGS_AS_ERRORS=ON "${wheel_library[@]}"
  echo "brdfbake python: virtual environment and test packages in $((python_deps - python_start)) s," \
       "pip install . in $((SECONDS - python_deps)) s" >&2
  BRDFBAKE_CLI="$PWD/$BUILD_DIR/host/cli/brdfbake" "$VENV/bin/python" -m pytest tests/python -q -p no:cacheprovider --durations=12 \
    || status=$?
  if [[ $status -eq 5 ]]; then
    echo "brdfbake python: pytest collected no tests" >&2
    return 1
  fi
  echo "brdfbake python: $((SECONDS - python_start)) s in all" >&2
  return $status
}

# ctest and the Python part run side by side (stop 30): ctest keeps both cores busy but for the
# long single-process tests at its end, and the Python part alone ran pytest on one core while the
# other idled. The two share nothing but the kernel caches above (loopback servers on ephemeral
# ports, temporary folders of their own). The Python part's output is kept in a file and printed
# after ctest's, so that the two do not interleave.
python_log="$BUILD_DIR/python-tests.log"
private_tmpdir
python_part > "$python_log" 2>&1 &
python_pid=$!
ctest_status=0
(cd "$BUILD_DIR" && ctest --output-on-failure -j "$(nproc)" --timeout 600) || ctest_status=$?
python_status=0
wait "$python_pid" || python_status=$?
python_pid=""
echo "---- the Python package (pip install ., pytest tests/python; $python_log) ----"
cat "$python_log"
if ((ctest_status != 0)); then echo "scripts/test.sh: ctest failed (exit $ctest_status)" >&2; fi
if ((python_status != 0)); then echo "scripts/test.sh: the Python part failed (exit $python_status)" >&2; fi
leftover_status=0
check_leftovers || leftover_status=1
remove_test_tmp
if ((ctest_status != 0 || python_status != 0 || leftover_status != 0)); then exit 1; fi
# Live fuzzing is opt-in (BRDFBAKE_FUZZ_SECONDS=N): ctest already replays every seed corpus, and a
# libFuzzer run needs its own clang build (build-fuzz/).
if [[ -n ${BRDFBAKE_FUZZ_SECONDS:-} ]]; then scripts/fuzz.sh "$BRDFBAKE_FUZZ_SECONDS"; fi
