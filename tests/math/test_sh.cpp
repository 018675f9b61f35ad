// The real SH basis of the shared maths: orthonormal by quadrature, its documented values and
// signs, and the cosine lobe's coefficients against their defining integral.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/gauss_legendre.hpp"
#include "brdfbake/math/sh.hpp"
#include "support/tolerances.hpp"

namespace brdfbake::math {
namespace {

TEST(ShBasis, IsOrthonormal) {
  // Gauss-Legendre in z times the midpoint rule in phi: exact for these polynomial products
  const auto& gl = gauss_legendre(16);
  const int n_phi = 32;
  std::vector<double> gram(25 * 25, 0.0);
  for (size_t a = 0; a < gl.nodes.size(); ++a)
    for (int m = 0; m < n_phi; ++m) {
      const double z = gl.nodes[a], phi = 2.0 * kPi * (m + 0.5) / n_phi, r = std::sqrt(1 - z * z);
      const auto y = sh_basis(5, {r * std::cos(phi), r * std::sin(phi), z});
      const double w = gl.weights[a] * 2.0 * kPi / n_phi;
      for (size_t i = 0; i < 25; ++i)
        for (size_t j = 0; j < 25; ++j) gram[i * 25 + j] += w * y[i] * y[j];
    }
  for (size_t i = 0; i < 25; ++i)
    for (size_t j = 0; j < 25; ++j) EXPECT_NEAR(gram[i * 25 + j], i == j ? 1.0 : 0.0, test::kAnalytic) << i << "," << j;
}

TEST(ShBasis, DocumentedValuesAndSigns) {
  // docs/CONVENTIONS.md and every SH JSON: Y00 = 0.282095, Y1-1 = 0.488603 y, Y10 = 0.488603 z,
  // Y11 = 0.488603 x, Y2-2 = 1.092548 xy, Y20 = 0.315392 (3z^2 - 1), Y22 = 0.546274 (x^2 - y^2)
  const double s = 1.0 / std::sqrt(3.0);
  const auto y = sh_basis(3, {s, s, s});
  EXPECT_NEAR(y[0], 0.282095, test::kSixDecimals);
  EXPECT_NEAR(y[size_t(sh_index(1, -1))], 0.488603 * s, test::kSixDecimals);
  EXPECT_NEAR(y[size_t(sh_index(1, 0))], 0.488603 * s, test::kSixDecimals);
  EXPECT_NEAR(y[size_t(sh_index(1, 1))], 0.488603 * s, test::kSixDecimals);
  EXPECT_NEAR(y[size_t(sh_index(2, -2))], 1.092548 / 3.0, test::kSixDecimals);
  EXPECT_NEAR(y[size_t(sh_index(2, 0))], 0.0, test::kRoundingFewOps);  // 3 z^2 - 1 = 0
  EXPECT_NEAR(y[size_t(sh_index(2, 2))], 0.0, test::kRoundingFewOps);
  // the Condon-Shortley-free signs: Y_1,-1 ~ +y, Y_10 ~ +z, Y_11 ~ +x
  EXPECT_GT(sh_basis(2, {0.0, 1.0, 0.0})[1], 0.0);
  EXPECT_GT(sh_basis(2, {0.0, 0.0, 1.0})[2], 0.0);
  EXPECT_GT(sh_basis(2, {1.0, 0.0, 0.0})[3], 0.0);
  EXPECT_EQ(sh_basis(3, {0, 0, 1}).size(), 9u);
  EXPECT_EQ(sh_basis(5, {0, 0, 1}).size(), 25u);
  EXPECT_THROW(sh_basis(6, {0, 0, 1}), std::invalid_argument);
}

// A_l = 2 pi int_0^1 t P_l(t) dt (Ramamoorthi & Hanrahan 2001, eq. 8): the zonal coefficient of the
// clamped cosine, by Gauss-Legendre on [0, 1] (exact: P_l is a polynomial), from Y_l0 at the pole:
// Y_l0(t) = sqrt((2l + 1) / 4pi) P_l(t).
TEST(ShBasis, CosineLobeIsTheClampedCosinesProjection) {
  const auto& gl = gauss_legendre(8);
  for (int l = 0; l <= 4; ++l) {
    double integral = 0.0;
    for (size_t k = 0; k < gl.nodes.size(); ++k) {
      const double t = 0.5 * (1.0 + gl.nodes[k]), w = 0.5 * gl.weights[k];
      const double r = std::sqrt(1.0 - t * t);
      const double y_l0 = sh_basis(5, {r, 0.0, t})[size_t(sh_index(l, 0))];
      integral += w * t * y_l0;
    }
    // the cosine's coefficient is 2 pi int t Y_l0 dt; A_l multiplies L_lm Y_lm, so A_l is that
    // coefficient divided by Y_l0 at the pole, sqrt((2l + 1) / 4pi)
    const double a_l = 2.0 * kPi * integral / std::sqrt((2.0 * l + 1.0) / (4.0 * kPi));
    EXPECT_NEAR(sh_cosine_lobe(l), a_l, test::kRounding) << l;
  }
  EXPECT_EQ(sh_cosine_lobe(3), 0.0);
  EXPECT_THROW(sh_cosine_lobe(5), std::invalid_argument);
}

}  // namespace
}  // namespace brdfbake::math
