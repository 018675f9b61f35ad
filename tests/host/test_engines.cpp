// Engine targets (brdfbake/engines.hpp): each engine's roughness <-> lod mapping against the
// engine's own formula, the SH conventions against closed forms, the packed R11F_G11F_B10F codec
// exhaustively, and every target's files read back field by field from the bytes (KTX1 header and
// keys, Filament's "sh" key, the Babylon .env manifest and its RGBD PNG faces decoded against the
// float chain, the glTF document, the ASTC HDR KTX2 structure and its measured error). No device:
// the chains are synthetic. The Filament comparison with cmgen runs in tests/device.
#include <astcenc.h>
#include <gtest/gtest.h>
#include <unistd.h>

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
#include "io/astc_ktx2.hpp"
#include "io/babylon_env.hpp"
#include "io/cubemap_io.hpp"
#include "io/ktx2.hpp"
#include "io/packed_float.hpp"
#include "io/png_rgbd.hpp"
#include "support/temp_dir.hpp"
#include "support/tolerances.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;
using brdfbake::math::kPi;

// `name` in the test's temporary folder (removed when the test ends), not there yet.
fs::path temp_dir(const std::string& name) {
  const fs::path d = brdfbake::test::test_temp_root() / name;
  fs::remove_all(d);
  return d;
}

std::vector<uint8_t> read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

uint32_t u32(const std::vector<uint8_t>& b, size_t at) {
  return uint32_t(b.at(at)) | uint32_t(b.at(at + 1)) << 8 | uint32_t(b.at(at + 2)) << 16 | uint32_t(b.at(at + 3)) << 24;
}
uint64_t u64(const std::vector<uint8_t>& b, size_t at) { return uint64_t(u32(b, at)) | uint64_t(u32(b, at + 4)) << 32; }

