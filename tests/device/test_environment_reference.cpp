// The reference backend of the environment families (prefilter_environment_reference,
// compute_irradiance_reference; host/src/reference_backend/): the same results as the device path
// within the device-against-reference tolerances of tests/device/test_prefilter.cpp and
// test_irradiance.cpp, the white furnace in closed form, the same metadata, and the size limits.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "support/device_fixture.hpp"
#include "support/tolerances.hpp"

namespace brdfbake {
namespace {

using brdfbake::math::kPi;

EnvImage constant_equirect(int width, float r, float g, float b) {
  EnvImage e;
  e.layout = EnvImage::Layout::Equirect;
  e.width = width;
  e.height = width / 2;
  e.source = "constant";
  for (int k = 0; k < e.width * e.height; ++k) e.rgb.insert(e.rgb.end(), {r, g, b});
  return e;
}

// Level 0 of a cube as a cube environment: both paths then filter the same texels.
EnvImage as_environment(const CubeLevels& cube, const std::string& source) {
  EnvImage e;
  e.layout = EnvImage::Layout::Cube;
  e.width = e.height = cube.size;
  e.source = source;
  for (size_t t = 0; t < cube.levels[0].size(); t += 4)
    e.rgb.insert(e.rgb.end(), {cube.levels[0][t], cube.levels[0][t + 1], cube.levels[0][t + 2]});
  return e;
}

struct Errors {
  double rms = 0, max = 0;
};

// Per channel |P - P_ref| / max(P_ref, 1e-3 mean(P_ref)), as tests/device/test_prefilter.cpp and
// bench/prefilter_bench measure.
Errors level_errors(const std::vector<float>& got, const std::vector<float>& want) {
  double mean = 0;
  size_t n = 0;
  for (size_t t = 0; t < want.size(); t += 4)
    for (size_t c = 0; c < 3; ++c, ++n) mean += double(want[t + c]);
  mean /= double(n);
  Errors e;
  double sum = 0;
  for (size_t t = 0; t < want.size(); t += 4)
    for (size_t c = 0; c < 3; ++c) {
      const double w = want[t + c];
      const double d = std::fabs(double(got[t + c]) - w) / std::max(w, 1e-3 * mean);
      sum += d * d;
      e.max = std::max(e.max, d);
    }
  e.rms = std::sqrt(sum / double(n));
  return e;
}

std::set<std::string> keys(const Metadata& m) {
  std::set<std::string> k;
  for (const auto& [key, value] : m) k.insert(key);
  return k;
}

template <class F>
void expect_error(F&& f, const std::vector<std::string>& needles) {
  try {
    f();
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    for (const std::string& n : needles) EXPECT_NE(std::string(e.what()).find(n), std::string::npos) << e.what();
  }
}

// ---- Prefiltered radiance ---------------------------------------------------------------------

// The device chain (quadrature estimator) against the reference backend on the same 32^2 source:
// the device-against-reference bounds of test_prefilter.cpp.
TEST(PrefilterReference, AgreesWithTheDeviceOnSmallCubes) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  for (const char* name : {"studio", "sun"}) {
    const EnvImage env = as_environment(environment_to_cube(*dev, builtin_environment(name, 256), 32), name);
    for (EnvDistribution d : {EnvDistribution::Ggx, EnvDistribution::Charlie}) {
      PrefilterSpec s;
      s.size = 32;
      s.min_size = 4;
      s.distribution = d;
      const CubeLevels got = prefilter_environment(*dev, env, s);
      const CubeLevels want = prefilter_environment_reference(env, s);
      ASSERT_EQ(got.level_count(), want.level_count());
      EXPECT_EQ(got.levels[0], want.levels[0]) << "level 0 is the source on both";
      for (int l = 1; l < want.level_count(); ++l) {
        const Errors e = level_errors(got.levels[size_t(l)], want.levels[size_t(l)]);
        EXPECT_LE(e.rms, test::kEnvPrefilterRms) << name << " " << env_distribution_name(d) << " level " << l;
        EXPECT_LE(e.max, test::kEnvPrefilterMax) << name << " " << env_distribution_name(d) << " level " << l;
      }
      EXPECT_EQ(got.meta("roughness_per_level"), want.meta("roughness_per_level"));
    }
  }
}

// A constant environment gives that constant in every texel of every level: the reference's
// normaliser is the same sum as its numerator, so up to float storage.
TEST(PrefilterReference, WhiteFurnace) {
  const float rgb[3] = {2.5f, 0.75f, 1.0f};
  for (EnvDistribution d : {EnvDistribution::Ggx, EnvDistribution::Charlie}) {
    PrefilterSpec s;
    s.size = 16;
    s.min_size = 2;
    s.distribution = d;
    const CubeLevels out = prefilter_environment_reference(constant_equirect(64, rgb[0], rgb[1], rgb[2]), s);
    ASSERT_EQ(out.level_count(), 4);
    for (int l = 0; l < out.level_count(); ++l)
      for (size_t t = 0; t < out.levels[size_t(l)].size(); t += 4)
        for (size_t c = 0; c < 3; ++c)
          ASSERT_NEAR(out.levels[size_t(l)][t + c] / rgb[c], 1.0, test::kEnvFurnace) << "level " << l;
  }
}

// The metadata says what the levels hold with every key the device's chain writes (but the
// estimator's own settings), and that the reference made them.
TEST(PrefilterReference, MetadataHasTheDeviceKeys) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  const EnvImage env = builtin_environment("studio", 128);
  PrefilterSpec s;
  s.size = 16;
  s.min_size = 4;
  const CubeLevels want = prefilter_environment_reference(env, s);
  std::set<std::string> device_keys;
  for (EnvEstimator e : {EnvEstimator::Quadrature, EnvEstimator::Sampling}) {
    PrefilterSpec d = s;
    d.estimator = e;
    if (e == EnvEstimator::Sampling) d.samples = 64;
    const std::set<std::string> k = keys(prefilter_environment(*dev, env, d).metadata);
    if (device_keys.empty()) {
      device_keys = k;
    } else {
      std::set<std::string> common;
      for (const std::string& key : k)
        if (device_keys.count(key)) common.insert(key);
      device_keys = common;
    }
  }
  const std::set<std::string> reference_keys = keys(want.metadata);
  for (const std::string& key : device_keys) EXPECT_TRUE(reference_keys.count(key)) << key;
  EXPECT_EQ(want.meta("device"), "reference (scalar double)");
  EXPECT_EQ(want.meta("estimator"), "reference");
  EXPECT_EQ(want.meta("precision"), "fp64");
  EXPECT_EQ(want.meta("kind"), "prefiltered radiance");
  EXPECT_EQ(want.meta("source"), env.source);
  EXPECT_EQ(want.meta("levels"), "3");
}

