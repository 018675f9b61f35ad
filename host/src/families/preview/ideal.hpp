// Internal: the preview's ideal bake (docs/PREVIEW.md, "Engine share and bake share"): what a target's
// shader would show from perfect files. The target's own files with their inputs replaced, so that the
// same split-sum code (splitsum.hpp) renders them: each level of the GGX chain at the roughness the
// target's schedule gives it in a chain of the files' level count (the engine's LOD mapping and its
// blend between levels unchanged), filtered on its own at a high face size in float32; the Charlie
// chain (KHR_materials_sheen) likewise at the roughness its lookup asks of each level (lod =
// sheenRoughness (levels - 1): linear); the DFG table
// at its texel centres' exact albedos in float32 at a high size (a target whose engine samples its own
// table keeps it: no file changes it); no storage. What the files add to the render's error is then
// split-sum(files) - split-sum(ideal), what the engine's approximation adds split-sum(ideal) -
// reference.
#pragma once

#include <string>

#include "brdfbake/backend.hpp"
#include "brdfbake/environment.hpp"
#include "families/preview/bake_files.hpp"

namespace brdfbake::detail::preview {

// The ideal bake's sizes: the mirror (level 0) the environment converted to 2 size (no finer than
// the source resolves, an equirect's width / 2, unless size needs it), size the files' level 0's
// within [kIdealChainSize, kIdealChainMaxSize]; every other level at least 4 x the files'
// level of its index, its texels no wider than an eighth of its lobe, at least kIdealMinLevelSize and
// at most size (ideal.cpp, level_size), filtered from the environment converted to twice its size;
// the DFG table kIdealLutSize^2.
inline constexpr int kIdealChainSize = 256;
inline constexpr int kIdealChainMaxSize = 512;
inline constexpr int kIdealMinLevelSize = 64;
inline constexpr int kIdealLutSize = 256;
// The Lambertian cube of a target that samples one (khronos-viewer): kIdealIrradianceSize, or twice
// the files' face size where that is larger (at most kIrradianceMaxCube), from the environment
// converted to kIdealIrradianceSource (irradiance is smooth: the irradiance family's default source).
// 128^2 (~1 s on two CPU cores) against the bakes' 32^2: a bilinear lookup's error, second order in
// the texel, 1/16 of theirs.
inline constexpr int kIdealIrradianceSize = 128;
inline constexpr int kIdealIrradianceSource = 256;
// The quadrature's refinement of the ideal chain's levels, the bakes' default: at 8 the shares of
// venice's default grid for babylon (its 8 filtered levels) moved by at most 0.052 percentage points
// on any sphere (engine share) for twice the seconds (5.9 s against 2.8 s; docs/PREVIEW.md).
inline constexpr double kIdealRefinement = 4.0;

struct IdealBake {
  BakeFiles files;    // the files' own, with the chain and the DFG table replaced
  Metadata settings;  // what each input is, for the JSON
  double seconds = 0.0;
};

// What an ideal bake replaces in a bake's files: the chain's levels, the DFG table (unless the engine
// samples its own) and the charlie table (Estevez & Kulla's visibility). They depend on the files only
// through ideal_parts_key(files): bakes of one target whose keys are equal (a sweep's settings that
// change the storage, the refinement or the DFG table's size, not the chain's shape) share them.
struct IdealParts {
  std::string key;
  std::vector<CubeLevels> specular_levels;
  std::vector<CubeLevels> sheen_levels;  // empty: the bake has no Charlie chain
  CubeLevels irradiance;                 // empty: the files' diffuse (SH: exact projections already)
  Table dfg;                             // width 0: the files' own (the engine samples its own table)
  Table charlie;                         // width 0: the files' own (none, or another visibility)
  Metadata settings;
  double seconds = 0.0;
};
std::string ideal_parts_key(const BakeFiles& files);
IdealParts ideal_parts(Backend& backend, const EnvImage& environment, const BakeFiles& files);
// `files` with `parts` in place of what they replace. Throws Error when parts.key is not files' key.
IdealBake apply_ideal_parts(const IdealParts& parts, const BakeFiles& files);

// The ideal bake of `files` (a target's bake read by read_bake_files) under `environment`, on
// `backend`'s OpenCL device: apply_ideal_parts(ideal_parts(...), files). Throws Error on the scalar
// reference backend (the chain's levels would take minutes there).
IdealBake ideal_bake(Backend& backend, const EnvImage& environment, const BakeFiles& files);

}  // namespace brdfbake::detail::preview
