// The split-sum render's cube lookup against each engine's own formula, on the host alone: a chain
// whose level l holds the constant l + 1 (every texel, every face), so that a mirror-like metal of F0 1
// reflects exactly 1 + the LOD the target's shader computed, blended linearly between the two nearest
// levels. A white furnace (all levels equal) cannot see a wrong LOD or a missing blend; this can:
// Filament's perceptualRoughnessToLod made linear, Babylon.js's LOD without its lodGenerationScale,
// or no blending between levels each move the measured LOD by far more than the tolerance.
// Also Babylon.js's mixIblRadianceWithIrradiance weight, the glTF loader's second gamma decoding of
// the reflection and its specular anti-aliasing, each against the shader's formula.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "brdfbake/preview.hpp"
#include "families/preview/bake_files.hpp"
#include "families/preview/splitsum.hpp"

namespace brdfbake {
namespace {

using detail::preview::BakeFiles;
using detail::preview::DiffuseSource;
using detail::preview::SplitSum;
using detail::preview::SplitSumOptions;

// The lookup is fp32 (as a shader): the LOD's log2 and products round at ~1e-7 relative, the trilinear
// weights at ~1e-7 of a level; 1e-4 of a level is far above that and far below what any defect above
// moves (Filament's linear LOD at r = 0.5 is off by 1.5 levels of 6; no blend by up to half a level).
constexpr double kLodTolerance = 1e-4;

constexpr int kSize = 64;

// A chain of `levels` levels of a kSize cube, level l the constant l + 1.
CubeLevels staircase(int levels) {
  CubeLevels c;
  c.size = kSize;
  for (int l = 0; l < levels; ++l) {
    const int s = c.level_size(l);
    c.levels.emplace_back(size_t(6) * size_t(s) * size_t(s) * 4, float(l + 1));
  }
  return c;
}

// A DFG table of constant (bias 0, albedo 1): the F0 = 1 metal then reflects the sampled radiance
// itself in every target (its energy compensation 1 + F0 (1 / 1 - 1) = 1).
Table unit_dfg() {
  Table t;
  t.width = t.height = 8;
  t.channels = {"bias", "albedo"};
  t.data.assign(8 * 8 * 2, 0.0f);
  for (size_t k = 1; k < t.data.size(); k += 2) t.data[k] = 1.0f;
  return t;
}

// The bake files of `target` with a staircase chain and no diffuse light (every coefficient 0).
BakeFiles staircase_files(EngineTarget target, int levels) {
  BakeFiles b;
  b.target = target;
  b.specular = staircase(levels);
  b.dfg = unit_dfg();
  b.dfg_multiscatter = true;
  b.sh.assign(27, 0.0);
  switch (target) {
    case EngineTarget::Generic:
      b.diffuse = DiffuseSource::OurSh;
      break;
    case EngineTarget::Filament:
      b.diffuse = DiffuseSource::FilamentSh;
      break;
    case EngineTarget::Gltf:
      b.diffuse = DiffuseSource::GltfSh;
      b.lod_scale = double(levels - 1) / std::log2(double(kSize));  // EXT_lights_image_based.ts
      break;
    case EngineTarget::Babylon:
      b.diffuse = DiffuseSource::BabylonPolynomial;
      b.lod_scale = 0.8;  // the .env's lodGenerationScale
      break;
    case EngineTarget::KhronosViewer: {
      b.diffuse = DiffuseSource::IrradianceCube;
      b.irradiance.size = 4;
      b.irradiance.levels.emplace_back(size_t(6) * 16 * 4, 0.0f);
      break;
    }
  }
  return b;
}

PreviewMaterial white_metal(double roughness) {
  PreviewMaterial m;
  m.base_color = {1.0, 1.0, 1.0};
  m.metallic = 1.0;
  m.roughness = roughness;
  return m;
}

// Each engine's own LOD for a perceptual roughness r on a chain of `levels` levels of kSize (before
// textureLod's clamp).
double engine_lod(EngineTarget target, double r, int levels) {
  double lod = 0.0;
  switch (target) {
    case EngineTarget::Generic:        // docs/CONVENTIONS.md: (levels - 1) r
    case EngineTarget::KhronosViewer:  // ibl.glsl getIBLRadianceGGX: roughness (u_MipCount - 1)
      lod = (levels - 1) * r;
      break;
    case EngineTarget::Filament: {  // perceptualRoughnessToLod, r clamped to MIN_PERCEPTUAL_ROUGHNESS
      const double pr = std::clamp(r, 0.045, 1.0);
      lod = (levels - 1) * pr * (2.0 - pr);
      break;
    }
    case EngineTarget::Gltf:  // getLodFromAlphaG x (N - 1) / log2 S
      lod = std::log2(kSize * (r * r + 0.0005)) * (levels - 1) / std::log2(double(kSize));
      break;
    case EngineTarget::Babylon:  // getLodFromAlphaG x 0.8
      lod = std::log2(kSize * (r * r + 0.0005)) * 0.8;
      break;
  }
  return lod;
}

// What the staircase reflects at that LOD: 1 + lod, clamped to the chain; for gltf, Babylon.js's cube
// has log2(kSize) + 1 levels, those past the file's `levels` zero, so past the last level the value
// falls linearly to 0 over one level.
double staircase_value(EngineTarget target, double lod, int levels) {
  const double last = levels - 1;
  if (target != EngineTarget::Gltf || lod <= last) return 1.0 + std::clamp(lod, 0.0, last);
  return levels * std::max(0.0, 1.0 - (lod - last));
}

struct Case {
  EngineTarget target;
  int levels;
};

class PreviewLookup : public ::testing::TestWithParam<Case> {};

// Level l holds l + 1, blended linearly: the metal reflects 1 + lod (the gltf target's reflection
// raised to 2.2 once more: the glTF loader's gamma, undone here).
TEST_P(PreviewLookup, TheLodIsTheEnginesFormulaAndLevelsBlendLinearly) {
  const Case c = GetParam();
  SplitSumOptions o;
  o.babylon_mix_ibl_radiance_with_irradiance = false;  // its weight is the next test's
  const SplitSum split(staircase_files(c.target, c.levels), o);
  const Vec3 n{0.0, 0.0, 1.0};
  int fractional = 0;
  for (double r = 0.0; r <= 1.0 + 1e-9; r += 0.025) {
    const Rgb out = split.shade(n, n, white_metal(r));
    double value = out.r;
    if (c.target == EngineTarget::Gltf) value = std::pow(value, 1.0 / 2.2);
    const double lod = engine_lod(c.target, r, c.levels), expected = staircase_value(c.target, lod, c.levels);
    EXPECT_NEAR(value, expected, kLodTolerance * expected) << engine_target_name(c.target) << " at roughness " << r;
    EXPECT_DOUBLE_EQ(out.r, out.g);
    if (lod - std::floor(lod) > 0.1 && lod - std::floor(lod) < 0.9 && lod < c.levels - 1) ++fractional;
  }
  EXPECT_GT(fractional, 10) << "the roughness sweep must fall between levels to see the blend";
}

INSTANTIATE_TEST_SUITE_P(EveryTarget, PreviewLookup,
                         ::testing::Values(Case{EngineTarget::Generic, 5}, Case{EngineTarget::Filament, 7},
                                           Case{EngineTarget::Gltf, 5}, Case{EngineTarget::Babylon, 7},
                                           Case{EngineTarget::KhronosViewer, 5}),
                         [](const ::testing::TestParamInfo<Case>& i) {
                           std::string s = engine_target_name(i.param.target);
                           s.erase(std::remove(s.begin(), s.end(), '-'), s.end());
                           return s;
                         });

// reflectionBlock's MIX_IBL_RADIANCE_WITH_IRRADIANCE: environmentRadiance = mix(environmentRadiance,
// environmentIrradiance, alphaG), alphaG = r^2 + 0.0005. With no irradiance the metal's reflection is
// scaled by exactly 1 - alphaG against the same render with the switch off.
TEST(PreviewLookup, BabylonMixesTheReflectionWithTheIrradianceByAlphaG) {
  for (EngineTarget target : {EngineTarget::Babylon, EngineTarget::Gltf}) {
    SplitSumOptions off;
    off.babylon_mix_ibl_radiance_with_irradiance = false;
    const SplitSum mixed(staircase_files(target, target == EngineTarget::Babylon ? 7 : 5));
    const SplitSum plain(staircase_files(target, target == EngineTarget::Babylon ? 7 : 5), off);
    const Vec3 n{0.0, 0.0, 1.0};
    for (double r : {0.0, 0.3, 0.6, 0.9}) {  // (at r = 1 alphaG is 1.0005: a slightly negative mix, clamped)
      // (the gltf target's mix comes after its gamma step: both sides carry it alike)
      const double a = mixed.shade(n, n, white_metal(r)).r, b = plain.shade(n, n, white_metal(r)).r;
      const double alpha_g = r * r + 0.0005;
      EXPECT_NEAR(a, b * (1.0 - alpha_g), 1e-5 * b) << engine_target_name(target) << " r " << r;
    }
  }
}

// The glTF loader's specular anti-aliasing (getAARoughnessFactors): alphaG + 0.75 sqrt(slopeSquare),
// so the LOD of a mirror moves to log2(S (0.0005 + 0.75 sqrt(s))) x scale; the .env's PBRMaterial
// (babylon) has it off.
TEST(PreviewLookup, TheGltfLoadersSpecularAntiAliasingRaisesAlphaG) {
  SplitSumOptions off;
  off.babylon_mix_ibl_radiance_with_irradiance = false;
  const SplitSum gltf(staircase_files(EngineTarget::Gltf, 5), off);
  const SplitSum env(staircase_files(EngineTarget::Babylon, 7), off);
  const Vec3 n{0.0, 0.0, 1.0};
  const float slope2 = 1.0f / (20.0f * 20.0f);  // a sphere of radius 20 pixels at its centre
  const double scale = 4.0 / std::log2(double(kSize));
  const double expected = std::log2(kSize * (0.0005 + 0.75 * std::sqrt(double(slope2)))) * scale;
  EXPECT_NEAR(std::pow(double(gltf.shade(n, n, white_metal(0.0), slope2).r), 1.0 / 2.2) - 1.0, expected,
              kLodTolerance * (1.0 + expected));
  // a rough metal's alphaG above 1 reaches past the file's last level into Babylon.js's zero levels
  const float rim2 = 4.0f;  // a slope of 2: alphaG = 1.0005 + 1.5
  const double lod = std::log2(kSize * (1.0005 + 0.75 * 2.0)) * scale;
  EXPECT_NEAR(std::pow(double(gltf.shade(n, n, white_metal(1.0), rim2).r), 1.0 / 2.2),
              staircase_value(EngineTarget::Gltf, lod, 5), kLodTolerance);
  EXPECT_DOUBLE_EQ(env.shade(n, n, white_metal(0.0), slope2).r, env.shade(n, n, white_metal(0.0), 0.0f).r);
}

}  // namespace
}  // namespace brdfbake
