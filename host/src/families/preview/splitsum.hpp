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

// The switches an engine has that change its shading, named as the engine names them.
struct SplitSumOptions {
  // gltf, babylon: Babylon.js's PBRBRDFConfiguration.DEFAULT_MIX_IBL_RADIANCE_WITH_IRRADIANCE (true in
  // 8.46.2, since 7.45): the base's reflection mixed with the irradiance by alphaG.
  bool babylon_mix_ibl_radiance_with_irradiance = true;
};

class SplitSum {
 public:
  explicit SplitSum(BakeFiles files, SplitSumOptions options = {});
  // The radiance towards v (unit, from the surface to the viewer) of a surface of normal n.
  // normal_slope2: the squared screen-space derivative of the normal, max(|dn/dx|^2, |dn/dy|^2) per
  // pixel, which Babylon.js's specular anti-aliasing adds to alphaG (the `gltf` target: its loader
  // turns it on); 0 for none.
  Rgb shade(const Vec3& n, const Vec3& v, const PreviewMaterial& m, float normal_slope2 = 0.0f) const;
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
  // Babylon.js's sampleReflectionTexture: the chain at lod, then toLinearSpace (x^2.2) where the
  // texture is in gamma space (the glTF loader's RawCubeTexture keeps gammaSpace true: GAMMAREFLECTION).
  void reflection(const Vec3& d, float lod, float out[3]) const;
  static void trilinear_in(const std::vector<Level>& chain, const Vec3& d, float lod, float out[3]);
  void dfg(float n_dot_v, float roughness, float* bias, float* albedo) const;
  void diffuse(const Vec3& n, float out[3]) const;
  // What shade() computes once for every target: F0, the diffuse colour, F90, the specular factor,
  // n and v in fp32, n.v, the chain's last level and the diffuse irradiance.
  struct BaseInputs {
    float f0[3], cd[3], f90, specular, nx, ny, nz, vx, vy, vz, dot_nv, levels_minus_one, irr[3];
    float aa_alpha_g;  // Babylon.js's specular anti-aliasing: 0.75 sqrt(normal_slope2) (gltf), else 0
  };
  // Each target's base shading (specular + diffuse, before sheen and coat) into `out`.
  void base_generic(const PreviewMaterial& m, const BaseInputs& in, float out[3]) const;
  void base_filament(const PreviewMaterial& m, const BaseInputs& in, float out[3]) const;
  void base_babylon(const PreviewMaterial& m, const BaseInputs& in, float out[3]) const;  // and gltf
  void base_khronos_viewer(const PreviewMaterial& m, const BaseInputs& in, float out[3]) const;
  // KHR_materials_clearcoat layered over the shaded base `out`, as the target's shader does.
  void coat(const Vec3& n, const Vec3& v, const PreviewMaterial& m, float aa_alpha_g, float out[3]) const;
  // KHR_materials_sheen over the shaded base `out` (before the coat), as the target's shader does.
  void sheen(const Vec3& n, const Vec3& v, const PreviewMaterial& m, float aa_alpha_g, float out[3]) const;
  // The charlie table's albedo E(n.v, sheenRoughness): bilinear, clamp to edge, texel centres.
  float charlie(float n_dot_v, float sheen_roughness) const;

  BakeFiles files_;
  SplitSumOptions options_;
  bool reflection_gamma_ = false;  // gltf: GAMMAREFLECTION (the loader's cube keeps gammaSpace true)
  bool specular_aa_ = false;       // gltf: SPECULARAA (the loader sets enableSpecularAntiAliasing)
  std::vector<Level> levels_;
  std::vector<Level> irradiance_;
  std::vector<Level> sheen_levels_;  // the Charlie chain (generic, khronos-viewer)
  std::vector<double> harmonics_;    // Babylon.js's pre-scaled harmonics (babylon, gltf)
};

}  // namespace brdfbake::detail::preview
