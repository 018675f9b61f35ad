// The `gltf` target, glTF 2.0 EXT_lights_image_based, as Babylon.js 8.46.2's glTF loader reads it: the preview's
// split-sum lookup against the engine's own formula (host/src/engines/gltf/splitsum.cpp on a staircase chain,
// test_target_support.hpp) and its files read back field by field from the bytes (host/src/engines/gltf/writer.cpp).
// The engine's own render of the target's files and its orientation probe: tests/python/test_engine_babylon.py
// (Babylon.js's glTF loader in headless Chromium renders the bake's .gltf; its orientation probe and the planted
// defects there; harness tests/engines/babylon/), and the document against the extension's schema
// (engines.gltf_ext_lights_image_based_schema, tests/engines/validate_gltf_ibl.py, which runs GltfIbl.* here).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "brdfbake/engines.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "engines/babylon_frame.hpp"
#include "io/babylon_env.hpp"
#include "io/cubemap_io.hpp"
#include "io/ktx2.hpp"
#include "io/packed_float.hpp"
#include "io/png_rgbd.hpp"
#include "support/tolerances.hpp"
#include "test_target_support.hpp"

namespace brdfbake {
namespace {

using namespace target_test;  // NOLINT: the shared helpers of every target's test

// ---- The split-sum lookup ------------------------------------------------------------------------

// getLodFromAlphaG x (N - 1) / log2 S.
TEST(PreviewLookup, GltfLodIsTheEnginesFormulaAndLevelsBlendLinearly) {
  expect_lookup_is_engines(EngineTarget::Gltf, 5, [](double r, int levels) {
    return std::log2(kSize * (r * r + 0.0005)) * (levels - 1) / std::log2(double(kSize));
  });
}

// reflectionBlock's MIX_IBL_RADIANCE_WITH_IRRADIANCE weight (expect_mix_by_alpha_g).
TEST(PreviewLookup, GltfMixesTheReflectionWithTheIrradianceByAlphaG) { expect_mix_by_alpha_g(EngineTarget::Gltf); }

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

// ---- The files, read back ----------------------------------------------------------------------

TEST(EngineSh, GltfIrradianceCoefficientsAreBabylonBasisIrradiance) {
  const auto e = gltf_irradiance_coefficients(sh_one_plus_x());
  // Babylon's SH3ylmBasisConstants (with the Condon-Shortley sign): l00 1/(2 sqrt(pi)), l11
  // -sqrt(3/(4 pi)) x; sum E_lm Y_lm(n) = E(n) = pi + (2 pi/3) n.x.
  for (int sign : {-1, 1})
    EXPECT_NEAR(e[0][0] * 0.5 / std::sqrt(kPi) - e[3][0] * std::sqrt(3.0 / (4.0 * kPi)) * sign,
                kPi + 2.0 * kPi / 3.0 * sign, test::kRoundingSums);
  EXPECT_LT(e[3][0], 0.0);  // the sign flip of l11
}

TEST(GltfIbl, DocumentImagesAndCoefficients) {
  // BRDFBAKE_GLTF_OUT: write into that folder and keep it (tests/engines/validate_gltf_ibl.py
  // validates the document against the extension's schema)
  const char* keep = std::getenv("BRDFBAKE_GLTF_OUT");
  const fs::path dir = keep ? fs::path(keep) : temp_dir("gltf");
  const CubeLevels chain = synthetic_chain(32, 16, RoughnessSchedule::Linear);
  const ShCoefficients sh = sh_one_plus_x();
  EngineBake bake{&chain, &sh};
  EngineWriteOptions o;
  o.name = "env";
  const EngineWriteResult r = write_engine_files(EngineTarget::Gltf, bake, dir.string(), o);
  EXPECT_EQ(r.files.size(), 1u + 12u);
  const auto text = read_all(dir / "env.gltf");
  const auto g = nlohmann::json::parse(text.begin(), text.end());
  EXPECT_EQ(g.at("asset").at("version"), "2.0");
  EXPECT_EQ(g.at("extensionsUsed")[0], "EXT_lights_image_based");
  EXPECT_EQ(g.at("scenes")[0].at("extensions").at("EXT_lights_image_based").at("light"), 0);
  const auto& light = g.at("extensions").at("EXT_lights_image_based").at("lights")[0];
  EXPECT_EQ(light.at("specularImageSize"), 32);
  EXPECT_EQ(light.at("intensity"), 1.0);
  ASSERT_EQ(light.at("specularImages").size(), 2u);
  const auto e = gltf_irradiance_coefficients(sh);
  ASSERT_EQ(light.at("irradianceCoefficients").size(), 9u);
  // Babylon.js's left-handed world (engines/babylon_frame.hpp): mirrored in x, so l11 (x)
  // changes sign and l00 does not; rotation identity
  EXPECT_DOUBLE_EQ(light.at("irradianceCoefficients")[3][0].get<double>(), -e[3][0]);
  EXPECT_DOUBLE_EQ(light.at("irradianceCoefficients")[0][0].get<double>(), e[0][0]);
  EXPECT_EQ(light.at("rotation"), nlohmann::json::array({0.0, 0.0, 0.0, 1.0}));
  EXPECT_EQ(g.at("asset").at("extras").at("brdfbake").at("babylon_scene"), "left-handed");
  // every referenced image exists and is an RGBA PNG of its level's size, holding the mirrored cube
  // bottom row first: texel (i, j) of face f at image row s - 1 - j is the source's (-x, y, z) texel
  const CubeLevels mirrored = detail::mirror_cube_x(chain);
  for (size_t l = 0; l < 2; ++l)
    for (size_t f = 0; f < 6; ++f) {
      const int index = light.at("specularImages")[l][f];
      const std::string uri = g.at("images")[size_t(index)].at("uri");
      const auto png = read_all(dir / uri);
      int w = 0, h = 0;
      const auto rgba = io::decode_png_rgba8(png.data(), png.size(), &w, &h);
      EXPECT_EQ(w, 32 >> l);
      // a bright texel (the chain grows as (a b)^3 towards the corner i, j = size - 1 of every face), so that
      // the row order and the mirror both move it by far more than RGBD's precision (3 %: half an 8-bit
      // step of gamma 2.2 is 1.3 % at 0.05, less above)
      const int i = 2, j = h - 3;  // the mirror takes it from i = size - 3 of the source
      double d[3];
      io::rgbd_decode(&rgba[4 * (size_t(h - 1 - j) * size_t(w) + size_t(i))], d);
      const float* ref = mirrored.texel(int(l), int(f), i, j);
      EXPECT_NEAR(d[0], double(ref[0]), 0.03 * double(ref[0])) << "level " << l << " face " << f;
      EXPECT_GT(std::fabs(double(ref[0]) - double(mirrored.texel(int(l), int(f), i, h - 1 - j)[0])),
                0.1 * double(ref[0]));
    }
  // for a right-handed scene (which flips every lookup's z): the same mirrored cube and coefficients,
  // rotation (0, 1, 0, 0)
  o.gltf_scene = GltfScene::RightHanded;
  const fs::path rh = temp_dir("gltf-rh");
  write_engine_files(EngineTarget::Gltf, bake, rh.string(), o);
  const auto rtext = read_all(rh / "env.gltf");
  const auto rg = nlohmann::json::parse(rtext.begin(), rtext.end());
  const auto& rlight = rg.at("extensions").at("EXT_lights_image_based").at("lights")[0];
  EXPECT_DOUBLE_EQ(rlight.at("irradianceCoefficients")[3][0].get<double>(), -e[3][0]);
  EXPECT_EQ(rlight.at("rotation"), nlohmann::json::array({0.0, 1.0, 0.0, 0.0}));
}

TEST(GltfIbl, MirroringInXIsAnExactInvolution) {
  const CubeLevels chain = synthetic_chain(8, 1, RoughnessSchedule::Linear);
  const CubeLevels twice = detail::mirror_cube_x(detail::mirror_cube_x(chain));
  ASSERT_EQ(twice.levels, chain.levels);
  const CubeLevels once = detail::mirror_cube_x(chain);
  // +X face's texel (i, j) looks along (1, -b, -a): mirrored, it holds -X's texel at (-1, -b, -a),
  // which is -X's (s - 1 - i, j)
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i) EXPECT_EQ(once.texel(0, 0, i, j)[0], chain.texel(0, 1, 7 - i, j)[0]);
}

}  // namespace
}  // namespace brdfbake
