// The `filament` target, Filament 1.76 (cmgen -x DIR -f ktx, KtxUtility): the preview's split-sum lookup against the
// engine's own formula (host/src/engines/filament/splitsum.cpp on a staircase chain, test_target_support.hpp) and its
// files read back field by field from the bytes (host/src/engines/filament/writer.cpp). The engine's own render of the
// target's files and its orientation probe: tests/python/test_engine_filament.py (Filament itself, from the pinned
// open3d-cpu wheel on lavapipe, renders the bake's _ibl.ktx / sh.txt; its orientation probe and the planted defects
// there; harness tests/engines/filament/).
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

// perceptualRoughnessToLod, r clamped to MIN_PERCEPTUAL_ROUGHNESS.
TEST(PreviewLookup, FilamentLodIsTheEnginesFormulaAndLevelsBlendLinearly) {
  expect_lookup_is_engines(EngineTarget::Filament, 7, [](double r, int levels) {
    const double pr = std::clamp(r, 0.045, 1.0);
    return (levels - 1) * pr * (2.0 - pr);
  });
}

// ---- The files, read back ----------------------------------------------------------------------

// Filament cmgen (tools/cmgen/src/cmgen.cpp, lodToPerceptualRoughness): the positive root of
// lod = r (2 - r) solved as (sqrt(a^2 + 4 b lod) - a) / (2 b) with a = 2, b = -1, lod = l/(L-1);
// shader (light_indirect.fs, perceptualRoughnessToLod): lod = (L - 1) r (2 - r).
TEST(EngineSchedule, FilamentMatchesCmgenAndItsShader) {
  for (int levels : {2, 5, 9}) {
    for (int l = 0; l < levels; ++l) {
      const double lod = double(l) / (levels - 1);
      const double a = 2.0, b = -1.0;
      const double cmgen = lod != 0 ? std::clamp((std::sqrt(a * a + 4.0 * b * lod) - a) / (2.0 * b), 0.0, 1.0) : 0.0;
      EXPECT_NEAR(schedule_roughness(RoughnessSchedule::Filament, l, levels), cmgen, test::kRoundingFewOps)
          << l << "/" << levels;
    }
    for (double r = 0.0; r <= 1.0; r += 0.0625)
      EXPECT_NEAR(schedule_lod(RoughnessSchedule::Filament, r, levels), (levels - 1) * r * (2.0 - r),
                  test::kRoundingFewOps);
  }
}

// E(n) for L = 1 + x is pi + (2 pi / 3) n.x: E/pi = 1 + (2/3) n.x.
TEST(EngineSh, FilamentPrescaledEvaluatesToIrradianceOverPi) {
  const auto c = filament_sh(sh_one_plus_x());
  for (int sign : {-1, 1}) {
    // Filament's shader (Irradiance_SphericalHarmonics): sh0 + sh1 y + sh2 z + sh3 x + ...
    const double x = sign;
    for (size_t ch = 0; ch < 3; ++ch)
      EXPECT_NEAR(c[0][ch] + c[3][ch] * x + c[8][ch] * x * x, 1.0 + (2.0 / 3.0) * x, test::kRoundingFewOps);
  }
  // constant environment of radiance 1: sh0 = 1 exactly (E/pi = 1), nothing else
  EXPECT_NEAR(c[0][1], 1.0, test::kRoundingFewOps);
  EXPECT_EQ(c[1][0], 0.0);
}

TEST(PackedFloat, EveryFiniteCodeRoundTripsAndMidpointsRoundToEven) {
  for (int m : {io::kUf11MantissaBits, io::kUf10MantissaBits}) {
    const uint32_t max_code = (30u << m) | ((1u << m) - 1u);
    for (uint32_t code = 0; code <= max_code; ++code) {
      const double v = io::decode_unsigned_float(code, m);
      ASSERT_EQ(io::encode_unsigned_float(v, m), code) << m << " " << code;
      if (code < max_code) {
        const double next = io::decode_unsigned_float(code + 1, m);
        const double mid = 0.5 * (v + next);
        ASSERT_EQ(io::encode_unsigned_float(mid, m), (code & 1u) ? code + 1 : code) << "tie at " << mid;
        ASSERT_EQ(io::encode_unsigned_float(std::nextafter(mid, 0.0), m), code);
        ASSERT_EQ(io::encode_unsigned_float(std::nextafter(mid, 1e9), m), code + 1);
      }
    }
    EXPECT_EQ(io::decode_unsigned_float(max_code, m), m == 6 ? io::kUf11Max : io::kUf10Max);
    bool sat = false;
    EXPECT_EQ(io::encode_unsigned_float(1e6, m, &sat), max_code);
    EXPECT_TRUE(sat);
    EXPECT_EQ(io::encode_unsigned_float(INFINITY, m), max_code);  // never infinity
    EXPECT_EQ(io::encode_unsigned_float(NAN, m), 0u);             // never NaN
    EXPECT_EQ(io::encode_unsigned_float(-3.0, m), 0u);            // no sign bit
  }
}

