#!/usr/bin/env bash
# Installs the build into a temporary prefix, then builds the consumer against it twice: with CMake's
# find_package and with pkg-config, and runs both. Usage: run.sh BUILD_DIR SOURCE_DIR [CXX [SANITIZERS]]
# (a sanitizer build's library needs consumers built by the same compiler with the same sanitizers)
set -euo pipefail
build=$1
src=$2
cxx=${3:-c++}
sanitize=${4:-}
flags=""
[[ -n $sanitize ]] && flags="-fsanitize=$sanitize"
work=$(mktemp -d -t brdfbake-consumer.XXXXXX)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
test -x "$work/prefix/bin/brdfbake"
"$work/prefix/bin/brdfbake" --version
cmake -S "$src/tests/consumer" -B "$work/cmake" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="$flags" >/dev/null
cmake --build "$work/cmake" >/dev/null
out=$(BRDFBAKE_CONSUMER_REFERENCE=1 "$work/cmake/consumer")
echo "cmake consumer: $out"
export PKG_CONFIG_PATH="$work/prefix/lib/pkgconfig:$work/prefix/lib64/pkgconfig${PKG_CONFIG_PATH:+:$PKG_CONFIG_PATH}"
# shellcheck disable=SC2046
"$cxx" -O1 $flags "$src/tests/consumer/main.cpp" -o "$work/pc_consumer" $(pkg-config --cflags --static --libs brdfbake)
out2=$(BRDFBAKE_CONSUMER_REFERENCE=1 "$work/pc_consumer")
echo "pkg-config consumer: $out2"
# The reference's converged GGX scale at the centre of cell (3, 3) of a 4x4 table (n_dot_v 0.875,
# roughness 0.875): both consumers print the same value, and it is the table's.
[[ "$out" == "$out2" ]] || { echo "the two consumers disagree" >&2; exit 1; }
[[ "$out" == *"dfg_ggx_4.exr scale(3,3) 0."* ]] || { echo "unexpected: $out" >&2; exit 1; }
