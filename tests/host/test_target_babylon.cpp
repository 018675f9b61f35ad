// The `babylon` target, Babylon.js 8.46.2's .env (EnvironmentTextureTools): the preview's split-sum lookup against the
// engine's own formula (host/src/engines/babylon/splitsum.cpp on a staircase chain, test_target_support.hpp) and its
// files read back field by field from the bytes (host/src/engines/babylon/writer.cpp). The engine's own render of the
// target's files and its orientation probe: tests/python/test_engine_babylon.py (Babylon.js in headless Chromium
// renders the bake's .env; its orientation probe and the planted defects there; harness tests/engines/babylon/).
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

// getLodFromAlphaG x 0.8.
TEST(PreviewLookup, BabylonLodIsTheEnginesFormulaAndLevelsBlendLinearly) {
  expect_lookup_is_engines(EngineTarget::Babylon, 7,
                           [](double r, int /*levels*/) { return std::log2(kSize * (r * r + 0.0005)) * 0.8; });
}

// reflectionBlock's MIX_IBL_RADIANCE_WITH_IRRADIANCE weight (expect_mix_by_alpha_g).
TEST(PreviewLookup, BabylonMixesTheReflectionWithTheIrradianceByAlphaG) {
  expect_mix_by_alpha_g(EngineTarget::Babylon);
}

// ---- The files, read back ----------------------------------------------------------------------

// Babylon.js HDRFiltering: alphaG = 2^(lod / 0.8) / width, 0 at lod 0; pbrBlockReflection:
// lod = log2(width * alphaG) * 0.8 with alphaG = roughness^2 + 0.0005.
TEST(EngineSchedule, BabylonMatchesHdrFilteringAndItsShader) {
  for (int size : {64, 256}) {
    const int levels = int(std::log2(size)) + 1;
    EXPECT_EQ(schedule_roughness(RoughnessSchedule::Babylon, 0, levels), 0.0);
    for (int l = 1; l < levels; ++l) {
      const double alpha = std::pow(2.0, l / 0.8) / size;
      const double r = schedule_roughness(RoughnessSchedule::Babylon, l, levels);
      EXPECT_NEAR(r, std::min(1.0, std::sqrt(alpha)), test::kRoundingFewOps) << l;
      if (alpha <= 1.0) {
        // The shader lands on level l up to the 0.0005 Babylon adds to alpha before the lookup.
        const double shader = 0.8 * std::log2(size * (r * r + 0.0005));
        EXPECT_NEAR(schedule_lod(RoughnessSchedule::Babylon, r, levels), shader, test::kRoundingFewOps);
        EXPECT_NEAR(shader, l, 0.8 * std::log2(1.0 + 0.0005 / alpha) + test::kRoundingFewOps) << l;
      }
    }
    // roughness 1 sits at 0.8 log2(size): the levels above it are never read, as in Babylon
    EXPECT_NEAR(schedule_lod(RoughnessSchedule::Babylon, 1.0, levels), 0.8 * std::log2(size * 1.0005),
                test::kRoundingFewOps);
    EXPECT_EQ(schedule_lod(RoughnessSchedule::Babylon, 0.0, levels), 0.0);  // clamped at the mirror
  }
  EXPECT_EQ(roughness_schedule_from_name("babylon"), RoughnessSchedule::Babylon);
}

// Babylon's .env stores SphericalPolynomial.FromHarmonics of the irradiance SH / pi; its renderer
// (the default SPHERICAL_HARMONICS path) turns the polynomial back into pre-scaled harmonics with
// SphericalHarmonics.FromPolynomial + preScaleForRendering and evaluates sum h_lm Y_lm(n). That
// round trip, with Babylon's constants, must give E/pi = 1 + (2/3) n.x.
TEST(EngineSh, BabylonPolynomialReadsBackAsIrradianceOverPi) {
  const auto p = babylon_polynomial(sh_one_plus_x());
  const size_t c = 0;
  const double x = p[0][c], y = p[1][c], z = p[2][c], xx = p[3][c], yy = p[4][c], zz = p[5][c];
  // FromPolynomial (sphericalPolynomial.ts), then the sign flips and the scale by pi
  const double l00 = kPi * (0.376127 * xx + 0.376127 * yy + 0.376126 * zz);
  const double l11 = -kPi * 0.977204 * x;
  const double l1m1 = -kPi * 0.977204 * y, l10 = kPi * 0.977204 * z;
  const double l20 = kPi * (1.34567 * zz - 0.672834 * xx - 0.672834 * yy);
  const double l22 = kPi * 1.16538 * (xx - yy);
  for (int sign : {-1, 1}) {
    const double n[3] = {double(sign), 0.0, 0.0};
    const double e = l00 * std::sqrt(1 / (4 * kPi)) - l1m1 * std::sqrt(3 / (4 * kPi)) * n[1] +
                     l10 * std::sqrt(3 / (4 * kPi)) * n[2] - l11 * std::sqrt(3 / (4 * kPi)) * n[0] +
                     l20 * std::sqrt(5 / (16 * kPi)) * (3 * n[2] * n[2] - 1) +
                     l22 * std::sqrt(15 / (16 * kPi)) * (n[0] * n[0] - n[1] * n[1]);
    // Babylon's 0.886277 (for pi Y_00 = 0.886227) puts band 0 5.6e-5 high; the rest of its
    // constants carry 6 digits
    EXPECT_NEAR(e, 1.0 + (2.0 / 3.0) * sign, test::kBabylonBand0) << sign;
  }
  // the stored polynomial itself: band 0 through 0.886277 (Babylon's value for pi Y_00 = 0.886227)
  EXPECT_NEAR(xx, 0.886277 * 2.0 / std::sqrt(kPi), test::kRoundingFewOps);
  EXPECT_NEAR(x, 1.02333 * (2.0 / 3.0) * 0.4886025119029199 * 4.0 / 3.0, test::kRoundingFewOps);
}