TEST(PackedFloat, PackingIsGlUnsignedInt10f11f11fRev) {
  // R = 1.0 (exp 15, mantissa 0), G = 2.0 (exp 16), B = 0.5 (exp 14), at bits 0, 11 and 22
  const uint32_t p = io::pack_r11g11b10(1.0f, 2.0f, 0.5f);
  EXPECT_EQ(p & 0x7FFu, 15u << 6);
  EXPECT_EQ((p >> 11) & 0x7FFu, 16u << 6);
  EXPECT_EQ(p >> 22, 14u << 5);
  float rgb[3];
  io::unpack_r11g11b10(p, rgb);
  EXPECT_EQ(rgb[0], 1.0f);
  EXPECT_EQ(rgb[1], 2.0f);
  EXPECT_EQ(rgb[2], 0.5f);
}

TEST(Ktx1Keys, OnlyKeysKtx11DefinesPlusOurs) {
  const fs::path dir = temp_dir("ktx1keys");
  fs::create_directories(dir);
  write_cubemap(synthetic_chain(8, 2, RoughnessSchedule::Linear), (dir / "c.ktx").string(), CubeFormat::Ktx1);
  const auto kv = ktx1_keys(read_all(dir / "c.ktx"));
  for (const auto& [k, v] : kv) {
    const bool ours = k.rfind("brdfbake:", 0) == 0;
    EXPECT_TRUE(ours || k == "KTXorientation") << "key " << k << " is neither KTX 1.1's nor namespaced";
  }
  EXPECT_EQ(key(kv, "KTXorientation"), "S=r,T=d");  // KTX 1.1's format (ktx2ktx2 turns it into "rd")
  EXPECT_EQ(key(kv, "KTXwriter"), "<missing>");
  EXPECT_EQ(key(kv, "brdfbake:writer").rfind("brdfbake ", 0), 0u);
  // KTX2 cubes say "rd", the only orientation KTX 2.0 allows for cubemaps, and KTXwriter
  write_cubemap(synthetic_chain(8, 2, RoughnessSchedule::Linear), (dir / "c.ktx2").string(), CubeFormat::Ktx2);
  const io::Ktx2Image k2 = io::read_ktx2((dir / "c.ktx2").string());
  EXPECT_EQ(key(k2.key_values, "KTXorientation"), "rd");
  EXPECT_EQ(key(k2.key_values, "KTXwriter").rfind("brdfbake ", 0), 0u);
}

TEST(Ktx1Keys, R11fG11fB10fHeaderIsKtx11ByDefault) {
  const fs::path dir = temp_dir("r11");
  fs::create_directories(dir);
  CubeWriteOptions o;
  o.pixel = PixelType::R11G11B10;
  const CubeLevels cube = synthetic_chain(8, 1, RoughnessSchedule::Linear);
  write_cubemap(cube, (dir / "c.ktx").string(), CubeFormat::Ktx1, o);
  const auto b = read_all(dir / "c.ktx");
  EXPECT_EQ(u32(b, 16), 0x8C3Bu);  // glType GL_UNSIGNED_INT_10F_11F_11F_REV
  EXPECT_EQ(u32(b, 20), 4u);       // glTypeSize: the packed UInt32
  EXPECT_EQ(u32(b, 24), 0x1907u);  // glFormat GL_RGB
  EXPECT_EQ(u32(b, 28), 0x8C3Au);  // glInternalFormat GL_R11F_G11F_B10F
  EXPECT_EQ(u32(b, 32), 0x1907u);  // glBaseInternalFormat GL_RGB
  const size_t first = 64 + u32(b, 60);
  EXPECT_EQ(u32(b, first), 8u * 8u * 4u);  // imageSize of one face
  float rgb[3];
  io::unpack_r11g11b10(u32(b, first + 4), rgb);  // face +X, texel (0, 0)
  for (size_t c = 0; c < 3; ++c)
    EXPECT_NEAR(rgb[c], cube.levels[0][c], io::unsigned_float_half_ulp(cube.levels[0][c], c < 2 ? 6 : 5));
  EXPECT_THROW(write_cubemap(cube, (dir / "c.ktx2").string(), CubeFormat::Ktx2, o), Error);
  EXPECT_FALSE(fs::exists(dir / "c.ktx2"));
}

