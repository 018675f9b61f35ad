// Internal: what every target's split-sum shading shares (the targets' host/src/engines/<target>/splitsum.cpp
// include this header): the bake's chains padded for seamless sampling, textureLod's trilinear sampling and its
// blend between levels, the DFG and charlie tables' bilinear lookup, the diffuse term (the SH evaluated, or the
// irradiance cube), and the row a target registers (engines/registry.hpp, TargetDef::shading). In fp32, as a
// shader; the implementation is splitsum.cpp.
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

// One level of a cube padded for seamless filtering: (size + 2)^2 RGB texels a face, a border of the neighbours.
struct PaddedLevel {
  int size = 0;
  std::vector<float> rgb;
};
using PaddedChain = std::vector<PaddedLevel>;

inline float mixf(float a, float b, float t) { return a + (b - a) * t; }
inline float pow5(float x) {
  const float x2 = x * x;
  return x2 * x2 * x;
}

// textureLod on a chain: lod clamped to [0, levels - 1], GL_LINEAR within the two nearest levels and linear
// between them (GL_LINEAR_MIPMAP_LINEAR), seamless across faces.
void trilinear_in(const PaddedChain& chain, const Vec3& d, float lod, float out[3]);
// texture(lut, vec2(n_dot_v, roughness)) of a table's channels first .. first + channels - 1: bilinear,
// clamp to edge, texel centres at (i + 0.5) / N; the n_dot_v axis sqrt-spaced where the table says so.
void lut_lookup(const Table& t, bool sqrt_n_dot_v, float n_dot_v, float roughness, int channels, float* c,
                int first = 0);
// KHR_materials_iridescence where the engine mixes the film into its F0 (generic's runtime, Babylon.js's
// iridescenceBlock): f0 = mix(f0, evalIridescence(1, iridescenceIor, n.v, thickness, f0), factor);
// unchanged without a film.
void iridescent_f0(const PreviewMaterial& m, float n_dot_v, float f0[3]);
// A file's name without its folder, for the notes.
std::string file_name(const std::string& path);

// The bake's files as the target's engine samples them, and that sampling.
struct SplitSumSampler {
  BakeFiles files;
  SplitSumOptions options;
  bool reflection_gamma = false;  // gltf: GAMMAREFLECTION (the loader's cube keeps gammaSpace true)
  bool specular_aa = false;       // gltf: SPECULARAA (the loader sets enableSpecularAntiAliasing)
  PaddedChain levels;             // the GGX chain (a target's prepare may append levels)
  PaddedChain irradiance;         // the irradiance cube (khronos-viewer)
  PaddedChain sheen_levels;       // the Charlie chain (generic, khronos-viewer)
  std::vector<double> harmonics;  // Babylon.js's pre-scaled harmonics (babylon, gltf)

  // Level l of a cube, padded (cube.clh's layout; OpenGL 4.6 8.13.1, GL_TEXTURE_CUBE_MAP_SEAMLESS).
  static PaddedLevel pad(const CubeLevels& cube, int l);
  // GL_LINEAR on level `level` of the GGX chain (-1: the irradiance cube) in direction d's face.
  void bilinear(int level, const Vec3& d, float out[3]) const;
  // textureLod on the GGX chain.
  void trilinear(const Vec3& d, float lod, float out[3]) const { trilinear_in(levels, d, lod, out); }
  // Babylon.js's sampleReflectionTexture: the chain at lod, then toLinearSpace (x^2.2) where the
  // texture is in gamma space (the glTF loader's RawCubeTexture keeps gammaSpace true: GAMMAREFLECTION).
  void reflection(const Vec3& d, float lod, float out[3]) const;
  // The DFG table the engine samples at (n.v, roughness) as (bias, albedo), whatever its channels hold.
  void dfg(float n_dot_v, float roughness, float* bias, float* albedo) const;
  // The charlie table's albedo E(n.v, sheenRoughness): bilinear, clamp to edge, texel centres.
  float charlie(float n_dot_v, float sheen_roughness) const;
  // The diffuse light at n as the files give it (DiffuseSource): the SH evaluated, or the irradiance cube.
  void diffuse(const Vec3& n, float out[3]) const;
  // The texts the targets' steps share: the DFG table's lookup and the chain's sampling.
  std::string lut_text() const;
  std::string cube_text() const;
};

// What SplitSum::shade computes once for every target: F0, the diffuse colour, F90, the specular factor,
// n and v in fp32, n.v, the chain's last level and the diffuse irradiance.
struct BaseInputs {
  float f0[3], cd[3], f90, specular, nx, ny, nz, vx, vy, vz, dot_nv, levels_minus_one, irr[3];
  float aa_alpha_g;  // Babylon.js's specular anti-aliasing: 0.75 sqrt(normal_slope2) (gltf), else 0
};

// A target's split-sum shading (its folder's splitsum.cpp), the shading row of the registry.
struct SplitSumShading {
  // Once, after the chains are padded: what the engine's loader makes of them (nullptr: nothing).
  void (*prepare)(SplitSumSampler& s) = nullptr;
  // The base shading (specular + diffuse, before sheen and coat) into `out`.
  void (*base)(const SplitSumSampler& s, const PreviewMaterial& m, const BaseInputs& in, float out[3]) = nullptr;
  // KHR_materials_sheen over the shaded base `out` (before the coat), as the target's shader does.
  void (*sheen)(const SplitSumSampler& s, const Vec3& n, const Vec3& v, const PreviewMaterial& m, float aa_alpha_g,
                float out[3]) = nullptr;
  // KHR_materials_clearcoat layered over the shaded base `out`, as the target's shader does.
  void (*coat)(const SplitSumSampler& s, const Vec3& n, const Vec3& v, const PreviewMaterial& m, float aa_alpha_g,
               float out[3]) = nullptr;
  // Whether the render renders the sheen from this bake, and what it does (asked only where it does).
  bool (*renders_sheen)(const SplitSumSampler& s) = nullptr;
  std::string (*sheen_note)(const SplitSumSampler& s) = nullptr;
  // What each step does and which shader function it is, for the JSON.
  Metadata (*steps)(const SplitSumSampler& s) = nullptr;
  // The final colour clamped at 0 (Babylon.js's pbrBlockFinalColorComposition.fx: max(finalColor, 0)).
  bool clamp_at_zero = false;
};

}  // namespace brdfbake::detail::preview
