// The environment-map reference: the seamless bilinear environment, the brute-force conversions, the
// lobe normalisation in closed form, and the brute-force integrals' identities and convergence. Cube
// addressing, solid angles, the equirect mapping and the SH basis are the shared maths'
// (tests/math).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/math/equirect.hpp"
#include "brdfbake/math/sh.hpp"
#include "brdfbake/reference/envmap.hpp"
#include "support/tolerances.hpp"

namespace brdfbake::reference {
namespace {

using math::cube_plane_point;
using math::cube_rect_solid_angle;
using math::cube_texel_direction;
using math::cube_texel_solid_angle;
using math::dot;
using math::kPi;
using math::sh_basis;
using math::sh_cosine_lobe;

EnvCube constant_cube(int size, double r, double g, double b) {
  EnvCube c;
  c.size = size;
  c.rgb.resize(18u * size_t(size) * size_t(size));
  for (size_t t = 0; t < c.rgb.size(); t += 3) {
    c.rgb[t] = r;
    c.rgb[t + 1] = g;
    c.rgb[t + 2] = b;
  }
  return c;
}

// A smooth environment with structure in every band: texel values of
// 1 + 0.5 x + 0.25 y z + 0.3 z^2 (channel 0), scaled per channel.
EnvCube smooth_cube(int size) {
  EnvCube c;
  c.size = size;
  c.rgb.resize(18u * size_t(size) * size_t(size));
  for (int f = 0; f < 6; ++f)
    for (int j = 0; j < size; ++j)
      for (int i = 0; i < size; ++i) {
        const Vec3 d = cube_texel_direction(f, size, i, j);
        const double v = 1.0 + 0.5 * d.x + 0.25 * d.y * d.z + 0.3 * d.z * d.z;
        for (int ch = 0; ch < 3; ++ch) c.at(f, i, j, ch) = v * (1.0 + 0.1 * ch);
      }
  return c;
}

TEST(EnvmapBilinear, TexelCentresAndSeams) {
  const EnvCube c = smooth_cube(8);
  // at a texel centre the interpolation is the texel
  for (int f = 0; f < 6; ++f) {
    const auto v = cube_bilinear(c, cube_texel_direction(f, 8, 3, 5));
    EXPECT_NEAR(v[0], c.at(f, 3, 5, 0), test::kRounding);
  }
  // continuous across an edge: just either side of the +X / +Z edge
  const double e = 1e-9;
  const auto left = cube_bilinear(c, {1.0, 0.3, 1.0 - e}), right = cube_bilinear(c, {1.0 - e, 0.3, 1.0});
  EXPECT_NEAR(left[0], right[0], test::kEdgeContinuity);
  // a border position takes the neighbouring face's edge texel: left of +Z is -X's right column
  const auto b = cube_fetch_extended(c, 4, -1, 3);
  EXPECT_DOUBLE_EQ(b[0], c.at(1, 7, 3, 0));
}

// The brute-force conversions reproduce what they average: a constant exactly; the mean of a smooth
// environment converges with the sub-cells; an equirect pixel's centre is the pixel.
TEST(EnvmapConversion, ConstantAndSmoothSources) {
  EnvEquirect e;
  e.width = 64;
  e.height = 32;
  for (int y = 0; y < e.height; ++y)
    for (int x = 0; x < e.width; ++x) e.rgb.insert(e.rgb.end(), {2.0, 0.5, 1e6});
  const EnvCube c = equirect_to_cube(e, 8, 0, 1);
  ASSERT_EQ(c.size, 8);
  for (size_t t = 0; t < c.rgb.size(); t += 3) {
    EXPECT_NEAR(c.rgb[t] / 2.0, 1.0, test::kRounding);
    EXPECT_NEAR(c.rgb[t + 2] / 1e6, 1.0, test::kRounding);
  }
  const EnvCube r = cube_resample(constant_cube(16, 1.0, 3.0, 0.25), 4);
  for (size_t t = 0; t < r.rgb.size(); t += 3) EXPECT_NEAR(r.rgb[t + 1] / 3.0, 1.0, test::kRounding);
  // the mean over a texel of a smooth environment converges with the sub-cells (doubling them changes
  // it far less than any tolerance of the environment tests)
  const EnvCube s = smooth_cube(8), a = cube_resample(s, 4, 8), b = cube_resample(s, 4, 16);
  for (size_t k = 0; k < a.rgb.size(); ++k) EXPECT_NEAR(a.rgb[k] / b.rgb[k], 1.0, test::kEnvReferenceSubCells) << k;
  // the equirect's bilinear function at a pixel centre is the pixel
  EnvEquirect g;
  g.width = 16;
  g.height = 8;
  for (int k = 0; k < 16 * 8; ++k) g.rgb.insert(g.rgb.end(), {double(k), 0.0, 1.0});
  const auto v = equirect_bilinear(g, math::equirect_direction(5.5 / 16.0, 3.5 / 8.0));
  EXPECT_NEAR(v[0], 3.0 * 16.0 + 5.0, test::kRoundingLong);
}

TEST(EnvmapLobe, NormalisationInClosedForm) {
  // GGX: W = 4 int_0^xi_max (2 cos^2 - 1) d xi in the CDF variable, with b = 1 - alpha^2,
  // xi_max = 1 / (1 + alpha^2): W = 4 [2 xi_max / b + (2 alpha^2 / b^2) ln(2 alpha^2 / (1 + alpha^2)) - xi_max]
  for (double alpha : {0.01, 0.1, 0.3, 0.5, 0.8}) {
    const double b = 1 - alpha * alpha, xm = 1 / (1 + alpha * alpha);
    const double want =
        4 * (2 * xm / b + 2 * alpha * alpha / (b * b) * std::log(2 * alpha * alpha / (1 + alpha * alpha)) - xm);
    EXPECT_NEAR(env_lobe_normalization(EnvLobe::Ggx, alpha) / want, 1.0, test::kAnalytic) << alpha;
  }
  // alpha = 1: D = 1 / pi, K = c / pi, W = 1
  EXPECT_NEAR(env_lobe_normalization(EnvLobe::Ggx, 1.0), 1.0, test::kAnalytic);
  // Charlie at alpha = 1: D = 3 sin(theta_h) / (2 pi) with sin(theta_h) = sqrt((1 - c) / 2), so
  // W = 2 pi int_0^1 K dc = (3 / sqrt 2) B(2, 3/2) = (3 / sqrt 2)(4 / 15)
  EXPECT_NEAR(env_lobe_normalization(EnvLobe::Charlie, 1.0), 4.0 / (5.0 * std::sqrt(2.0)), test::kAnalytic);
}

TEST(EnvmapPrefilter, ConstantEnvironmentIsReturnedExactly) {
  const EnvCube c = constant_cube(4, 2.0, 0.5, 1e6);
  for (EnvLobe lobe : {EnvLobe::Ggx, EnvLobe::Charlie})
    for (double r : {0.0, 0.3, 1.0}) {
      const EnvCube out = prefilter_cube(c, lobe, r, 2, 0, 1);
      for (size_t t = 0; t < out.rgb.size(); t += 3) {
        EXPECT_NEAR(out.rgb[t] / 2.0, 1.0, test::kRounding);
        EXPECT_NEAR(out.rgb[t + 1] / 0.5, 1.0, test::kRounding);
        EXPECT_NEAR(out.rgb[t + 2] / 1e6, 1.0, test::kRounding);
      }
    }
}

TEST(EnvmapPrefilter, MirrorIsTheBilinearEnvironment) {
  const EnvCube c = smooth_cube(8);
  const EnvCube out = prefilter_cube(c, EnvLobe::Ggx, 0.0, 8);
  for (size_t k = 0; k < out.rgb.size(); ++k) EXPECT_NEAR(out.rgb[k], c.rgb[k], test::kRounding);
}

// The sum's normaliser converges to W: the sub-cells resolve the lobe.
TEST(EnvmapPrefilter, SubCellsResolveTheLobe) {
  for (EnvLobe lobe : {EnvLobe::Ggx, EnvLobe::Charlie})
    for (double r : {0.25, 0.6}) {
      const double alpha = r * r;
      const int q = env_default_subdivision(lobe, alpha, 16);
      // sum of K Omega over the sub-cells around one direction
      const Vec3 d = cube_texel_direction(4, 16, 5, 9);
      double sum = 0;
      for (int f = 0; f < 6; ++f)
        for (int j = 0; j < 16 * q; ++j)
          for (int i = 0; i < 16 * q; ++i) {
            const double a0 = -1 + 2.0 * i / (16 * q), a1 = -1 + 2.0 * (i + 1) / (16 * q);
            const double b0 = -1 + 2.0 * j / (16 * q), b1 = -1 + 2.0 * (j + 1) / (16 * q);
            Vec3 p = cube_plane_point(f, 0.5 * (a0 + a1), 0.5 * (b0 + b1));
            const double n = std::sqrt(dot(p, p));
            p = {p.x / n, p.y / n, p.z / n};
            sum += env_lobe_kernel(lobe, alpha, dot(d, p)) * cube_rect_solid_angle(a0, b0, a1, b1);
          }
      EXPECT_NEAR(sum / env_lobe_normalization(lobe, alpha), 1.0, test::kEnvReferenceSubCells)
          << (lobe == EnvLobe::Ggx ? "ggx" : "charlie") << " r " << r << " q " << q;
    }
}

// Doubling the sub-cells changes the prefiltered radiance by far less than any device tolerance.
TEST(EnvmapPrefilter, SelfConvergence) {
  const EnvCube c = smooth_cube(8);
  for (EnvLobe lobe : {EnvLobe::Ggx, EnvLobe::Charlie}) {
    const double r = 0.4, alpha = r * r;
    const int q = env_default_subdivision(lobe, alpha, 8);
    const EnvCube a = prefilter_cube(c, lobe, r, 4, q), b = prefilter_cube(c, lobe, r, 4, 2 * q);
    for (size_t k = 0; k < a.rgb.size(); ++k) EXPECT_NEAR(a.rgb[k] / b.rgb[k], 1.0, test::kEnvReferenceSubCells) << k;
  }
}

// One bright texel in a black environment spreads into the lobe: P(R) = L Omega K(R.l) / W where
// the lobe is wide against the texel.
TEST(EnvmapPrefilter, SingleTexelSpreadsIntoTheLobe) {
  EnvCube c = constant_cube(16, 0, 0, 0);
  const int f = 4, i = 7, j = 8;
  for (int ch = 0; ch < 3; ++ch) c.at(f, i, j, ch) = 1000.0;
  const double r = 0.7, alpha = r * r;
  const Vec3 l = cube_texel_direction(f, 16, i, j);
  const double omega = cube_texel_solid_angle(16, i, j);
  const std::vector<Vec3> dirs = {cube_texel_direction(4, 8, 3, 4), cube_texel_direction(4, 8, 1, 6),
                                  cube_texel_direction(0, 8, 2, 4)};
  const auto p = prefilter_directions(c, EnvLobe::Ggx, r, dirs);
  for (size_t k = 0; k < dirs.size(); ++k) {
    const double want = 1000.0 * omega * env_lobe_kernel(EnvLobe::Ggx, alpha, dot(dirs[k], l)) /
                        env_lobe_normalization(EnvLobe::Ggx, alpha);
    // the bilinear tent spreads the texel over its neighbours: a second-order change here
    EXPECT_NEAR(p[3 * k] / want, 1.0, test::kBilinearTent) << k;
  }
}

TEST(EnvmapSh, ConstantEnvironmentHasOnlyL00) {
  const EnvCube c = constant_cube(8, 1.0, 2.0, 3.0);
  const auto sh = sh_project(c, 5);
  for (size_t k = 0; k < 25; ++k)
    for (size_t ch = 0; ch < 3; ++ch) {
      const double level = double(ch) + 1.0;
      const double want = k == 0 ? level * 2.0 * std::sqrt(kPi) : 0.0;  // 4 pi Y_00 L
      EXPECT_NEAR(sh[3 * k + ch], want, test::kEnvShDiscretisation * 2.0 * std::sqrt(kPi) * level) << k << "," << ch;
    }
}

TEST(EnvmapIrradiance, ConstantAndSmoothEnvironments) {
  // a constant L: E / pi = L
  const EnvCube c = constant_cube(4, 1.5, 1.5, 1.5);
  const std::vector<Vec3> dirs = {{0, 1, 0}, {0.6, 0, 0.8}, cube_texel_direction(3, 4, 1, 2)};
  for (double v : irradiance_directions(c, dirs)) EXPECT_NEAR(v / 1.5, 1.0, test::kEnvReferenceCosine);
  // a smooth L of degree <= 2: the 9-coefficient SH irradiance is exact, so both routes agree
  const EnvCube s = smooth_cube(16);
  const auto sh = sh_project(s, 3);
  const auto direct = irradiance_directions(s, dirs);
  for (size_t k = 0; k < dirs.size(); ++k) {
    const auto y = sh_basis(3, dirs[k]);
    double e = 0;
    for (int l = 0; l < 3; ++l)
      for (int m = -l; m <= l; ++m)
        e += sh_cosine_lobe(l) / kPi * sh[3 * size_t(l * (l + 1) + m)] * y[size_t(l * (l + 1) + m)];
    EXPECT_NEAR(e / direct[3 * k], 1.0, test::kEnvIrradianceRoutes) << k;
  }
}

}  // namespace
}  // namespace brdfbake::reference
