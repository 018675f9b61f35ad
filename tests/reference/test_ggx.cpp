// Identities of the reference's GGX terms (host/reference/src/ggx.cpp), each checked against a
// closed form or an integral computed here by its own route.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "brdfbake/math/conventions.hpp"
#include "brdfbake/reference/ggx.hpp"
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

// Integral of D_GGX(h) (n.h) over the hemisphere, in th_h directly: 2 pi int D cos sin dth, panels
// refined towards th = 0 at the lobe's width alpha.
double ggx_projected_area(double alpha) {
  return 2.0 * kPi * integrate_graded(0.0, 0.5 * kPi, 0.01 * alpha, 0.0, 0.05, [&](double th) {
           return ref::D_GGX(std::cos(th), alpha) * std::cos(th) * std::sin(th);
         });
}

// Visible-normal normalisation (Heitz 2014): integral over h of G1(v) max(0, v.h) D(h) = n.v.
// In th, ph about n with v in the x-z plane: v.h > 0 for every ph while th < pi/2 - th_v, else for
// ph < acos(-cot th_v cot th); the ph range closes like a square root there (square-root map).
double visible_normals(double n_dot_v, double alpha) {
  const double sin_v = std::sqrt(1.0 - n_dot_v * n_dot_v);
  const double th_v = std::acos(n_dot_v);
  const double th_c = 0.5 * kPi - th_v;
  const ref::GaussLegendreRule& rule = ref::gauss_legendre(20);
  auto phi_integral = [&](double th) {
    const double s = std::sin(th);
    const double c = std::cos(th);
    double phi_end = kPi;
    if (th > th_c && sin_v > 0.0) phi_end = std::acos(std::max(-1.0, -n_dot_v * c / (sin_v * s)));
    return 2.0 * ref::integrate_uniform(0.0, phi_end, 8, rule, [&](double ph) {
             const double v_dot_h = sin_v * s * std::cos(ph) + n_dot_v * c;
             return std::max(0.0, v_dot_h) * ref::D_GGX(c, alpha) * s;
           });
  };
  std::vector<ref::Panel> panels;
  ref::append_panels(0.0, th_c, ref::EndRefinement{true, 0.01 * alpha, 1.0}, ref::EndRefinement{}, 0.05, panels);
  ref::append_panels(th_c, 0.5 * kPi, ref::EndRefinement{false, 0.0, 2.0}, ref::EndRefinement{}, 0.05, panels);
  double sum = 0.0;
  for (const ref::Panel& p : panels) {
    ref::for_each_node(p, rule, [&](const ref::PanelNode& node) { sum += node.weight * phi_integral(node.t); });
  }
  return ref::G1_SmithGGX(n_dot_v, alpha) * sum;
}

}  // namespace

TEST(GgxReference, DistributionPeakAndWhiteLimit) {
  // D(n.h = 1) = 1 / (pi alpha^2); at alpha = 1 GGX is uniform, D = 1/pi for every n.h > 0.
  for (double alpha : {1e-3, 0.1, 0.5, 1.0}) {
    EXPECT_NEAR(ref::D_GGX(1.0, alpha) * kPi * alpha * alpha, 1.0, test::kRounding) << alpha;
  }
  for (double c : {1e-6, 0.3, 0.9}) EXPECT_NEAR(ref::D_GGX(c, 1.0), 1.0 / kPi, test::kRounding) << c;
  EXPECT_NEAR(ref::D_GGX(0.0, 0.5), 0.25 / kPi, test::kRounding);  // horizon: alpha^2 / pi
  EXPECT_EQ(ref::D_GGX(-0.5, 0.5), 0.0);                           // below the horizon
}

TEST(GgxReference, DistributionIsNormalised) {
  // Integral of D (n.h) dh = 1 (Walter et al. 2007, eq. 4), down to alpha = 1e-3.
  for (double alpha : {1e-3, 0.02, 0.1, 0.3, 0.7, 1.0}) {
    EXPECT_NEAR(ggx_projected_area(alpha), 1.0, test::kIdentityQuadrature) << "alpha " << alpha;
  }
}

