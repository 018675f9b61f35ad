// The preview's double reference (host/reference/src/preview.cpp): the brute force that checks the
// device's reference render, held to closed forms and to its own convergence.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "brdfbake/reference/dfg_lut.hpp"
#include "brdfbake/reference/preview.hpp"

namespace brdfbake {
namespace {

Vec3 unit(double x, double y, double z) {
  const double l = std::sqrt(x * x + y * y + z * z);
  return {x / l, y / l, z / l};
}

std::vector<float> random_image(int width, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> v(size_t(3 * width * width / 2));
  for (float& x : v) x = u(rng);
  return v;
}

// A white environment: the lobe's albedos (the DFG reference's scale + bias and bias) and pi.
TEST(PreviewBruteForce, WhiteEnvironmentGivesTheAlbedos) {
  const std::vector<float> white(3u * 128u * 64u, 1.0f);
  const Vec3 v{0.0, 0.0, 1.0};
  for (double r : {0.1, 0.4, 1.0})
    for (double nv : {0.1, 0.5, 0.95}) {
      const double s = std::sqrt(1.0 - nv * nv);
      const reference::PreviewIntegrals p =
          reference::preview_integrals(white.data(), 128, 64, unit(s, 0.0, nv), v, r * r);
      const reference::DfgGgx d = reference::dfg_ggx(nv, r);
      // the brute force's midpoint rule on a 128 x 64 map: 2e-4 (its convergence, below)
      EXPECT_NEAR(p.s1[0], d.scale + d.bias, 2e-4) << "r " << r << " n.v " << nv;
      EXPECT_NEAR(p.s2[0], d.bias, 2e-4) << "r " << r << " n.v " << nv;
      // the cosine by the midpoint rule in (u, v) on 128 x 64 cells: second order, 1e-4 here
      EXPECT_NEAR(p.irr[1], M_PI, 1e-4 * M_PI);
    }
}

// Roughness 0: the radiance of the pixel r falls in, times 1 and (1 - n.v)^5.
TEST(PreviewBruteForce, RoughnessZeroIsThePixelReflected) {
  const std::vector<float> img = random_image(64, 3);
  const Vec3 v = unit(0.1, 0.2, 1.0), n = unit(0.3, -0.2, 0.9);
  const reference::PreviewIntegrals p = reference::preview_integrals(img.data(), 64, 32, n, v, 0.0);
  const double nv = n.x * v.x + n.y * v.y + n.z * v.z;
  const Vec3 r{2 * nv * n.x - v.x, 2 * nv * n.y - v.y, 2 * nv * n.z - v.z};
  const double u = 0.5 - std::atan2(r.x, r.z) / (2 * M_PI), w = 0.5 - std::asin(r.y) / M_PI;
  const size_t at = 3 * (size_t(std::floor(w * 32)) * 64 + size_t(std::floor(u * 64)));
  for (size_t c = 0; c < 3; ++c) {
    EXPECT_EQ(p.s1[c], double(img[at + c]));
    EXPECT_NEAR(p.s2[c], std::pow(1 - nv, 5) * double(img[at + c]), 1e-15);
  }
}

// Subdivision 16 (the tests' default) against 32, on a map of noise (the hardest case for cells).
TEST(PreviewBruteForce, ConvergesWithItsSubdivision) {
  const std::vector<float> img = random_image(128, 5);
  const Vec3 v{0.0, 0.0, 1.0};
  for (double r : {0.05, 0.3, 0.8})
    for (double nv : {0.2, 0.7}) {
      const Vec3 n = unit(-std::sqrt(1 - nv * nv), 0.0, nv);
      const auto a = reference::preview_integrals(img.data(), 128, 64, n, v, r * r, 16.0);
      const auto b = reference::preview_integrals(img.data(), 128, 64, n, v, r * r, 32.0);
      EXPECT_NEAR(a.s1[0] / b.s1[0], 1.0, 2e-4) << "r " << r << " n.v " << nv;
      EXPECT_NEAR(a.irr[0] / b.irr[0], 1.0, 2e-4) << "r " << r << " n.v " << nv;
    }
}

// A normal a hair off unit length (a float's) gives the same integrals: a narrow lobe's D near its
// peak is 1 - (n.h)^2 over alpha^2, which an unnormalised n moved by 0.7% at roughness 0.05.
TEST(PreviewBruteForce, NormalisesItsVectors) {
  const std::vector<float> img = random_image(128, 7);
  const Vec3 n = unit(0.3, 0.2, 0.9), v{0.0, 0.0, 1.0};
  const Vec3 nf{double(float(n.x)), double(float(n.y)), double(float(n.z))};
  const auto a = reference::preview_integrals(img.data(), 128, 64, n, v, 0.0025);
  const auto b = reference::preview_integrals(img.data(), 128, 64, nf, v, 0.0025);
  EXPECT_NEAR(a.s1[0] / b.s1[0], 1.0, 1e-5);
}

}  // namespace
}  // namespace brdfbake
