#!/usr/bin/env bash
# Packs what bench/gpu/run.sh needs on a machine that has an OpenCL GPU but none of the project's
# libraries (docs/BENCHMARKS.md, "On an NVIDIA GPU"): the CLI and the benchmark programs of BUILD,
# every shared library they load except the C library's own (the loader finds the GPU's ICD through
# OCL_ICD_VENDORS, which run.sh sets), the shared maps and a few scenes. About 35 MiB.
#   bench/gpu/bundle.sh [BUILD] [SHARED] [OUT]      (defaults: build ../shared .gpu)
set -euo pipefail
build=${1:-build} shared=${2:-../shared} out=${3:-.gpu}
rm -rf "$out" && mkdir -p "$out/bin" "$out/lib" "$out/shared/envmaps" "$out/scenes"
cp "$build/host/cli/brdfbake" "$out/bin/"
for b in prefilter_bench brdf_bench lut_accuracy bake_bench fresnel_bench startup_stages; do cp "$build/bench/$b" "$out/bin/"; done
strip "$out"/bin/*
for f in "$out"/bin/*; do ldd "$f" | awk '{print $3}' | grep '^/' || true; done | sort -u |
  grep -v -E '/(libc|libm|libpthread|libdl|librt)\.so|ld-linux' | xargs -I{} cp -L {} "$out/lib/"
cp "$shared"/envmaps/*_1k.hdr "$out/shared/envmaps/"
for s in SheenChair ClearCoatTest MetalRoughSpheres IridescenceLamp SpecularTest; do
  [[ -f $shared/scenes/$s.gltf ]] && cp "$shared/scenes/$s.gltf" "$out/scenes/"
done
cp "$(dirname "$0")/run.sh" "$out/"
du -sh "$out"
