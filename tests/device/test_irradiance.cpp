// Diffuse irradiance: the irradiance cube on the device against the brute-force reference, the SH
// that compute_irradiance returns (project_sh on the host, tests/host/test_sh_projection.cpp);
// the white furnace; windows and the JSON.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/reference/envmap.hpp"
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

reference::EnvCube to_reference(const CubeLevels& c) {
  reference::EnvCube e;
  e.size = c.size;
  e.rgb.resize(18u * size_t(c.size) * size_t(c.size));
  for (size_t t = 0; t < e.rgb.size() / 3; ++t)
    for (size_t ch = 0; ch < 3; ++ch) e.rgb[3 * t + ch] = c.levels[0][4 * t + ch];
  return e;
}

// A white environment: L_00 = 4 pi Y_00 L = 2 sqrt(pi) L exactly, every other coefficient 0, and
// E / pi = L in every texel of the cube.
TEST(Irradiance, WhiteFurnace) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  const float rgb[3] = {1.0f, 0.5f, 4.0f};
  for (int order : {3, 5}) {
    IrradianceSpec s;
    s.sh_order = order;
    s.source_size = 32;
    s.cube_size = 8;
    const IrradianceResult r = compute_irradiance(*dev, constant_equirect(64, rgb[0], rgb[1], rgb[2]), s);
    ASSERT_EQ(r.sh.radiance.size(), size_t(3 * order * order));
    for (size_t c = 0; c < 3; ++c) {
      const double l00 = 2.0 * std::sqrt(kPi) * double(rgb[c]);
      EXPECT_NEAR(r.sh.radiance[c] / l00, 1.0, test::kEnvFurnace);
      EXPECT_NEAR(r.sh.irradiance_over_pi[c] * 0.5 / std::sqrt(kPi), double(rgb[c]),
                  test::kEnvFurnace * double(rgb[c]));
      // the equirect's exact projection: every other coefficient vanishes to rounding
      for (size_t k = 1; k < size_t(order * order); ++k)
        EXPECT_NEAR(r.sh.radiance[3 * k + c] / l00, 0.0, test::kEnvFurnace) << "coefficient " << k << " channel " << c;
    }
    for (size_t t = 0; t < r.cube.levels[0].size(); t += 4)
      for (size_t c = 0; c < 3; ++c)
        ASSERT_NEAR(double(r.cube.levels[0][t + c] / rgb[c]), 1.0, test::kEnvIrradianceDevice) << t / 4;
  }
}

TEST(Irradiance, AgreesWithTheReference) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  for (const char* name : {"studio", "sun"}) {
    const EnvImage env = builtin_environment(name, 256);
    IrradianceSpec s;
    s.sh_order = 5;
    s.source_size = 64;
    s.cube_size = 8;
    const IrradianceResult r = compute_irradiance(*dev, env, s);
    const CubeLevels source = environment_to_cube(*dev, env, 64);
    const reference::EnvCube src = to_reference(source);
    // SH: the host projection of the environment itself, whatever the cube
    EXPECT_EQ(r.sh.radiance, project_sh(env, 5).radiance) << name;
    EXPECT_EQ(r.cube.meta("sh_projection"), project_sh(env, 5).projection) << name;
    // the cube: brute-force cosine convolution of the same source
    std::vector<Vec3> dirs;
    for (int f = 0; f < 6; ++f)
      for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 8; ++i) dirs.push_back(math::cube_texel_direction(f, 8, i, j));
    const auto e = reference::irradiance_directions(src, dirs);
    double sum = 0;
    for (size_t t = 0; t < dirs.size(); ++t)
      for (size_t c = 0; c < 3; ++c) {
        const double d = double(r.cube.levels[0][4 * t + c]) / e[3 * t + c] - 1.0;
        EXPECT_NEAR(d, 0.0, test::kEnvIrradianceDevice) << name << " " << t;
        sum += d * d;
      }
    EXPECT_LE(std::sqrt(sum / double(3 * dirs.size())), test::kEnvIrradianceDeviceRms) << name;
  }
}

TEST(Irradiance, WindowsAndCoefficients) {
  const auto none = sh_window_weights(ShWindow::None, 3);
  const auto hann = sh_window_weights(ShWindow::Hanning, 3);
  const auto lanczos = sh_window_weights(ShWindow::Lanczos, 5);
  EXPECT_EQ(none, (std::vector<double>{1, 1, 1}));
  EXPECT_DOUBLE_EQ(hann[0], 1.0);
  EXPECT_NEAR(hann[1], 0.5 * (1 + std::cos(kPi / 3)), test::kUlpsOfOne);
  EXPECT_NEAR(lanczos[2], std::sin(0.4 * kPi) / (0.4 * kPi), test::kUlpsOfOne);
  BRDFBAKE_REQUIRE_DEVICE(dev);
  IrradianceSpec s;
  s.sh_order = 3;
  s.window = ShWindow::Hanning;
  s.source_size = 16;
  s.cube_size = 0;
  const IrradianceResult r = compute_irradiance(*dev, builtin_environment("sun", 128), s);
  const double a[3] = {1.0, 2.0 / 3.0, 0.25};  // A_l / pi
  for (int l = 0; l < 3; ++l)
    for (int m = -l; m <= l; ++m)
      for (size_t c = 0; c < 3; ++c) {
        const size_t k = size_t(l * (l + 1) + m);
        EXPECT_NEAR(r.sh.irradiance_over_pi[3 * k + c], a[l] * hann[size_t(l)] * r.sh.radiance[3 * k + c],
                    test::kRoundingFewOps);
      }
  EXPECT_TRUE(r.cube.levels.empty());
  const auto j = nlohmann::json::parse(sh_to_json(r.sh, {{"source", "builtin:sun"}}));
  EXPECT_EQ(j["order"], 3);
  EXPECT_EQ(j["coefficients"], 9);
  EXPECT_EQ(j["irradiance_over_pi"].size(), 9u);
  EXPECT_EQ(j["window"], "hanning");
  EXPECT_NE(j["irradiance_definition"].get<std::string>().find("DIVIDED BY PI"), std::string::npos);
  EXPECT_EQ(j["metadata"]["source"], "builtin:sun");
}

TEST(Irradiance, BadSpecs) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  IrradianceSpec s;
  s.sh_order = 4;
  EXPECT_THROW(compute_irradiance(*dev, constant_equirect(8, 1, 1, 1), s), Error);
  s.sh_order = 3;
  s.cube_size = -1;
  EXPECT_THROW(compute_irradiance(*dev, constant_equirect(8, 1, 1, 1), s), Error);
}

}  // namespace
}  // namespace brdfbake