// Above its work limit the reference refuses, naming the limit and the way out.
TEST(PrefilterReference, RefusesLargeCubesWithAClearMessage) {
  PrefilterSpec s;  // the default chain: 256^2
  EXPECT_GT(prefilter_reference_work(s), kPrefilterReferenceMaxWork);
  expect_error([&] { prefilter_environment_reference(constant_equirect(64, 1, 1, 1), s); },
               {"scalar reference", "limit", "OpenCL device", "size 256"});
  s.size = 32;
  s.min_size = 4;
  EXPECT_LE(prefilter_reference_work(s), kPrefilterReferenceMaxWork);
}

// ---- Irradiance ------------------------------------------------------------------------------------

// The device against the reference backend on the same 64^2 source: SH within the device's SH
// bound (texel centres against sub-cells), the cube within the device's irradiance bounds.
TEST(IrradianceReference, AgreesWithTheDeviceOnSmallCubes) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  for (const char* name : {"studio", "sun"}) {
    const EnvImage env = as_environment(environment_to_cube(*dev, builtin_environment(name, 256), 64), name);
    IrradianceSpec s;
    s.sh_order = 5;
    s.source_size = 64;
    s.cube_size = 8;
    const IrradianceResult got = compute_irradiance(*dev, env, s);
    const IrradianceResult want = compute_irradiance_reference(env, s);
    ASSERT_EQ(got.sh.radiance.size(), want.sh.radiance.size());
    const double l00 = std::fabs(want.sh.radiance[0]) + std::fabs(want.sh.radiance[1]) + std::fabs(want.sh.radiance[2]);
    for (size_t k = 0; k < want.sh.radiance.size(); ++k)
      EXPECT_NEAR(got.sh.radiance[k], want.sh.radiance[k], test::kShTexelCentres * l00) << name << " " << k / 3;
    ASSERT_EQ(got.cube.levels[0].size(), want.cube.levels[0].size());
    double sum = 0;
    size_t n = 0;
    for (size_t t = 0; t < want.cube.levels[0].size(); t += 4)
      for (size_t c = 0; c < 3; ++c, ++n) {
        const double d = double(got.cube.levels[0][t + c]) / double(want.cube.levels[0][t + c]) - 1.0;
        EXPECT_NEAR(d, 0.0, test::kEnvIrradianceDevice) << name << " " << t / 4;
        sum += d * d;
      }
    EXPECT_LE(std::sqrt(sum / double(n)), test::kEnvIrradianceDeviceRms) << name;
    // the same cube metadata keys
    EXPECT_EQ(keys(got.cube.metadata), keys(want.cube.metadata));
    EXPECT_EQ(want.cube.meta("device"), "reference (scalar double)");
    EXPECT_EQ(want.cube.meta("precision"), "fp64");
  }
}

