#!/usr/bin/env bash
# The preview's speed (docs/BENCHMARKS.md, "Material previews"): whole-process wall times of the
# command line and the times its JSON records (device time from OpenCL event profiling), with the
# machine's load before each run. Not a test: run it on a quiet machine for the figures to quote.
#
#   bench/preview_bench.sh [build/host/cli/brdfbake] [../shared/envmaps] [out folder]
set -euo pipefail
cli=${1:-build/host/cli/brdfbake}
maps=${2:-../shared/envmaps}
out=${3:-bench-out/preview}
mkdir -p "$out"
runs=3

load() { cut -d' ' -f1 /proc/loadavg; }
# Median of the whole process's wall time over $runs runs of "$@".
wall() {
  local times=()
  for _ in $(seq $runs); do
    local t0 t1
    t0=$(date +%s.%N)
    "$@" > /dev/null 2>&1
    t1=$(date +%s.%N)
    times+=("$(echo "$t1 - $t0" | bc)")
  done
  printf '%s\n' "${times[@]}" | sort -g | sed -n "$(( (runs + 1) / 2 ))p"
}
# A time the JSON records: times.<key>.
json_time() { python3 -c "import json,sys; print('%.3f' % json.load(open(sys.argv[1]))['times'][sys.argv[2]])" "$1" "$2"; }

env=$maps/venice_sunset_1k.hdr
sun=$maps/rooitou_park_1k.hdr
"$cli" bake --env "$env" --target filament -o "$out/venice_filament" --quiet
"$cli" bake --env "$sun" --target filament -o "$out/rooitou_filament" --quiet

echo "# split-sum render alone from a bake folder, 512x512 (whole process, median of $runs)"
echo "load $(load): $(wall "$cli" preview --env "$env" --target filament --bake "$out/venice_filament" --no-reference -o "$out/s.png" --quiet) s"

echo "# the reference of the default grid at 512x512, with its bound (whole process; JSON: reference wall, device, bound)"
for m in venice:"$env":venice_filament rooitou:"$sun":rooitou_filament; do
  IFS=: read -r name map bake <<< "$m"
  l=$(load)
  w=$(wall "$cli" preview --env "$map" --target filament --bake "$out/$bake" -o "$out/$name.png" --quiet)
  echo "$name load $l: $w s; reference $(json_time "$out/$name.json" reference) s, device $(json_time "$out/$name.json" reference_device) s, bound $(json_time "$out/$name.json" bound) s"
done

echo "# scaling with pixels (venice, default grid)"
for size in 256 512 1024; do
  "$cli" preview --env "$env" --target filament --bake "$out/venice_filament" --width $size --height $size -o "$out/px$size.png" --quiet
  echo "${size}x${size} load $(load): device $(json_time "$out/px$size.json" reference_device) s, reference $(json_time "$out/px$size.json" reference) s"
done

echo "# scaling with roughness (venice, one gold sphere of radius 118 in 256x256: 43,600 pixels, each integrated)"
for r in 0 0.05 0.2 0.5 1; do
  printf '{"materials": [{"name": "gold", "baseColor": [1, 0.766, 0.336], "metallic": 1, "roughness": %s}]}' "$r" > "$out/r$r.json"
  "$cli" preview --env "$env" --target filament --bake "$out/venice_filament" --materials "$out/r$r.json" \
    --width 256 --height 256 -o "$out/rough$r.png" --quiet
  echo "roughness $r load $(load): device $(json_time "$out/rough$r.json" reference_device) s"
done

echo "# scaling with the environment's size (venice 256x128 derived against 1024x512, 512x512 grid)"
small=$maps/derived/venice_sunset_256x128_derived.hdr
"$cli" preview --env "$small" --target filament -o "$out/small.png" --quiet
echo "256x128 load $(load): device $(json_time "$out/small.json" reference_device) s"
echo "1024x512: see the 512x512 row above"