TEST(BabylonEnv, RoundTripsFieldByFieldWithinRgbdPrecision) {
  const fs::path dir = temp_dir("env");
  const CubeLevels chain = synthetic_chain(16, 1, RoughnessSchedule::Babylon);
  const ShCoefficients sh = sh_one_plus_x();
  EngineBake bake{&chain, &sh};
  EngineWriteOptions o;
  o.name = "studio";
  write_engine_files(EngineTarget::Babylon, bake, dir.string(), o);
  const auto b = read_all(dir / "studio.env");
  const uint8_t magic[8] = {0x86, 0x16, 0x87, 0x96, 0xF6, 0xD6, 0x96, 0x36};
  ASSERT_EQ(std::memcmp(b.data(), magic, 8), 0);
  size_t nul = 8;
  while (b[nul] != 0) ++nul;
  for (size_t i = 8; i < nul; ++i) ASSERT_LT(b[i], 0x80) << "the manifest must be ASCII";
  const auto m = nlohmann::json::parse(b.begin() + 8, b.begin() + std::ptrdiff_t(nul));
  EXPECT_EQ(m.at("version"), 2);
  EXPECT_EQ(m.at("width"), 16);
  EXPECT_EQ(m.at("imageType"), "image/png");
  EXPECT_DOUBLE_EQ(m.at("specular").at("lodGenerationScale").get<double>(), 0.8);
  // Babylon.js's left-handed world (engines/babylon_frame.hpp): the polynomial and the cube mirrored in x
  const auto p = detail::mirror_babylon_polynomial_x(babylon_polynomial(sh));
  for (size_t k = 0; k < 9; ++k)
    EXPECT_DOUBLE_EQ(m.at("irradiance").at(kBabylonPolynomialNames[k])[1].get<double>(), p[k][1]);
  EXPECT_DOUBLE_EQ(p[0][1], -babylon_polynomial(sh)[0][1]);  // x: odd in x
  const CubeLevels stored = detail::mirror_cube_x(chain);
  const auto& mips = m.at("specular").at("mipmaps");
  ASSERT_EQ(mips.size(), 6u * 5u);  // 16, 8, 4, 2, 1
  size_t expect_position = 0;
  double worst = 0.0;
  for (size_t n = 0; n < mips.size(); ++n) {
    const size_t position = mips[n].at("position"), length = mips[n].at("length");
    EXPECT_EQ(position, expect_position);  // contiguous, level-major
    expect_position += length;
    const int level = int(n / 6), face = int(n % 6);
    int w = 0, h = 0;
    const auto rgba = io::decode_png_rgba8(b.data() + nul + 1 + position, length, &w, &h);
    ASSERT_EQ(w, chain.level_size(level));
    ASSERT_EQ(h, w);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const uint8_t* t = &rgba[4 * (size_t(j) * size_t(w) + size_t(i))];
        double d[3];
        io::rgbd_decode(t, d);
        // Babylon.js reads row 0 of a face image as the face's last row: written bottom row first
        const float* ref = stored.texel(level, face, i, h - 1 - j);
        for (int c = 0; c < 3; ++c) {
          // within half an 8-bit step of RGBD at this code: the encoding's precision
          ASSERT_LE(std::fabs(d[c] - double(ref[c])), io::rgbd_half_step(t, c) * (1 + 1e-9))
              << "level " << level << " face " << face << " (" << i << ", " << j << ") channel " << c;
          worst = std::max(worst, std::fabs(d[c] - double(ref[c])) / double(std::max({ref[0], ref[1], ref[2]})));
        }
      }
  }
  EXPECT_EQ(nul + 1 + expect_position, b.size());
  // Texels above 1 keep their largest channel within about 2.2 x 0.5/255 / 0.73 (0.6%); darker
  // ones are plain 8-bit gamma 2.2 (D = 1), coarser: at this chain's floor 0.05, half a code step.
  const double g = std::pow(0.05, 1 / 2.2);
  EXPECT_LE(worst, (std::pow(g + 0.5 / 255.0, 2.2) - 0.05) / 0.05);
  EXPECT_GT(worst, 0.0);
  const io::BabylonEnv env = io::decode_babylon_env(b);  // and through the parser
  EXPECT_EQ(env.images.size(), 30u);
  EXPECT_EQ(env.extra.at("brdfbake").at("engine_target"), "babylon");
}

TEST(BabylonEnv, RgbdMatchesBabylonsFormulaAndClampsAbove255) {
  const float v[3] = {2.0f, 1.0f, 0.25f};
  uint8_t t[4];
  io::rgbd_encode(v, t);
  EXPECT_EQ(t[3], 127);  // D = floor(255 / 2) / 255
  EXPECT_EQ(t[0], uint8_t(std::lround(std::pow(2.0 * 127 / 255, 1 / 2.2) * 255)));
  const float big[3] = {1000.0f, 1.0f, 1.0f};
  bool clamped = false;
  io::rgbd_encode(big, t, &clamped);
  EXPECT_TRUE(clamped);
  EXPECT_EQ(t[3], 1);
  EXPECT_EQ(t[0], 255);
}

TEST(BabylonEnv, NeedsTheFullChain) {
  const CubeLevels chain = synthetic_chain(16, 4, RoughnessSchedule::Babylon);
  const ShCoefficients sh = sh_one_plus_x();
  EngineBake bake{&chain, &sh};
  EXPECT_THROW(write_engine_files(EngineTarget::Babylon, bake, temp_dir("partial").string()), Error);
}

}  // namespace
}  // namespace brdfbake
