#!/usr/bin/env bash
# The server's benchmarks (docs/BENCHMARKS.md, "The server"): POST /v1/tables latency for a 128^2
# GGX DFG table on a warm server (no result cache, then with it, then 128^2 ggx-multiscatter tables
# the cache does not hold), beside cmgen's and brdfbake's
# whole process for the same table, then 50 clients submitting small jobs for 60 s.
# usage: bench/server_bench.sh [BUILD_DIR] [LOAD_SECONDS]
set -euo pipefail
build=$(realpath "${1:-build}")
seconds=${2:-60}
cli=$build/host/cli/brdfbake
bench=$build/bench/server_bench
work=$(mktemp -d)
server=""
trap '[ -n "$server" ] && kill "$server" 2>/dev/null; rm -rf "$work"' EXIT
start() {  # start ARGS...: a server on a free loopback port
  rm -f "$work/url"
  "$cli" serve --data "$work/data-$1" --listen 127.0.0.1:0 --url-file "$work/url" "${@:2}" >/dev/null 2>"$work/server.err" &
  server=$!
  until [ -s "$work/url" ]; do sleep 0.1; done
  url=$(cat "$work/url")
}
stop() { kill -TERM "$server"; wait "$server" || true; server=""; }
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); device: $("$cli" devices | sed -n 2p | xargs)"
echo "load before: $(uptime | sed 's/.*load/load/')"
start nocache --table-cache 0
"$bench" tables "$url" 200
stop
start cache
"$bench" tables "$url" 200
# the warm path of a table the result cache does not hold: a 128^2 ggx-multiscatter table, a new
# output name each request (docs/BENCHMARKS.md, "POST /v1/tables: a table not in the result cache")
"$bench" misses "$url" 200
stop
"$bench" process 20 cmgen --ibl-dfg="$work/cmgen_dfg.png" --size=128
"$bench" process 20 "$cli" lut --kind ggx --size 128 --quiet -o "$work/dfg.exr"
echo "load before the load test: $(uptime | sed 's/.*load/load/')"
start load
"$bench" load "$url" 50 "$seconds"
stop
echo "load after: $(uptime | sed 's/.*load/load/')"
