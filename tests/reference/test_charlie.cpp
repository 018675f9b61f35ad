// Identities of the reference's Charlie sheen terms (host/reference/src/charlie.cpp), each checked
// against a closed form, the paper's parameters or an integral computed here by its own route.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "brdfbake/math/conventions.hpp"
#include "brdfbake/reference/charlie.hpp"
#include "brdfbake/reference/quadrature.hpp"
#include "support/tolerances.hpp"

namespace ref = brdfbake::reference;
namespace test = brdfbake::test;

namespace {

using brdfbake::math::kPi;

// Integral over [a, b] on panels refined geometrically towards both ends (down to `min_size`) and
// at most `max_width` wide, 20 Gauss nodes each.
template <class F>
double integrate_graded(double a, double b, double min_a, double min_b, double max_width, F&& f) {
  std::vector<ref::Panel> panels;
  ref::append_panels(a, b, ref::EndRefinement{min_a > 0.0, min_a, 1.0}, ref::EndRefinement{min_b > 0.0, min_b, 1.0},
                     max_width, panels);
  const ref::GaussLegendreRule& rule = ref::gauss_legendre(20);
  double sum = 0.0;
  for (const ref::Panel& p : panels) {
    ref::for_each_node(p, rule, [&](const ref::PanelNode& node) { sum += node.weight * f(node.t); });
  }
  return sum;
}

// Integral of D_Charlie(h) (n.h) over the hemisphere, in c = n.h (dh = dc dph): the band at
// c ~ 0 has width sqrt(alpha), the power law (1 - c^2)^(1/2alpha) sits at c = 1.
double charlie_projected_area(double alpha) {
  return 2.0 * kPi * integrate_graded(0.0, 1.0, 0.01 * std::sqrt(alpha), 1e-10, 0.5 * std::sqrt(alpha), [&](double c) {
           return ref::D_Charlie(c, alpha) * c;
         });
}

}  // namespace

TEST(CharlieReference, DistributionSpotValues) {
  // D(n.h = 0) = (2 + 1/alpha) / (2 pi); D(n.h = 1) = 0.
  for (double alpha : {1e-6, 0.1, 1.0}) {
    EXPECT_NEAR(ref::D_Charlie(0.0, alpha) * 2.0 * kPi / (2.0 + 1.0 / alpha), 1.0, test::kRounding);
    EXPECT_EQ(ref::D_Charlie(1.0, alpha), 0.0);
  }
  // alpha = 1/2: D = 4 sin^2 / (2 pi) = 4 (1 - c^2) / (2 pi).
  EXPECT_NEAR(ref::D_Charlie(0.6, 0.5), 4.0 * 0.64 / (2.0 * kPi), test::kRounding);
}

TEST(CharlieReference, DistributionIsNormalised) {
  // Estevez & Kulla 2017: integral of D (n.h) dh = 1, including non-integer 1/alpha.
  for (double alpha : {1e-4, 0.01, 0.1, 0.3, 0.5, 0.7, 1.0}) {
    EXPECT_NEAR(charlie_projected_area(alpha), 1.0, test::kIdentityQuadrature) << "alpha " << alpha;
  }
}

TEST(CharlieReference, FittedLambdaEndpointsUseThePaperParameters) {
  // Lambda(0) = exp(L(0)) = exp(a + e): the r = 0 set (25.3245, -4.85967) at alpha = 0 and the
  // r = 1 set (21.5473, -4.32054) at alpha = 1 (Estevez & Kulla 2017).
  EXPECT_NEAR(ref::Lambda_CharlieEstevezKulla(0.0, 0.0) / std::exp(25.3245 - 4.85967), 1.0, test::kRounding);
  EXPECT_NEAR(ref::Lambda_CharlieEstevezKulla(0.0, 1.0) / std::exp(21.5473 - 4.32054), 1.0, test::kRounding);
  // Lambda(1) = exp(2 L(1/2) - L(0)) is tiny but positive; Lambda decreases with the cosine.
  for (double alpha : {0.0, 0.3, 1.0}) {
    double previous = ref::Lambda_CharlieEstevezKulla(0.0, alpha);
    for (double c = 0.05; c <= 1.0 + 1e-12; c += 0.05) {
      const double lambda = ref::Lambda_CharlieEstevezKulla(c, alpha);
      EXPECT_LT(lambda, previous) << alpha << " " << c;
      previous = lambda;
    }
    EXPECT_GT(previous, 0.0);
    EXPECT_LT(previous, 1e-7);
  }
}

TEST(CharlieReference, FittedLambdaIsContinuousAtOneHalf) {
  // The two branches meet at cos = 1/2 in value and slope (the mirrored form is built for it).
  for (double alpha : {1e-6, 0.25, 0.6, 1.0}) {
    const double below = ref::Lambda_CharlieEstevezKulla(std::nextafter(0.5, 0.0), alpha);
    const double at = ref::Lambda_CharlieEstevezKulla(0.5, alpha);
    EXPECT_NEAR(below / at, 1.0, test::kRounding) << alpha;
    const double h = 1e-6;
    const double slope_below = (at - ref::Lambda_CharlieEstevezKulla(0.5 - h, alpha)) / h;
    const double slope_above = (ref::Lambda_CharlieEstevezKulla(0.5 + h, alpha) - at) / h;
    // One-sided differences differ by O(h |Lambda''|); Lambda'' jumps at 1/2 but is O(10).
    EXPECT_NEAR(slope_below, slope_above, test::kOneSidedSlopes * std::fabs(slope_below)) << alpha;
  }
}

TEST(CharlieReference, VisibilitiesAreSymmetricWithSpotValues) {
  for (double nv : {1e-3, 0.3, 0.8}) {
    for (double nl : {0.02, 0.5, 1.0}) {
      EXPECT_EQ(ref::V_Neubelt(nv, nl), ref::V_Neubelt(nl, nv));
      EXPECT_NEAR(ref::V_CharlieEstevezKulla(nv, nl, 0.3) / ref::V_CharlieEstevezKulla(nl, nv, 0.3), 1.0,
                  test::kRounding);
      const double lambdas = 1.0 + ref::Lambda_CharlieEstevezKulla(nv, 0.3) + ref::Lambda_CharlieEstevezKulla(nl, 0.3);
      EXPECT_NEAR(ref::V_CharlieEstevezKulla(nv, nl, 0.3) * lambdas * 4.0 * nv * nl, 1.0, test::kRounding);
    }
  }
  EXPECT_EQ(ref::V_Neubelt(1.0, 1.0), 0.25);
  EXPECT_NEAR(ref::V_Neubelt(0.5, 0.5), 1.0 / 3.0, test::kRounding);
}

TEST(CharlieReference, EveryTermIsFiniteAtTheCorners) {
  for (double alpha : {0.0, 1e-6, 1.0}) {
    for (double a : {0.0, 1e-6, 1.0}) {
      EXPECT_TRUE(std::isfinite(ref::D_Charlie(a, alpha)));
      EXPECT_TRUE(std::isfinite(ref::Lambda_CharlieEstevezKulla(a, alpha)));
      for (double b : {0.0, 1e-6, 1.0}) {
        EXPECT_TRUE(std::isfinite(ref::V_CharlieEstevezKulla(a, b, alpha))) << a << " " << b << " " << alpha;
        EXPECT_TRUE(std::isfinite(ref::V_Neubelt(a, b)));
      }
    }
  }
}
