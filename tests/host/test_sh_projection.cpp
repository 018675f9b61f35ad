// The SH projection on the host (project_sh, host/src/families/irradiance/sh_projection.cpp): an equirect's exact
// projection against an independent quadrature of the definition over every pixel, the white
// furnace at any resolution, a cube at its texel centres against the scalar reference.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/math/equirect.hpp"
#include "brdfbake/math/sh.hpp"
#include "brdfbake/reference/envmap.hpp"
#include "families/irradiance/model.hpp"
#include "support/tolerances.hpp"

namespace brdfbake {
namespace {

using brdfbake::math::kPi;

EnvImage equirect(int w, int h, const std::vector<float>& rgb) {
  EnvImage e;
  e.layout = EnvImage::Layout::Equirect;
  e.width = w;
  e.height = h;
  e.rgb = rgb;
  e.source = "test";
  return e;
}

// Gauss-Legendre nodes and weights on [-1, 1], n = 16, by Newton's iteration on P_16.
void gauss_legendre16(double* x, double* w) {
  const int n = 16;
  for (int i = 0; i < n; ++i) {
    double t = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = t;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * t * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (t * p1 - p0) / (t * t - 1);
      const double step = p1 / dp;
      t -= step;
      if (std::fabs(step) < 1e-16) break;
    }
    x[i] = t;
    w[i] = 2.0 / ((1 - t * t) * dp * dp);
  }
}

// The definition, integrated independently: over each pixel's (u, v) square with 16 x 16
// Gauss-Legendre nodes, the direction from math::equirect_direction (the documented mapping)
// and dl = 2 pi^2 cos(latitude) du dv, the basis from the reference.
std::vector<double> brute_force(const EnvImage& e, int order) {
  double gx[16], gw[16];
  gauss_legendre16(gx, gw);
  std::vector<double> out(3 * size_t(order * order), 0.0);
  for (int y = 0; y < e.height; ++y)
    for (int x = 0; x < e.width; ++x) {
      const float* l = &e.rgb[3 * (size_t(y) * size_t(e.width) + size_t(x))];
      for (int a = 0; a < 16; ++a)
        for (int b = 0; b < 16; ++b) {
          const double u = (x + 0.5 * (gx[a] + 1)) / e.width, v = (y + 0.5 * (gx[b] + 1)) / e.height;
          const double dl = 2.0 * kPi * kPi * std::cos(kPi * (0.5 - v)) * (0.25 * gw[a] * gw[b]) / (e.width * e.height);
          const auto basis = math::sh_basis(order, math::equirect_direction(u, v));
          for (size_t k = 0; k < basis.size(); ++k)
            for (size_t c = 0; c < 3; ++c) out[3 * k + c] += double(l[c]) * basis[k] * dl;
        }
    }
  return out;
}

double largest(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::fabs(x));
  return m;
}

TEST(ShProjection, ExactForTheEquirectsPixels) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (const auto& [w, h] : {std::pair{8, 4}, std::pair{24, 12}, std::pair{7, 5}}) {
    std::vector<float> rgb;
    for (int k = 0; k < w * h; ++k) rgb.insert(rgb.end(), {u(rng), u(rng), k == w + 2 ? 1e6f : u(rng)});  // and a sun
    const EnvImage e = equirect(w, h, rgb);
    for (int order : {3, 5}) {
      const ShCoefficients sh = project_sh(e, order);
      const std::vector<double> want = brute_force(e, order);
      ASSERT_EQ(sh.radiance.size(), want.size());
      const double scale = largest(want);
      for (size_t k = 0; k < want.size(); ++k)
        EXPECT_NEAR(sh.radiance[k], want[k], test::kShExactProjection * scale)
            << w << "x" << h << " order " << order << " coefficient " << k / 3 << " channel " << k % 3;
    }
  }
}

