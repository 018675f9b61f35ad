// Internal: the split-sum render, what a target engine's shader computes from a bake's files
// (docs/ENGINES.md, "What the preview emulates", cites the function each step reproduces): its LOD
// from roughness, trilinear seamless sampling of the stored cube levels (decoded as the GPU sees
// them: bake_files.hpp), the DFG table at its stored size by bilinear lookup (clamp to edge, texel
// centres), its multiple-scattering compensation, and its diffuse term. In fp32, as a shader.
#pragma once

#include <string>
#include <vector>

#include "brdfbake/preview.hpp"
#include "families/preview/bake_files.hpp"

namespace brdfbake::detail::preview {

class SplitSum {
 public:
  explicit SplitSum(BakeFiles files);
  // The radiance towards v (unit, from the surface to the viewer) of a surface of normal n.
  Rgb shade(const Vec3& n, const Vec3& v, const PreviewMaterial& m) const;
  // Level 0 of the chain in direction d (the background: the engine's skybox).
  Rgb sky(const Vec3& d) const;
  // What each step does for this target and which shader function it is, for the JSON.
  Metadata steps() const;
  const BakeFiles& files() const { return files_; }
  // Whether this target's split-sum render renders KHR_materials_sheen from this bake, and what it
  // does (or why not), for the notes of a sheened sphere and the JSON's steps.
  bool renders_sheen() const;
  std::string sheen_note() const;

 private:
  struct Level {
    int size = 0;
    std::vector<float> rgb;  // padded faces: (size + 2)^2 texels a face, a border of the neighbours
  };
  void bilinear(int level, int face, float a, float b, float out[3]) const;
  void trilinear(const Vec3& d, float lod, float out[3]) const;
  static void trilinear_in(const std::vector<Level>& chain, const Vec3& d, float lod, float out[3]);
  void dfg(float n_dot_v, float roughness, float* bias, float* albedo) const;
  void diffuse(const Vec3& n, float out[3]) const;
  // What shade() computes once for every target: F0, the diffuse colour, F90, the specular factor,
  // n and v in fp32, n.v, the chain's last level and the diffuse irradiance.
  struct BaseInputs {
    float f0[3], cd[3], f90, specular, nx, ny, nz, vx, vy, vz, dot_nv, levels_minus_one, irr[3];
  };
  // Each target's base shading (specular + diffuse, before sheen and coat) into `out`.
  void base_generic(const PreviewMaterial& m, const BaseInputs& in, float out[3]) const;
  void base_filament(const PreviewMaterial& m, const BaseInputs& in, float out[3]) const;
  void base_babylon(const PreviewMaterial& m, const BaseInputs& in, float out[3]) const;  // and gltf
  void base_khronos_viewer(const PreviewMaterial& m, const BaseInputs& in, float out[3]) const;
  // KHR_materials_clearcoat layered over the shaded base `out`, as the target's shader does.
  void coat(const Vec3& n, const Vec3& v, const PreviewMaterial& m, float out[3]) const;
  // KHR_materials_sheen over the shaded base `out` (before the coat), as the target's shader does.
  void sheen(const Vec3& n, const Vec3& v, const PreviewMaterial& m, float out[3]) const;
  // The charlie table's albedo E(n.v, sheenRoughness): bilinear, clamp to edge, texel centres.
  float charlie(float n_dot_v, float sheen_roughness) const;

  BakeFiles files_;
  std::vector<Level> levels_;
  std::vector<Level> irradiance_;
  std::vector<Level> sheen_levels_;  // the Charlie chain (generic, khronos-viewer)
  std::vector<double> harmonics_;    // Babylon.js's pre-scaled harmonics (babylon, gltf)
};

}  // namespace brdfbake::detail::preview
