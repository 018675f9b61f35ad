#!/usr/bin/env bash
# The warm path alone (docs/BENCHMARKS.md, "POST /v1/tables: a table not in the result cache"):
# a server on loopback, then N x POST /v1/tables for a 128^2 ggx-multiscatter DFG table that the
# result cache does not hold (a new output name each), after 10 warm-up requests: the latency's
# p50/p90/p99 and the server's own split (Server-Timing) at the median. The load average is printed
# before and after: quote the figures of a quiet machine.
# usage: bench/tables_miss_bench.sh [BUILD_DIR] [N]
set -euo pipefail
build=$(realpath "${1:-build}")
n=${2:-200}
work=$(mktemp -d)
server=""
trap '[ -n "$server" ] && kill "$server" 2>/dev/null; rm -rf "$work"' EXIT
"$build/host/cli/brdfbake" serve --data "$work/data" --listen 127.0.0.1:0 --url-file "$work/url" >/dev/null 2>"$work/server.err" &
server=$!
until [ -s "$work/url" ]; do sleep 0.1; done
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
"$build/bench/server_bench" misses "$(cat "$work/url")" "$n"
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