// A white environment: L_00 = 4 pi Y_00 L = 2 sqrt(pi) L and nothing else, at any resolution (the
// cells' integrals are exact, so even 4 x 2 pixels give it).
TEST(ShProjection, WhiteFurnaceAtAnyResolution) {
  for (const auto& [w, h] : {std::pair{4, 2}, std::pair{64, 32}, std::pair{1024, 512}}) {
    const EnvImage e = equirect(w, h, std::vector<float>(3 * size_t(w) * size_t(h), 3.0f));
    const ShCoefficients sh = project_sh(e, 5);
    const double l00 = 2.0 * std::sqrt(kPi) * 3.0;
    for (size_t c = 0; c < 3; ++c) {
      EXPECT_NEAR(sh.radiance[c], l00, test::kShExactProjection * l00) << w;
      EXPECT_NEAR(sh.irradiance_over_pi[c], 3.0 * 2.0 * std::sqrt(kPi), test::kShExactProjection * l00) << w;
      for (size_t k = 1; k < 25; ++k)
        EXPECT_NEAR(sh.radiance[3 * k + c], 0.0, test::kShExactProjection * l00) << w << " " << k;
    }
  }
}

// A cube is projected at its texel centres with their exact solid angles: the reference's
// definition at one sub-cell per texel.
TEST(ShProjection, CubeAtTexelCentresAsTheReference) {
  const int s = 6;
  EnvImage e;
  e.layout = EnvImage::Layout::Cube;
  e.width = e.height = s;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 2.0f);
  reference::EnvCube ref;
  ref.size = s;
  for (int k = 0; k < 18 * s * s; ++k) {
    e.rgb.push_back(u(rng));
    ref.rgb.push_back(double(e.rgb.back()));
  }
  for (int order : {3, 5}) {
    const ShCoefficients sh = project_sh(e, order);
    const std::vector<double> want = reference::sh_project(ref, order, 1);
    const double scale = largest(want);
    for (size_t k = 0; k < want.size(); ++k)
      EXPECT_NEAR(sh.radiance[k], want[k], test::kShExactProjection * scale) << k;
    EXPECT_NE(sh.projection.find("texel"), std::string::npos) << sh.projection;
  }
}

TEST(ShProjection, WindowAndBadInput) {
  const EnvImage e = equirect(8, 4, std::vector<float>(96, 1.0f));
  const ShCoefficients sh = project_sh(e, 3, ShWindow::Hanning);
  const auto w = sh_window_weights(ShWindow::Hanning, 3);
  EXPECT_EQ(sh.window_weights, w);
  for (size_t c = 0; c < 3; ++c)  // band 0: A_0 / pi = 1, w_0 = 1
    EXPECT_DOUBLE_EQ(sh.irradiance_over_pi[c], sh.radiance[c]);
  EXPECT_THROW(project_sh(e, 4), Error);
  EXPECT_THROW(project_sh(equirect(8, 4, std::vector<float>(10, 1.0f)), 3), Error);
}

// cmgen's automatic deringing window (host/src/sh_window.cpp), piece by piece against closed forms.
TEST(ShWindowAuto, MinimumOfALinearFunctionIsItsClosedForm) {
  // f = a Y_00 + b Y_10 = a / (2 sqrt(pi)) + b sqrt(3 / 4pi) z: the minimum is at z = -sign(b).
  const double a = 1.3, b = 0.9;
  std::vector<double> c(9, 0.0);
  c[0] = a;
  c[2] = b;
  const double want = a * 0.5 / std::sqrt(kPi) - std::fabs(b) * std::sqrt(0.75 / kPi);
  // The search ends on a step of 1e-9 rad: the value is then within ~1e-17 of the minimum.
  EXPECT_NEAR(sh_minimum(c, 3), want, 1e-12);
  // a tilted linear function: the same minimum wherever its direction points
  std::vector<double> t(9, 0.0);
  t[0] = a;
  t[1] = b * 0.6;
  t[3] = b * 0.8;
  EXPECT_NEAR(sh_minimum(t, 3), want, 1e-12);
}

TEST(ShWindowAuto, MinimumOfBandTwoIsItsClosedForm) {
  // f = Y_20 = sqrt(5 / 16pi) (3 z^2 - 1): minimum -sqrt(5 / 16pi) on the equator.
  std::vector<double> c(25, 0.0);
  c[6] = 1.0;
  EXPECT_NEAR(sh_minimum(c, 5), -std::sqrt(5.0 / (16.0 * kPi)), 1e-12);
}

TEST(ShWindowAuto, EstimateIsExactForZonalFunctions) {
  // zonal about a tilted axis (linear + band 2 zonal about the same axis): the estimate is exact
  const Vec3 u{0.48, 0.6, 0.64};  // unit
  const std::vector<double> y1 = math::sh_basis(3, u);
  std::vector<double> c(9, 0.0);
  c[0] = 2.0;
  // the zonal functions about u: P1(u.n) and P2(u.n) in the basis are sums of Y_1m(u) Y_1m(n), ...
  for (int k = 1; k < 4; ++k) c[size_t(k)] = 0.7 * y1[size_t(k)];
  for (int k = 4; k < 9; ++k) c[size_t(k)] = -0.9 * y1[size_t(k)];
  EXPECT_NEAR(sh_minimum_estimate(c), sh_minimum(c, 3), 1e-6);
}

