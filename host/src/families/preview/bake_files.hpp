// Internal: a bake's files as a target engine loads them (docs/ENGINES.md): the GGX chain decoded
// from its stored encoding, the DFG table as stored, and the diffuse term's coefficients or cube.
#pragma once

#include <string>
#include <vector>

#include "brdfbake/engines.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/table.hpp"

namespace brdfbake::detail::preview {

enum class DiffuseSource {
  OurSh,              // generic: irradiance_over_pi in our basis (docs/CONVENTIONS.md), E/pi
  FilamentSh,         // Filament's 9 pre-scaled coefficients (the KTX1 "sh" key)
  GltfSh,             // EXT_lights_image_based irradianceCoefficients, E_lm with the Condon-Shortley phase
  BabylonPolynomial,  // the .env's spherical polynomial x, y, z, xx, yy, zz, yz, zx, xy (E/pi)
  IrradianceCube,     // the glTF-IBL-Sampler's Lambertian cube (E/pi a texel)
  None,               // generic: the bake holds no irradiance (a scene of metals): no sphere may need it
};

struct BakeFiles {
  EngineTarget target = EngineTarget::Generic;
  std::string folder;
  CubeLevels specular;  // every level, RGBA float as a GPU samples them
  std::string specular_file, specular_format;
  // The preview's ideal bake (ideal.hpp): each level of the chain as a cube of its own (its level 0,
  // at a face size of its own). When not empty, the split-sum render samples these in place of
  // `specular`'s levels, whose count and sizes the engine's lookup keeps reading.
  std::vector<CubeLevels> specular_levels;
  Table dfg;  // as stored
  std::string dfg_file;
  bool dfg_multiscatter = true;   // channels bias, albedo (else scale, bias)
  bool dfg_sqrt_n_dot_v = false;  // the table's n_dot_v axis is sqrt (lookup u = sqrt(n.v))
  DiffuseSource diffuse = DiffuseSource::OurSh;
  std::vector<double> sh;  // 3 a coefficient, in the source's order and convention
  int sh_order = 3;
  CubeLevels irradiance;  // IrradianceCube
  std::string diffuse_file;
  double lod_scale = 0.8;  // Babylon.js's lodGenerationScale (.env: the file's; glTF: (N - 1) / log2 S)
  // gltf: the Babylon.js scene the light's rotation is for; `specular` and `sh` are in the glTF frame,
  // as that scene samples them (engines/babylon_frame.hpp)
  GltfScene gltf_scene = GltfScene::LeftHanded;
  Metadata settings;  // what was read, for the preview's JSON
  // KHR_materials_sheen, when the bake holds them (a bake planned from sheened materials): the
  // Charlie chain the target's shader samples (generic: the prefilter entry of distribution charlie;
  // khronos-viewer: NAME_charlie.ktx2; filament samples its GGX chain) and the charlie DFG table.
  CubeLevels sheen;  // empty: none
  std::string sheen_file;
  // The ideal bake's Charlie chain, each level a cube of its own as specular_levels; when not empty
  // the render samples these in place of `sheen`'s levels.
  std::vector<CubeLevels> sheen_levels;
  Table charlie;  // width 0: none
  std::string charlie_file;
  bool charlie_sqrt_n_dot_v = false;
  std::string charlie_visibility;  // the table's sheen_visibility (estevez-kulla, neubelt); empty: unsaid
};

// Reads the folder's manifest.json and the files the target's engine loads. Throws Error naming the
// folder for a bake made for another target or from another environment than `environment` (its
// source; empty: not checked), or missing files.
BakeFiles read_bake_files(const std::string& folder, EngineTarget target, const std::string& environment);

}  // namespace brdfbake::detail::preview
