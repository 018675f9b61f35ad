#!/usr/bin/env bash
# The bytes the product writes, as one digest per file: a default bake, scene bakes with engine
# targets, a job and every one-table command. Two builds that print the same digest wrote the same
# files (the manifests' wall times aside, which are replaced by 0 before hashing). Used to show that a
# change of structure changed no output (issue 25):
#   scripts/output_digest.sh build/host/cli/brdfbake > before.txt   (on the old build)
#   scripts/output_digest.sh build/host/cli/brdfbake > after.txt    (on the new one)
#   diff before.txt after.txt
# The shared scenes and maps (../shared) are used when present.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
BRDFBAKE=$(realpath "${1:-build/host/cli/brdfbake}")
SHARED=${BRDFBAKE_SHARED:-$(realpath ../shared 2>/dev/null || true)}
work=$(mktemp -d -t brdfbake-digest.XXXXXX)
trap 'rm -rf "$work"' EXIT
repo=$PWD
b() { (cd "$work" && "$BRDFBAKE" "$@" --quiet) || { echo "FAILED: brdfbake $*" >&2; exit 1; }; }

b bake -o bake_default
b bake --env builtin:sun --chain-size 64 --lut-size 32 -o bake_sun
"$BRDFBAKE" run examples/job.json -o "$work/job" --quiet || { echo "FAILED: brdfbake run" >&2; exit 1; }
b lut --kind ggx --size 32 -o lut_ggx.exr
b lut --kind ggx-multiscatter --size 64 -o lut_ms.ktx2
b lut --kind charlie --size 32 --png-range scale -o lut_charlie.png
b lut --kind ggx --size 16 -o lut_ggx.csv
b lut --kind ggx --size 16 -o lut_ggx.h
b fresnel --model conductor --material gold --size 64 -o fresnel_gold.csv
b fresnel --model dielectric --ior 1.5 --size 64 -o fresnel_glass.exr
b fresnel --model schlick --f0 0.04 --size 32 -o fresnel_schlick.exr
b fresnel --model f82-tint --f0 0.9,0.6,0.2 --f82 0.8,0.5,0.2 --size 32 -o fresnel_f82.exr
b thin-film --base-ior 1.5 --size 32 -o thin_film.exr
b prefilter --env builtin:studio --chain-size 64 -o prefilter_studio.ktx2
b prefilter --env builtin:sun --chain-size 32 --distribution charlie -o prefilter_charlie.ktx2
b prefilter --env builtin:studio --chain-size 32 --chain-max-error 0.02 -o prefilter_dir
b irradiance --env builtin:studio -o irr_sh3.json
b irradiance --env builtin:sun --sh-order 5 --irradiance-size 16 -o irr_cube.ktx2
b eval --material "$repo/examples/materials.json" --name gold -i "$repo/examples/pairs.csv" -o eval_gold.csv
b tabulate --material "$repo/examples/materials.json" --name gold --layout merl -o gold.binary
b tabulate --material "$repo/examples/materials.json" --layout albedo --model gltf-correlated --res 16 -o albedo.exr
if [[ -n $SHARED && -d $SHARED/scenes ]]; then
  env=$SHARED/envmaps/derived/venice_sunset_256x128_derived.hdr
  b bake --scene "$SHARED/scenes/SheenChair.gltf" --env "$env" --chain-size 64 --lut-size 32 -o scene_sheen
  for target in filament gltf babylon khronos-viewer; do
    b bake --scene "$SHARED/scenes/MetalRoughSpheres.gltf" --env "$env" --chain-size 64 --lut-size 32 \
      --target "$target" -o "scene_$target"
  done
  b bake --scene "$SHARED/scenes/IridescenceLamp.gltf" --env "$env" --chain-size 32 --lut-size 32 -o scene_irid
else
  echo "output_digest: ../shared absent, scene bakes skipped" >&2
fi

cd "$work"
find . -type f | LC_ALL=C sort | while read -r f; do
  if [[ $f == *manifest.json ]]; then
    printf '%s  %s\n' "$(sed -E 's/"seconds": [0-9.e+-]+/"seconds": 0/g' "$f" | sha256sum | cut -c1-16)" "$f"
  else
    printf '%s  %s\n' "$(sha256sum "$f" | cut -c1-16)" "$f"
  fi
done