TEST(ShWindowAuto, SincWeights) {
  const std::vector<double> w = sh_sinc4_window_weights(2.5, 5);
  EXPECT_EQ(w[0], 1.0);
  EXPECT_NEAR(w[1], std::pow(std::sin(kPi / 2.5) / (kPi / 2.5), 4), 1e-15);
  EXPECT_NEAR(w[2], std::pow(std::sin(2 * kPi / 2.5) / (2 * kPi / 2.5), 4), 1e-15);
  EXPECT_EQ(w[3], 0.0);  // l >= cutoff
  EXPECT_EQ(w[4], 0.0);
  EXPECT_THROW(sh_window_weights(ShWindow::Auto, 3), Error);
  EXPECT_EQ(sh_window_from_name("auto"), ShWindow::Auto);
  EXPECT_STREQ(sh_window_name(ShWindow::Auto), "auto");
}

TEST(ShWindowAuto, CutoffIsTheWidestThatKeepsTheIrradianceNonNegative) {
  // A non-negative function keeps nearly the widest cutoff the search allows (4 order + 1 = 13):
  // each channel's search ends within 0.1 band below where it started, and starts where the
  // previous one ended, so the three channels end at 12.92, 12.84 and 12.7675 bands (cmgen
  // writes the same cutoff for every map that needs no deringing).
  std::vector<double> flat(27, 0.0);
  flat[0] = flat[1] = flat[2] = 1.0;
  const double wide = sh_auto_window_cutoff(flat, 3);
  EXPECT_NEAR(wide, 12.7675, 1e-3);
  // The irradiance of a small bright source (a sun) rings negative on the far side: the chosen
  // cutoff makes it non-negative, and a cutoff 0.2 band wider does not (the search's resolution
  // is 0.1 band). Green has half the source's strength over the same base, so it rings less;
  // the cutoff is the smallest over the channels (red's).
  const Vec3 sun{0.3, 0.4, std::sqrt(1.0 - 0.25)};
  const std::vector<double> y = math::sh_basis(3, sun);
  std::vector<double> irr(27, 0.0);
  for (int l = 0; l < 3; ++l)
    for (int m = -l; m <= l; ++m) {
      const size_t k = size_t(math::sh_index(l, m));
      const double lobe = math::sh_cosine_lobe(l) / kPi;
      irr[3 * k + 0] = 100.0 * y[k] * lobe + (k == 0 ? 0.01 : 0.0);
      irr[3 * k + 1] = 50.0 * y[k] * lobe + (k == 0 ? 0.01 : 0.0);
      irr[3 * k + 2] = (k == 0 ? 1.0 : 0.0);
    }
  const double cut = sh_auto_window_cutoff(irr, 3);
  EXPECT_GE(cut, 3.0);
  EXPECT_LT(cut, 12.7);
  auto windowed_min = [&](double cutoff, size_t channel) {
    const std::vector<double> w = sh_sinc4_window_weights(cutoff, 3);
    std::vector<double> c(9);
    for (int l = 0; l < 3; ++l)
      for (int m = -l; m <= l; ++m)
        c[size_t(math::sh_index(l, m))] = irr[3 * size_t(math::sh_index(l, m)) + channel] * w[size_t(l)];
    return sh_minimum_estimate(c);  // as the search decides, for 3 bands
  };
  EXPECT_GE(windowed_min(cut, 0), 0.0);
  EXPECT_GE(windowed_min(cut, 1), 0.0);
  EXPECT_LT(windowed_min(cut + 0.2, 0), 0.0);
  // The unwindowed irradiance of that source is negative somewhere (why the window exists).
  EXPECT_LT(windowed_min(1e9, 0), 0.0);
}