// A chain with smooth, direction-dependent HDR values (0.05 .. 40), as a bake would give, and the
// metadata of the schedule.
CubeLevels synthetic_chain(int size, int min_size, RoughnessSchedule schedule) {
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
ShCoefficients sh_one_plus_x() {
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

// ---- Descriptor ------------------------------------------------------------------------------------

TEST(EngineTarget, NamesRoundTripAndUnknownIsAnError) {
  for (const std::string& n : engine_target_names()) EXPECT_EQ(engine_target_name(engine_target_from_name(n)), n);
  EXPECT_EQ(engine_target_names().size(), 5u);
  try {
    engine_target_from_name("unreal");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("khronos-viewer"), std::string::npos) << e.what();
  }
}

TEST(EngineTarget, SettingsFixWhatEachEngineReads) {
  const EngineSettings f = engine_settings(EngineTarget::Filament);
  EXPECT_EQ(f.schedule, RoughnessSchedule::Filament);
  EXPECT_EQ(f.pixel, PixelType::R11G11B10);
  EXPECT_EQ(f.size, 256);     // cmgen IBL_DEFAULT_SIZE
  EXPECT_EQ(f.min_size, 16);  // cmgen IBL_DEFAULT_MIN_LOD_SIZE
  EXPECT_TRUE(f.skybox);
  EXPECT_EQ(f.files, (std::vector<std::string>{"NAME_ibl.ktx", "NAME_skybox.ktx", "sh.txt"}));
  EXPECT_EQ(engine_settings(EngineTarget::Babylon).schedule, RoughnessSchedule::Babylon);
  EXPECT_EQ(engine_settings(EngineTarget::Babylon).min_size, 1);  // .env holds the full chain
  EXPECT_EQ(engine_settings(EngineTarget::Gltf).schedule, RoughnessSchedule::Linear);
  EXPECT_EQ(engine_settings(EngineTarget::KhronosViewer).schedule, RoughnessSchedule::Linear);
  EXPECT_EQ(engine_settings(EngineTarget::Generic).schedule, RoughnessSchedule::Linear);
  EXPECT_EQ(engine_settings(EngineTarget::Generic).pixel, PixelType::F16);
}

// ---- Schedules against each engine's own formula ----------------------------------------------------

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

// glTF-IBL-Sampler: roughness = currentMipLevel / (mipLevelCount - 1); glTF-Sample-Viewer:
// lod = roughness * float(u_MipCount - 1).
TEST(EngineSchedule, KhronosLinearMatchesSamplerAndViewer) {
  const int levels = 5;
  for (int l = 0; l < levels; ++l)
    EXPECT_DOUBLE_EQ(schedule_roughness(RoughnessSchedule::Linear, l, levels), double(l) / (levels - 1));
  for (double r = 0.0; r <= 1.0; r += 0.125)
    EXPECT_DOUBLE_EQ(schedule_lod(RoughnessSchedule::Linear, r, levels), r * (levels - 1));
}

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

// ---- SH conventions ----------------------------------------------------------------------------

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

TEST(EngineSh, GltfIrradianceCoefficientsAreBabylonBasisIrradiance) {
  const auto e = gltf_irradiance_coefficients(sh_one_plus_x());
  // Babylon's SH3ylmBasisConstants (with the Condon-Shortley sign): l00 1/(2 sqrt(pi)), l11
  // -sqrt(3/(4 pi)) x; sum E_lm Y_lm(n) = E(n) = pi + (2 pi/3) n.x.
  for (int sign : {-1, 1})
    EXPECT_NEAR(e[0][0] * 0.5 / std::sqrt(kPi) - e[3][0] * std::sqrt(3.0 / (4.0 * kPi)) * sign,
                kPi + 2.0 * kPi / 3.0 * sign, test::kRoundingSums);
  EXPECT_LT(e[3][0], 0.0);  // the sign flip of l11
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

// ---- R11F_G11F_B10F ----------------------------------------------------------------------------

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

// ---- KTX 1.1 keys --------------------------------------------------------------------------------

// The key/value pairs of a KTX1 file, read from the bytes (KTX 1.1 "keyAndValueByteSize").
std::vector<std::pair<std::string, std::string>> ktx1_keys(const std::vector<uint8_t>& b) {
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

std::string key(const std::vector<std::pair<std::string, std::string>>& kv, const std::string& k) {
  for (const auto& [a, b] : kv)
    if (a == k) return b;
  return "<missing>";
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

// ---- Filament ----------------------------------------------------------------------------------

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

// ---- Babylon .env -----------------------------------------------------------------------------

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

// ---- glTF EXT_lights_image_based --------------------------------------------------------------

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

// ---- ASTC HDR KTX2 ------------------------------------------------------------------------------

// Six faces of `size`^2 texels of ASTC HDR blocks (`block` x `block`, 16 bytes each, consecutive
// faces of `face_bytes`) decoded to RGBA float by a decompress-only astcenc context.
std::vector<float> astc_decode_faces(const uint8_t* blocks, size_t face_bytes, unsigned size, int block) {
  astcenc_config config{};
  EXPECT_EQ(astcenc_config_init(ASTCENC_PRF_HDR, unsigned(block), unsigned(block), 1, ASTCENC_PRE_FASTEST,
                                ASTCENC_FLG_DECOMPRESS_ONLY, &config),
            ASTCENC_SUCCESS);
  astcenc_context* context = nullptr;
  EXPECT_EQ(astcenc_context_alloc(&config, 1, &context), ASTCENC_SUCCESS);
  std::vector<float> out(6u * size * size * 4u, -1.0f);
  if (!context) return out;
  const astcenc_swizzle rgba{ASTCENC_SWZ_R, ASTCENC_SWZ_G, ASTCENC_SWZ_B, ASTCENC_SWZ_A};
  for (size_t f = 0; f < 6; ++f) {
    void* slices[1] = {out.data() + 4u * size * size * f};
    astcenc_image image{size, size, 1, ASTCENC_TYPE_F32, slices};
    EXPECT_EQ(astcenc_decompress_image(context, blocks + f * face_bytes, face_bytes, &image, &rgba, 0),
              ASTCENC_SUCCESS);
    EXPECT_EQ(astcenc_decompress_reset(context), ASTCENC_SUCCESS);
  }
  astcenc_context_free(context);
  return out;
}

TEST(AstcKtx2, StructureFieldByFieldAndMeasuredError) {
  const fs::path dir = temp_dir("astc");
  fs::create_directories(dir);
  const CubeLevels chain = synthetic_chain(32, 4, RoughnessSchedule::Linear);
  for (int block : {4, 6}) {
    const fs::path path = dir / ("c" + std::to_string(block) + ".ktx2");
    const io::AstcCube astc = io::write_astc_ktx2_cube(chain, path.string(), block, 10.0);
    const auto b = read_all(path);
    EXPECT_EQ(std::memcmp(b.data(), "\xABKTX 20\xBB\r\n\x1A\n", 12), 0);
    EXPECT_EQ(u32(b, 12), block == 4 ? 1000066000u : 1000066004u);  // VK_FORMAT_ASTC_NxN_SFLOAT_BLOCK
    EXPECT_EQ(u32(b, 16), 1u);                                      // typeSize 1 for block formats
    EXPECT_EQ(u32(b, 20), 32u);
    EXPECT_EQ(u32(b, 36), 6u);  // faceCount
    EXPECT_EQ(u32(b, 40), 4u);  // levels 32, 16, 8, 4
    EXPECT_EQ(u32(b, 44), 0u);  // supercompressionScheme: none
    EXPECT_EQ(u64(b, 64), 0u);  // no supercompression global data
    for (uint32_t l = 0; l < 4; ++l) {
      const uint64_t s = 32u >> l, blocks = (s + uint64_t(block) - 1) / uint64_t(block);
      EXPECT_EQ(u64(b, 88 + 24 * l), 6 * blocks * blocks * 16) << l;  // byteLength: whole blocks
      EXPECT_EQ(u64(b, 96 + 24 * l), u64(b, 88 + 24 * l));            // uncompressedByteLength
      EXPECT_EQ(u64(b, 80 + 24 * l) % 16, 0u);                        // lcm(16, 4)
    }
    // DFD (KDF): ASTC model 162, BT.709, linear, texelBlockDimension N-1, 16 bytes, one sample of
    // 128 bits, ASTC_DATA | FLOAT | SIGNED, -1.0f .. 1.0f
    const size_t dfd = u32(b, 48);
    EXPECT_EQ(u32(b, 52), 4u + 24u + 16u);
    EXPECT_EQ(u32(b, dfd + 12) & 0xFFu, 162u);
    EXPECT_EQ((u32(b, dfd + 12) >> 8) & 0xFFu, 1u);
    EXPECT_EQ((u32(b, dfd + 12) >> 16) & 0xFFu, 1u);
    EXPECT_EQ(u32(b, dfd + 16), uint32_t(block - 1) | uint32_t(block - 1) << 8);
    EXPECT_EQ(u32(b, dfd + 20), 16u);
    EXPECT_EQ(u32(b, dfd + 28), 127u << 16 | 0xC0u << 24);
    EXPECT_EQ(u32(b, dfd + 36), 0xBF800000u);
    EXPECT_EQ(u32(b, dfd + 40), 0x3F800000u);
    // the reader accepts it and the delivered error is in the metadata, as measured
    const io::Ktx2Image k = io::decode_ktx2(b);
    EXPECT_EQ(key(k.key_values, "KTXorientation"), "rd");
    const std::string rel = key(k.key_values, "brdfbake:astc_max_rel_error_per_level");
    ASSERT_NE(rel, "<missing>");
    std::istringstream in(rel);
    for (size_t l = 0; l < astc.max_rel_error.size(); ++l) {
      double recorded = -1.0;
      in >> recorded;
      // rounded up to 3 digits: never below what was measured
      EXPECT_GE(recorded, astc.max_rel_error[l]);
      EXPECT_LE(recorded, astc.max_rel_error[l] * 1.01 + 1e-12);
    }
    // The blocks the file holds, found through its level index (not our reader) and decoded by a
    // decompress-only astcenc context of our own, as a GPU would: every texel of every face and
    // level against the source chain.
    const std::string abs_recorded = key(k.key_values, "brdfbake:astc_max_abs_error_per_level");
    ASSERT_NE(abs_recorded, "<missing>");
    std::istringstream abs_in(abs_recorded);
    ASSERT_EQ(astc.max_abs_error.size(), 4u);
    for (size_t l = 0; l < 4; ++l) {
      const unsigned s = 32u >> l;
      const size_t face_texels = size_t(s) * s, blocks = size_t((s + unsigned(block) - 1) / unsigned(block));
      const size_t face_bytes = blocks * blocks * 16, offset = size_t(u64(b, 80 + 24 * l));
      ASSERT_EQ(size_t(u64(b, 88 + 24 * l)), 6 * face_bytes);
      ASSERT_LE(offset + 6 * face_bytes, b.size());
      const std::vector<float> decoded = astc_decode_faces(b.data() + offset, face_bytes, s, block);
      // the error of every channel, and relative to the largest source value of its block
      double max_abs = 0.0, max_of_block = 0.0;
      for (size_t f = 0; f < 6; ++f)
        for (unsigned by = 0; by < s; by += unsigned(block))
          for (unsigned bx = 0; bx < s; bx += unsigned(block)) {
            std::vector<size_t> texels;
            for (unsigned j = by; j < std::min(s, by + unsigned(block)); ++j)
              for (unsigned i = bx; i < std::min(s, bx + unsigned(block)); ++i)
                texels.push_back(f * face_texels + j * s + i);
            double peak = 0.0, worst = 0.0;
            for (size_t t : texels)
              for (size_t c = 0; c < 3; ++c) {
                const double got = decoded[4 * t + c], want = chain.levels[l][4 * t + c];
                ASSERT_TRUE(std::isfinite(got)) << "level " << l << " texel " << t;
                peak = std::max(peak, want);
                worst = std::max(worst, std::fabs(got - want));
              }
            max_abs = std::max(max_abs, worst);
            max_of_block = std::max(max_of_block, worst / peak);
          }
      // what a GPU decodes is what the encoder measured, and within the file's recorded bounds
      EXPECT_EQ(decoded, astc.decoded[l]) << "block " << block << " level " << l;
      double recorded_abs = -1.0;
      abs_in >> recorded_abs;
      EXPECT_LE(max_abs, recorded_abs) << "block " << block << " level " << l;
      EXPECT_GE(max_abs, astc.max_abs_error[l]) << "block " << block << " level " << l;
      EXPECT_GT(max_abs, 0.0) << "lossy: a zero error means the source itself was stored";
      // and that error is ASTC HDR's at this effort, not a misplaced face, level or channel
      EXPECT_LE(max_of_block, block == 4 ? test::kAstcHdr4x4OfBlock : test::kAstcHdr6x6OfBlock)
          << "block " << block << " level " << l;
      EXPECT_LE(astc.rms_rel_error[l], astc.max_rel_error[l]);
    }
  }
}

}  // namespace
}  // namespace brdfbake