TEST(FilamentFiles, CmgenFileSetWithShKeyAndR11Chain) {
  const fs::path dir = temp_dir("venice");
  const CubeLevels chain = synthetic_chain(64, 16, RoughnessSchedule::Filament);
  const ShCoefficients sh = sh_one_plus_x();
  EngineBake bake;
  bake.prefiltered = &chain;
  bake.sh = &sh;
  const EngineWriteResult r = write_engine_files(EngineTarget::Filament, bake, dir.string());
  ASSERT_EQ(r.files.size(), 3u);
  EXPECT_EQ(fs::path(r.files[0]).filename(), "venice_ibl.ktx");  // the folder's name, as cmgen -x
  EXPECT_EQ(fs::path(r.files[1]).filename(), "venice_skybox.ktx");
  EXPECT_EQ(fs::path(r.files[2]).filename(), "sh.txt");
  const auto b = read_all(dir / "venice_ibl.ktx");
  EXPECT_EQ(u32(b, 16), 0x8C3Au);  // glType as Filament's KtxUtility::toPixelDataType maps it
  EXPECT_EQ(u32(b, 28), 0x8C3Au);
  EXPECT_EQ(u32(b, 36), 64u);
  EXPECT_EQ(u32(b, 52), 6u);  // numberOfFaces
  EXPECT_EQ(u32(b, 56), 3u);  // numberOfMipmapLevels: 64, 32, 16
  const auto kv = ktx1_keys(b);
  // "sh": 27 numbers, bands 0..2, each c_k = Y-constant (A_l/pi) L_lm
  std::istringstream in(key(kv, "sh"));
  std::vector<double> v;
  for (double x; in >> x;) v.push_back(x);
  ASSERT_EQ(v.size(), 27u);
  EXPECT_NEAR(v[0], 1.0, test::kTextNineDigits);
  EXPECT_NEAR(v[9], 2.0 / 3.0, test::kTextNineDigits);
  EXPECT_EQ(key(kv, "brdfbake:engine_target"), "filament");
  EXPECT_EQ(key(kv, "KTXwriter"), "<missing>");
  const auto sky = read_all(dir / "venice_skybox.ktx");
  EXPECT_EQ(u32(sky, 56), 1u);
  // The skybox is one level: the chain's schedule and LOD mapping do not describe it (issue 34: its
  // caption said "1 level ... (levels = 3)")
  const auto sky_kv = ktx1_keys(sky);
  EXPECT_EQ(key(sky_kv, "brdfbake:levels"), "1");
  EXPECT_EQ(key(sky_kv, "brdfbake:roughness_schedule"), "<missing>");
  EXPECT_EQ(key(sky_kv, "brdfbake:lod_from_roughness"), "<missing>");
  EXPECT_EQ(key(kv, "brdfbake:roughness_schedule"), "filament");  // the chain keeps them
  const std::string txt(reinterpret_cast<const char*>(read_all(dir / "sh.txt").data()), fs::file_size(dir / "sh.txt"));
  EXPECT_NE(txt.find("); // L00, irradiance, pre-scaled base"), std::string::npos);
  EXPECT_NE(key(r.delivered, "venice_ibl.ktx: storage_max_rel_error_per_level"), "<missing>");
}

TEST(FilamentFiles, RefusesAChainOfAnotherSchedule) {
  const fs::path dir = temp_dir("wrong");
  const CubeLevels chain = synthetic_chain(16, 4, RoughnessSchedule::Linear);
  const ShCoefficients sh = sh_one_plus_x();
  EngineBake bake{&chain, &sh};
  try {
    write_engine_files(EngineTarget::Filament, bake, dir.string());
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'linear' schedule"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir));  // nothing left behind
}

}  // namespace
}  // namespace brdfbake