// A white environment: L_00 = 4 pi Y_00 L = 2 sqrt(pi) L, bands 1-3 vanish by symmetry, band 4
// carries the sub-cells' O(1/(S q)^2); E / pi = L in every texel of the cube.
TEST(IrradianceReference, WhiteFurnace) {
  const float rgb[3] = {1.0f, 0.5f, 4.0f};
  IrradianceSpec s;
  s.sh_order = 5;
  s.source_size = 16;
  s.cube_size = 4;
  const IrradianceResult r = compute_irradiance_reference(constant_equirect(64, rgb[0], rgb[1], rgb[2]), s);
  for (size_t c = 0; c < 3; ++c) {
    const double l00 = 2.0 * std::sqrt(kPi) * double(rgb[c]);
    EXPECT_NEAR(r.sh.radiance[c] / l00, 1.0, test::kEnvFurnace);
    for (size_t k = 1; k < 25; ++k)
      EXPECT_NEAR(r.sh.radiance[3 * k + c] / l00, 0.0, k < 16 ? test::kEnvFurnace : test::kEnvShDiscretisation) << k;
    // irradiance_over_pi = (A_0 / pi) L_00 = L_00
    EXPECT_NEAR(r.sh.irradiance_over_pi[c], r.sh.radiance[c], test::kRounding);
  }
  for (size_t t = 0; t < r.cube.levels[0].size(); t += 4)
    for (size_t c = 0; c < 3; ++c)
      ASSERT_NEAR(double(r.cube.levels[0][t + c] / rgb[c]), 1.0, test::kEnvReferenceCosine) << t / 4;
  s.cube_size = 0;
  EXPECT_TRUE(compute_irradiance_reference(constant_equirect(32, 1, 1, 1), s).cube.levels.empty());
}

TEST(IrradianceReference, RefusesLargeRequestsWithAClearMessage) {
  IrradianceSpec s;
  s.source_size = 1024;
  s.cube_size = 0;
  expect_error([&] { compute_irradiance_reference(constant_equirect(64, 1, 1, 1), s); },
               {"scalar reference", "512", "OpenCL device"});
  s.source_size = 256;
  s.cube_size = 64;  // 6 x 64^2 normals x 6 x 256^2 sub-cells: 9.7e9 cosine terms
  expect_error([&] { compute_irradiance_reference(constant_equirect(64, 1, 1, 1), s); },
               {"scalar reference", "limit", "OpenCL device"});
  s.sh_order = 4;
  EXPECT_THROW(compute_irradiance_reference(constant_equirect(64, 1, 1, 1), s), Error);
}

// ---- Conversion -----------------------------------------------------------------------------------

// The reference backend's brute-force conversion of an equirect against the device's sampled one
// (k x k bilinear samples per texel): both estimate each texel's mean of the same bilinear function,
// here a smooth one (1 + 0.5 x + 0.25 y z + 0.3 z^2 per channel), where they differ by their
// sampling error only.
TEST(EnvironmentReference, ConversionAgreesWithTheDevice) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  EnvImage env;
  env.layout = EnvImage::Layout::Equirect;
  env.width = 256;
  env.height = 128;
  env.source = "smooth";
  for (int y = 0; y < env.height; ++y)
    for (int x = 0; x < env.width; ++x) {
      const double phi = 2.0 * kPi * (0.5 - (x + 0.5) / env.width), theta = kPi * (0.5 - (y + 0.5) / env.height);
      const double dx = std::sin(phi) * std::cos(theta), dy = std::sin(theta), dz = std::cos(phi) * std::cos(theta);
      const double v = 1.0 + 0.5 * dx + 0.25 * dy * dz + 0.3 * dz * dz;
      env.rgb.insert(env.rgb.end(), {float(v), float(1.1 * v), float(1.2 * v)});
    }
  PrefilterSpec s;
  s.size = 32;
  s.min_size = 32;  // level 0 only
  const CubeLevels want = prefilter_environment_reference(env, s);
  const CubeLevels got = environment_to_cube(*dev, env, 32);
  const Errors e = level_errors(got.levels[0], want.levels[0]);
  EXPECT_LE(e.rms, test::kEnvConversionRoutesRms);
  EXPECT_LE(e.max, test::kEnvConversionRoutesMax);
  RecordProperty("rms", std::to_string(e.rms));
  RecordProperty("max", std::to_string(e.max));
}

}  // namespace
}  // namespace brdfbake