TEST(ShWindowAuto, AppliedToAProjection) {
  const EnvImage e = equirect(8, 4, std::vector<float>(96, 1.0f));
  const ShCoefficients sh = project_sh(e, 3, ShWindow::Auto);
  EXPECT_EQ(sh.window, ShWindow::Auto);
  EXPECT_NEAR(sh.window_cutoff, 12.7675, 1e-3);  // a uniform environment: nothing rings (see above)
  EXPECT_EQ(sh.window_weights, sh_sinc4_window_weights(sh.window_cutoff, 3));
  for (size_t c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(sh.irradiance_over_pi[c], sh.radiance[c]);  // band 0 untouched
}

// The SH's irradiance error a file records (issue 35; families/irradiance/sh_error.cpp), against
// closed forms. A constant and a linear map (L = 1 + z: irradiance in bands 0 and 1 only) have no
// truncation error; one bright pixel (a point light) has the clamped cosine's: the L2 norm of
// max(0, cos) is 2 pi / 3, bands 0..2 hold sum_l (2l + 1) A_l^2 / (4 pi) = (pi / 4)(1 + 4/3 + 5/16),
// so the relative RMS over the sphere is sqrt(1 - (3 / 8)(1 + 4/3 + 5/16)) = 0.0884.
TEST(ShError, ClosedFormsOfTheTruncation) {
  const int w = 256, h = 128;
  auto sh_error = [&](const std::vector<float>& rgb) {
    const EnvImage env = environment_from_equirect(w, h, rgb, "test");
    return detail::sh_irradiance_error(env, project_sh(env, 3)).relative_rms;
  };
  std::vector<float> constant(3 * size_t(w) * h, 2.0f), linear(constant.size()), point(constant.size(), 0.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double t = math::kPi * (0.5 - (y + 0.5) / h), phi = 2.0 * math::kPi * (0.5 - (x + 0.5) / w);
      for (int c = 0; c < 3; ++c)
        linear[3 * (size_t(y) * w + size_t(x)) + size_t(c)] = float(1.0 + std::cos(phi) * std::cos(t));
    }
  for (int c = 0; c < 3; ++c) point[3 * (size_t(h / 2) * w + size_t(w / 3)) + size_t(c)] = 1e4f;
  // the exact side is a midpoint rule over 256 x 128 pixels, its error at the clamped cosine's
  // horizon kink 1.5e-5 here
  EXPECT_LT(sh_error(constant), 1e-4);
  EXPECT_LT(sh_error(linear), 2e-3);
  // 128 Fibonacci directions sample the sphere's mean square to about 5 %
  const double want = std::sqrt(1.0 - 0.375 * (1.0 + 4.0 / 3.0 + 5.0 / 16.0));
  EXPECT_NEAR(sh_error(point), want, 0.05 * want);
}

// The projection against the converged projection of the same pixels (issue 35;
// sh_projection_error): an equirect's cells are integrated exactly (0 recorded, no subdivision); a
// cube's texel centres are a midpoint rule whose error falls as 1 / n^2, so doubling the face size
// divides the measure by about 4 (a wrong sub-texel solid angle or direction would not converge,
// and the measure of a constant cube, exact at band 0 only, stays small).
TEST(ShError, ProjectionAgainstTheConvergedProjection) {
  const int w = 64, h = 32;
  const EnvImage flat = environment_from_equirect(w, h, std::vector<float>(3 * size_t(w) * h, 1.0f), "test");
  const detail::ShProjectionMeasure e = detail::sh_projection_error(flat, project_sh(flat, 3));
  EXPECT_EQ(e.subdivision, 0);
  EXPECT_EQ(e.relative_rms, 0.0);
  auto cube_error = [](int n) {
    EnvImage env;
    env.layout = EnvImage::Layout::Cube;
    env.width = env.height = n;
    env.source = "test";
    for (int f = 0; f < 6; ++f)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const Vec3 d = math::cube_texel_direction(f, n, i, j);
          const float v = float(1.0 + d.x + 0.5 * d.y * d.z);  // bands 0..2 and above
          env.rgb.insert(env.rgb.end(), {v, v, v});
        }
    const detail::ShProjectionMeasure m = detail::sh_projection_error(env, project_sh(env, 3));
    EXPECT_EQ(m.subdivision, 4);
    return m.relative_rms;
  };
  const double e8 = cube_error(8), e16 = cube_error(16);
  EXPECT_GT(e8, 0.0);
  EXPECT_LT(e8, 0.05);
  EXPECT_GT(e8 / e16, 3.0) << e8 << " " << e16;
  EXPECT_LT(e8 / e16, 5.0) << e8 << " " << e16;
}

}  // namespace
}  // namespace brdfbake
