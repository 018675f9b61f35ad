// What the per-target tests (tests/host/test_target_<target>.cpp) share: the files' round trips' helpers
// (temporary folders, bytes, synthetic chains and SH, KTX1 keys) and the split-sum lookup's staircase (a chain
// whose level l holds the constant l + 1, so that a mirror-like metal of F0 1 reflects exactly 1 + the LOD the
// target's shader computed, blended linearly between the two nearest levels. A white furnace (all levels equal)
// cannot see a wrong LOD or a missing blend; this can: Filament's perceptualRoughnessToLod made linear,
// Babylon.js's LOD without its lodGenerationScale, or no blending between levels each move the measured LOD by
// far more than the tolerance).
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "brdfbake/engines.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/preview.hpp"
#include "families/preview/bake_files.hpp"
#include "families/preview/splitsum.hpp"
#include "support/temp_dir.hpp"

namespace brdfbake::target_test {

namespace fs = std::filesystem;
using brdfbake::math::kPi;
using detail::preview::BakeFiles;
using detail::preview::DiffuseSource;
using detail::preview::SplitSum;
using detail::preview::SplitSumOptions;

// ---- Files ---------------------------------------------------------------------------------------

// `name` in the test's temporary folder (removed when the test ends, support/temp_dir.hpp), not there yet.
inline fs::path temp_dir(const std::string& name) {
  const fs::path d = brdfbake::test::test_temp_root() / name;
  fs::remove_all(d);
  return d;
}

inline std::vector<uint8_t> read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

inline uint32_t u32(const std::vector<uint8_t>& b, size_t at) {
  return uint32_t(b.at(at)) | uint32_t(b.at(at + 1)) << 8 | uint32_t(b.at(at + 2)) << 16 | uint32_t(b.at(at + 3)) << 24;
}
inline uint64_t u64(const std::vector<uint8_t>& b, size_t at) {
  return uint64_t(u32(b, at)) | uint64_t(u32(b, at + 4)) << 32;
}

// A chain with smooth, direction-dependent HDR values (0.05 .. 40), as a bake would give, and the
// metadata of the schedule.
inline CubeLevels synthetic_chain(int size, int min_size, RoughnessSchedule schedule) {
  CubeLevels c;
  c.size = size;
  for (int s = size; s >= min_size; s /= 2) {
    const int l = c.level_count();
    std::vector<float> v;
    for (int f = 0; f < 6; ++f)
      for (int j = 0; j < s; ++j)
        for (int i = 0; i < s; ++i) {
          const double a = (i + 0.5) / s, b = (j + 0.5) / s;
          const double base = 0.05 + 40.0 * std::pow(a * b, 3.0) * (f == 2 ? 1.0 : 0.2) / (1 + l);
          v.insert(v.end(), {float(base), float(base * (0.5 + 0.5 * a)), float(base * (0.3 + 0.7 * b)), 1.0f});
        }
    c.levels.push_back(v);
    if (s == 1) break;
  }
  c.set_meta("roughness_schedule", roughness_schedule_name(schedule));
  return c;
}

// SH of the radiance L(d) = 1 + d.x: L_00 = 2 sqrt(pi), L_11 (index 3, x) = 0.488603 * 4 pi / 3.
inline ShCoefficients sh_one_plus_x() {
  ShCoefficients sh;
  sh.order = 3;
  sh.radiance.assign(27, 0.0);
  sh.irradiance_over_pi.assign(27, 0.0);
  for (size_t c = 0; c < 3; ++c) {
    sh.radiance[c] = 2.0 * std::sqrt(kPi);
    sh.radiance[9 + c] = 0.4886025119029199 * 4.0 * kPi / 3.0;
    sh.irradiance_over_pi[c] = sh.radiance[c];                        // A_0 / pi = 1
    sh.irradiance_over_pi[9 + c] = (2.0 / 3.0) * sh.radiance[9 + c];  // A_1 / pi = 2/3
  }
  sh.window_weights = {1, 1, 1};
  return sh;
}

// The key/value pairs of a KTX1 file, read from the bytes (KTX 1.1 "keyAndValueByteSize").
inline std::vector<std::pair<std::string, std::string>> ktx1_keys(const std::vector<uint8_t>& b) {
  std::vector<std::pair<std::string, std::string>> kv;
  const size_t end = 64 + u32(b, 60);
  for (size_t at = 64; at < end;) {
    const uint32_t n = u32(b, at);
    const std::string entry(reinterpret_cast<const char*>(&b[at + 4]), n);
    const size_t nul = entry.find('\0');
    std::string value = entry.substr(nul + 1);
    if (!value.empty() && value.back() == '\0') value.pop_back();
    kv.emplace_back(entry.substr(0, nul), value);
    at += 4 + ((n + 3) & ~3u);
  }
  return kv;
}

inline std::string key(const std::vector<std::pair<std::string, std::string>>& kv, const std::string& k) {
  for (const auto& [a, b] : kv)
    if (a == k) return b;
  return "<missing>";
}

// ---- The split-sum lookup ------------------------------------------------------------------------

// The lookup is fp32 (as a shader): the LOD's log2 and products round at ~1e-7 relative, the trilinear
// weights at ~1e-7 of a level; 1e-4 of a level is far above that and far below what any defect above
// moves (Filament's linear LOD at r = 0.5 is off by 1.5 levels of 6; no blend by up to half a level).
constexpr double kLodTolerance = 1e-4;

constexpr int kSize = 64;

// A chain of `levels` levels of a kSize cube, level l the constant l + 1.
inline CubeLevels staircase(int levels) {
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
inline Table unit_dfg() {
  Table t;
  t.width = t.height = 8;
  t.channels = {"bias", "albedo"};
  t.data.assign(8 * 8 * 2, 0.0f);
  for (size_t k = 1; k < t.data.size(); k += 2) t.data[k] = 1.0f;
  return t;
}

// The bake files of `target` with a staircase chain and no diffuse light (every coefficient 0).
inline BakeFiles staircase_files(EngineTarget target, int levels) {
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

inline PreviewMaterial white_metal(double roughness) {
  PreviewMaterial m;
  m.base_color = {1.0, 1.0, 1.0};
  m.metallic = 1.0;
  m.roughness = roughness;
  return m;
}

// What the staircase reflects at that LOD: 1 + lod, clamped to the chain; for gltf, Babylon.js's cube
// has log2(kSize) + 1 levels, those past the file's `levels` zero, so past the last level the value
// falls linearly to 0 over one level.
inline double staircase_value(EngineTarget target, double lod, int levels) {
  const double last = levels - 1;
  if (target != EngineTarget::Gltf || lod <= last) return 1.0 + std::clamp(lod, 0.0, last);
  return levels * std::max(0.0, 1.0 - (lod - last));
}

// Level l holds l + 1, blended linearly: the metal reflects 1 + lod (the gltf target's reflection
// raised to 2.2 once more: the glTF loader's gamma, undone here). engine_lod: the engine's own LOD for a
// perceptual roughness r on a chain of `levels` levels of kSize (before textureLod's clamp).
inline void expect_lookup_is_engines(EngineTarget target, int levels, double (*engine_lod)(double r, int levels)) {
  SplitSumOptions o;
  o.babylon_mix_ibl_radiance_with_irradiance = false;  // its weight is expect_mix_by_alpha_g's
  const SplitSum split(staircase_files(target, levels), o);
  const Vec3 n{0.0, 0.0, 1.0};
  int fractional = 0;
  for (double r = 0.0; r <= 1.0 + 1e-9; r += 0.025) {
    const Rgb out = split.shade(n, n, white_metal(r));
    double value = out.r;
    if (target == EngineTarget::Gltf) value = std::pow(value, 1.0 / 2.2);
    const double lod = engine_lod(r, levels), expected = staircase_value(target, lod, levels);
    EXPECT_NEAR(value, expected, kLodTolerance * expected) << engine_target_name(target) << " at roughness " << r;
    EXPECT_DOUBLE_EQ(out.r, out.g);
    if (lod - std::floor(lod) > 0.1 && lod - std::floor(lod) < 0.9 && lod < levels - 1) ++fractional;
  }
  EXPECT_GT(fractional, 10) << "the roughness sweep must fall between levels to see the blend";
}

// reflectionBlock's MIX_IBL_RADIANCE_WITH_IRRADIANCE: environmentRadiance = mix(environmentRadiance,
// environmentIrradiance, alphaG), alphaG = r^2 + 0.0005. With no irradiance the metal's reflection is
// scaled by exactly 1 - alphaG against the same render with the switch off (babylon, gltf).
inline void expect_mix_by_alpha_g(EngineTarget target) {
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

}  // namespace brdfbake::target_test
