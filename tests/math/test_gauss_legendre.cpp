// Gauss-Legendre rules of the shared maths: exact on polynomials up to degree 2n - 1, the known
// small rules, symmetry.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "brdfbake/math/gauss_legendre.hpp"
#include "support/tolerances.hpp"

namespace brdfbake::math {
namespace {

TEST(GaussLegendre, ExactToDegree2nMinus1) {
  for (int n : {1, 2, 5, 10, 20, 64}) {
    const GaussLegendreRule& rule = gauss_legendre(n);
    ASSERT_EQ(rule.nodes.size(), static_cast<std::size_t>(n));
    for (int degree = 0; degree <= 2 * n - 1; ++degree) {
      double sum = 0.0;
      for (std::size_t k = 0; k < rule.nodes.size(); ++k) sum += rule.weights[k] * std::pow(rule.nodes[k], degree);
      const double exact = degree % 2 == 1 ? 0.0 : 2.0 / (degree + 1.0);
      EXPECT_NEAR(sum, exact, test::kRounding) << "n " << n << " degree " << degree;
    }
  }
  // ... and not beyond: x^(2n) is integrated with an error (2 / (2n + 1) > the rule's sum).
  const GaussLegendreRule& three = gauss_legendre(3);
  double x6 = 0.0;
  for (std::size_t k = 0; k < 3; ++k) x6 += three.weights[k] * std::pow(three.nodes[k], 6);
  EXPECT_GT(2.0 / 7.0 - x6, 1e-3);
}

TEST(GaussLegendre, KnownSmallRules) {
  // Abramowitz & Stegun, table 25.4: n = 2: +-1/sqrt(3), weights 1; n = 3: 0, +-sqrt(3/5), 8/9, 5/9.
  const GaussLegendreRule& two = gauss_legendre(2);
  EXPECT_NEAR(two.nodes[1], 1.0 / std::sqrt(3.0), test::kRounding);
  EXPECT_NEAR(two.weights[0], 1.0, test::kRounding);
  const GaussLegendreRule& three = gauss_legendre(3);
  EXPECT_EQ(three.nodes[1], 0.0);
  EXPECT_NEAR(three.nodes[2], std::sqrt(0.6), test::kRounding);
  EXPECT_NEAR(three.weights[1], 8.0 / 9.0, test::kRounding);
  EXPECT_NEAR(three.weights[0], 5.0 / 9.0, test::kRounding);
}

TEST(GaussLegendre, SymmetricAscendingAndCached) {
  for (int n : {7, 64, 512}) {
    const GaussLegendreRule& rule = gauss_legendre(n);
    double sum = 0.0;
    for (std::size_t k = 0; k < rule.nodes.size(); ++k) {
      EXPECT_EQ(rule.nodes[k], -rule.nodes[rule.nodes.size() - 1 - k]);
      EXPECT_EQ(rule.weights[k], rule.weights[rule.nodes.size() - 1 - k]);
      EXPECT_GT(rule.weights[k], 0.0);
      if (k > 0) {
        EXPECT_LT(rule.nodes[k - 1], rule.nodes[k]);
      }
      sum += rule.weights[k];
    }
    EXPECT_NEAR(sum, 2.0, test::kRounding) << n;
    EXPECT_EQ(&gauss_legendre(n), &rule);
  }
  EXPECT_THROW(gauss_legendre(0), std::invalid_argument);
  EXPECT_THROW(gauss_legendre(kMaxGaussLegendreOrder + 1), std::invalid_argument);
}

}  // namespace
}  // namespace brdfbake::math
