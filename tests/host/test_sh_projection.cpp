// The SH projection on the host (project_sh, host/src/families/irradiance/sh_projection.cpp): an equirect's exact
// projection against an independent quadrature of the definition over every pixel, the white
// furnace at any resolution, a cube at its texel centres against the scalar reference.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/math/equirect.hpp"
#include "brdfbake/math/sh.hpp"
#include "brdfbake/reference/envmap.hpp"
#include "support/tolerances.hpp"

namespace brdfbake {
namespace {

constexpr double kPi = 3.14159265358979323846;

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
      for (size_t k = 1; k < 25; ++k) EXPECT_NEAR(sh.radiance[3 * k + c], 0.0, test::kShExactProjection * l00) << w << " " << k;
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
    for (size_t k = 0; k < want.size(); ++k) EXPECT_NEAR(sh.radiance[k], want[k], test::kShExactProjection * scale) << k;
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

}  // namespace
}  // namespace brdfbake