TEST(GgxReference, LambdaSpotValues) {
  // Lambda = (sqrt(1 + alpha^2 tan^2) - 1) / 2: alpha = 1, 45 degrees gives (sqrt 2 - 1) / 2; normal
  // incidence gives 0; alpha = 0.5 at cos = 0.6 (tan = 4/3) gives (sqrt(1 + 4/9) - 1) / 2.
  EXPECT_NEAR(ref::Lambda_GGX(std::sqrt(0.5), 1.0), 0.5 * (std::sqrt(2.0) - 1.0), test::kRounding);
  EXPECT_EQ(ref::Lambda_GGX(1.0, 0.5), 0.0);
  EXPECT_NEAR(ref::Lambda_GGX(0.6, 0.5), 0.5 * (std::sqrt(13.0 / 9.0) - 1.0), test::kRounding);
  // Small alpha tan, where the naive formula cancels: Lambda ~ alpha^2 tan^2 / 4.
  EXPECT_NEAR(ref::Lambda_GGX(0.6, 1e-6) / (1e-12 * 16.0 / 9.0 / 4.0), 1.0, test::kSmallSlopeSeries);
  EXPECT_NEAR(ref::G1_SmithGGX(0.6, 0.5), 1.0 / (1.0 + ref::Lambda_GGX(0.6, 0.5)), test::kRounding);
}

TEST(GgxReference, HeightCorrelatedG2LiesBetweenSeparableAndMin) {
  // G1(v) G1(l) <= G2 <= min(G1(v), G1(l)), with equality on the left only at normal incidence.
  for (double alpha : {0.05, 0.4, 1.0}) {
    for (double nv : {0.05, 0.5, 1.0}) {
      for (double nl : {0.01, 0.3, 0.9}) {
        const double g2 = ref::G2_SmithGGXCorrelated(nv, nl, alpha);
        const double gv = ref::G1_SmithGGX(nv, alpha);
        const double gl = ref::G1_SmithGGX(nl, alpha);
        EXPECT_LE(gv * gl, g2 + test::kRounding);
        EXPECT_LE(g2, std::min(gv, gl) + test::kRounding);
      }
    }
  }
}

TEST(GgxReference, VisibilityIsG2Over4NlNvAndSymmetric) {
  for (double alpha : {1e-3, 0.2, 1.0}) {
    for (double nv : {1e-4, 0.3, 1.0}) {
      for (double nl : {1e-3, 0.6, 0.99}) {
        const double v = ref::V_SmithGGXCorrelated(nv, nl, alpha);
        const double expected = ref::G2_SmithGGXCorrelated(nv, nl, alpha) / (4.0 * nl * nv);
        EXPECT_NEAR(v / expected, 1.0, test::kRounding) << alpha << " " << nv << " " << nl;
        EXPECT_EQ(v, ref::V_SmithGGXCorrelated(nl, nv, alpha));
      }
    }
  }
}

TEST(GgxReference, VisibleNormalsAreNormalised) {
  // Heitz 2014: the visible projected area of the microsurface equals the macrosurface's,
  // integral of G1(v) max(0, v.h) D(h) dh = n.v.
  for (double alpha : {0.1, 0.5, 1.0}) {
    for (double nv : {0.2, 0.6, 0.95, 1.0}) {
      EXPECT_NEAR(visible_normals(nv, alpha), nv, test::kIdentityQuadrature) << alpha << " " << nv;
    }
  }
}

TEST(GgxReference, EveryTermIsFiniteAtTheCorners) {
  for (double alpha : {0.0, 1e-6, 1.0}) {
    for (double a : {0.0, 1e-6, 1.0}) {
      EXPECT_TRUE(std::isfinite(ref::D_GGX(a, alpha)));
      EXPECT_TRUE(std::isfinite(ref::Lambda_GGX(a, alpha)));
      EXPECT_TRUE(std::isfinite(ref::G1_SmithGGX(a, alpha)));
      for (double b : {0.0, 1e-6, 1.0}) {
        EXPECT_TRUE(std::isfinite(ref::G2_SmithGGXCorrelated(a, b, alpha)));
        EXPECT_TRUE(std::isfinite(ref::V_SmithGGXCorrelated(a, b, alpha))) << a << " " << b << " " << alpha;
      }
    }
  }
}
