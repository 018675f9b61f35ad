// The scalar reference's DFG integrals (host/reference/src/dfg_lut.cpp) against limits, closed forms,
// an independent brute-force quadrature over l, and their own doubled resolution.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "brdfbake/math/conventions.hpp"
#include "brdfbake/reference/burley.hpp"
#include "brdfbake/reference/charlie.hpp"
#include "brdfbake/reference/dfg_lut.hpp"
#include "brdfbake/reference/ggx.hpp"
#include "brdfbake/reference/quadrature.hpp"
#include "identities/dfg_identities.hpp"
#include "support/tolerances.hpp"

namespace ref = brdfbake::reference;
namespace test = brdfbake::test;

namespace brdfbake::test {
namespace {

// The converged reference integrals, in double.
class ReferenceDfg : public DfgBackend {
 public:
  std::vector<DfgTexel> ggx(const std::vector<double>& n_dot_v, double roughness) override {
    std::vector<DfgTexel> out;
    for (double nv : n_dot_v) {
      const ref::DfgGgx d = ref::dfg_ggx(nv, roughness);
      out.push_back({d.scale, d.bias, ref::burley_albedo(nv, roughness)});
    }
    return out;
  }
  std::vector<double> charlie(const std::vector<double>& n_dot_v, double sheen_roughness, bool neubelt) override {
    std::vector<double> out;
    for (double nv : n_dot_v)
      out.push_back(ref::charlie_albedo(nv, sheen_roughness,
                                        neubelt ? ref::SheenVisibility::Neubelt : ref::SheenVisibility::EstevezKulla));
    return out;
  }
};

}  // namespace

void make_dfg_backend(Backend, std::unique_ptr<DfgBackend>& out) { out = std::make_unique<ReferenceDfg>(); }

INSTANTIATE_TEST_SUITE_P(Reference, DfgIdentities, ::testing::Values(Backend::Reference), BackendName());

}  // namespace brdfbake::test

namespace {

using brdfbake::math::kPi;

double pow5(double x) { return x * x * x * x * x; }

// Brute force over l in spherical coordinates about n (unlike the reference, which integrates over
// h): mu = n.l in [0, 1] split at 1/2 and refined towards 0 and 1 (the visibilities' features sit
// there), ph in [0, pi] doubled, `panels` panels per unit in each, 16 Gauss nodes per panel.
// f(n_dot_l, n_dot_h, v_dot_h) is the BRDF times n.l.
template <class F>
double brute_force(double n_dot_v, int panels, F&& f) {
  const ref::GaussLegendreRule& rule = ref::gauss_legendre(16);
  const double sin_v = std::sqrt(1.0 - n_dot_v * n_dot_v);
  std::vector<ref::Panel> mu_panels;
  ref::append_panels(0.0, 0.5, ref::EndRefinement{true, 1e-9, 1.0}, ref::EndRefinement{}, 1.0 / panels, mu_panels);
  ref::append_panels(0.5, 1.0, ref::EndRefinement{}, ref::EndRefinement{true, 1e-9, 1.0}, 1.0 / panels, mu_panels);
  double sum = 0.0;
  for (const ref::Panel& p : mu_panels) {
    ref::for_each_node(p, rule, [&](const ref::PanelNode& node) {
      const double mu = node.t;
      const double sin_l = std::sqrt((1.0 - mu) * (1.0 + mu));
      sum += node.weight * 2.0 * ref::integrate_uniform(0.0, kPi, 4 * panels, rule, [&](double ph) {
               // h = (l + v) / |l + v|
               const double hx = sin_l * std::cos(ph) + sin_v;
               const double hy = sin_l * std::sin(ph);
               const double hz = mu + n_dot_v;
               const double len = std::sqrt(hx * hx + hy * hy + hz * hz);
               return f(mu, hz / len, (hx * sin_v + hz * n_dot_v) / len);
             });
    });
  }
  return sum;
}

// The brute force at `panels` and twice that; asserts its own convergence and returns the finer.
template <class F>
double converged_brute_force(double n_dot_v, F&& f) {
  const double coarse = brute_force(n_dot_v, 4, f);
  const double fine = brute_force(n_dot_v, 8, f);
  EXPECT_NEAR(coarse, fine, test::kBruteForceConverged) << "brute force itself not converged";
  return fine;
}

// Inputs covering the corners of every table and the interior.
const double kViewCorners[] = {0.0, 1e-6, 1e-3, 0.5, 1.0};
const double kRoughCorners[] = {0.0, 1e-3, 0.5, 1.0};

}  // namespace

// Gauss-Legendre rules themselves are tested with the shared maths (tests/math/test_gauss_legendre.cpp).
TEST(Quadrature, GradedPanelsCoverTheIntervalAndMapsRemoveSquareRoots) {
  std::vector<ref::Panel> panels;
  ref::append_panels(0.0, 2.0, ref::EndRefinement{true, 1e-6, 2.0}, ref::EndRefinement{true, 1e-3, 1.0}, 0.3, panels);
  ASSERT_GE(panels.size(), 20u);
  EXPECT_EQ(panels.front().a, 0.0);
  EXPECT_EQ(panels.back().b, 2.0);
  for (std::size_t k = 0; k < panels.size(); ++k) {
    EXPECT_LE(panels[k].b - panels[k].a, 0.3 + 1e-15);
    if (k > 0) {
      EXPECT_EQ(panels[k].a, panels[k - 1].b);
    }
  }
  EXPECT_NEAR(panels.front().b, 1e-6, test::kPanelBreakpoint);
  // integral_0^2 sqrt(t) dt = (2/3) 2^(3/2), exact to rounding with the square-root map at 0.
  const ref::GaussLegendreRule& rule = ref::gauss_legendre(10);
  double sum = 0.0;
  for (const ref::Panel& p : panels) {
    ref::for_each_node(p, rule, [&](const ref::PanelNode& node) { sum += node.weight * std::sqrt(node.t); });
  }
  EXPECT_NEAR(sum, 2.0 / 3.0 * std::pow(2.0, 1.5), test::kRounding);
}

// At roughness 1 and n.v = 1 the bias is int_0^1 mu / (1 + mu) (1 - sqrt((1 + mu) / 2))^5 dmu
// (v.h = n.h); the albedo's closed form is in the identity body (tests/identities/dfg_identities.hpp).
TEST(DfgGgx, WhiteLobeBiasAtNormalView) {
  const double bias_n = ref::integrate_uniform(0.0, 1.0, 8, ref::gauss_legendre(20), [](double mu) {
    return mu / (1.0 + mu) * pow5(1.0 - std::sqrt(0.5 * (1.0 + mu)));
  });
  EXPECT_NEAR(ref::dfg_ggx(1.0, 1.0).bias, bias_n, test::kAnalytic);
}

TEST(DfgGgx, AgreesWithBruteForceOverL) {
  const double points[][2] = {{0.3, 0.5}, {0.7, 0.8}, {0.5, 0.6}, {0.9, 1.0}};
  for (const auto& p : points) {
    const double nv = p[0];
    const double alpha = p[1] * p[1];
    const double scale = converged_brute_force(nv, [&](double mu, double nh, double vh) {
      return ref::D_GGX(nh, alpha) * ref::V_SmithGGXCorrelated(nv, mu, alpha) * mu * (1.0 - pow5(1.0 - vh));
    });
    const double bias = converged_brute_force(nv, [&](double mu, double nh, double vh) {
      return ref::D_GGX(nh, alpha) * ref::V_SmithGGXCorrelated(nv, mu, alpha) * mu * pow5(1.0 - vh);
    });
    const ref::DfgGgx d = ref::dfg_ggx(nv, p[1]);
    EXPECT_NEAR(d.scale, scale, test::kAnalytic) << nv << " " << p[1];
    EXPECT_NEAR(d.bias, bias, test::kAnalytic) << nv << " " << p[1];
  }
}

TEST(DfgGgx, GrazingViewIsTheLimit) {
  // n.v = 0 stands for the limit n.v -> 0 (docs/CONVENTIONS.md): it must match the linear
  // extrapolation of two tiny n.v, at roughness where the lobe's grazing scale is small and large.
  for (double r : {0.0, 0.03, 0.5, 1.0}) {
    const double h = 1e-12;
    const ref::DfgGgx at0 = ref::dfg_ggx(0.0, r);
    const ref::DfgGgx at1 = ref::dfg_ggx(h, r);
    const ref::DfgGgx at2 = ref::dfg_ggx(2.0 * h, r);
    EXPECT_NEAR(at0.scale, 2.0 * at1.scale - at2.scale, test::kGrazingLimit) << r;
    EXPECT_NEAR(at0.bias, 2.0 * at1.bias - at2.bias, test::kGrazingLimit) << r;
  }
  // At roughness 1 the limits are closed forms: albedo 1, bias = mean of Fc = 1/21.
  const ref::DfgGgx d = ref::dfg_ggx(0.0, 1.0);
  EXPECT_NEAR(d.scale + d.bias, 1.0, test::kGrazingLimit);
  EXPECT_NEAR(d.bias, 1.0 / 21.0, test::kGrazingLimit);
}

TEST(BurleyAlbedo, FixedRetroReflectionHasAClosedForm) {
  // F_D90 = 1 is Lambert (albedo 1). For any fixed F_D90, with 2 int mu (1 - mu)^5 dmu = 1/21:
  // albedo = (1 + (F_D90 - 1)(1 - n.v)^5)(1 + (F_D90 - 1) / 21).
  for (double nv : {0.0, 0.3, 1.0}) {
    EXPECT_NEAR(ref::burley_albedo_fixed_f90(nv, 1.0), 1.0, test::kRounding) << nv;
    for (double f90 : {0.5, 1.5, 2.5}) {
      const double expected = (1.0 + (f90 - 1.0) * pow5(1.0 - nv)) * (1.0 + (f90 - 1.0) / 21.0);
      EXPECT_NEAR(ref::burley_albedo_fixed_f90(nv, f90), expected, test::kRounding) << nv << " " << f90;
    }
  }
}

TEST(BurleyAlbedo, AgreesWithBruteForceOverL) {
  for (double nv : {0.1, 0.6}) {
    for (double r : {0.2, 0.9}) {
      const double brute = converged_brute_force(nv, [&](double mu, double, double vh) {
        return ref::Fd_Burley(nv, mu, vh, r) * mu;  // l.h = v.h
      });
      EXPECT_NEAR(ref::burley_albedo(nv, r), brute, test::kAnalytic) << nv << " " << r;
    }
  }
}

TEST(CharlieAlbedo, AgreesWithBruteForceOverL) {
  // Over l, D_Charlie ~ sin(th_h)^(1/alpha) has a conical point at the mirror direction (h = n)
  // unless 1/alpha is an even integer, which would stall the brute force: alpha = 1/2, 1/4, 1/6.
  const double points[][2] = {{0.3, std::sqrt(0.5)}, {0.6, 0.5}, {0.8, std::sqrt(1.0 / 6.0)}, {0.15, std::sqrt(0.5)}};
  for (const auto& p : points) {
    const double nv = p[0];
    const double alpha = p[1] * p[1];
    const double ek = converged_brute_force(nv, [&](double mu, double nh, double) {
      return ref::D_Charlie(nh, alpha) * ref::V_CharlieEstevezKulla(nv, mu, alpha) * mu;
    });
    const double neubelt = converged_brute_force(
        nv, [&](double mu, double nh, double) { return ref::D_Charlie(nh, alpha) * ref::V_Neubelt(nv, mu) * mu; });
    EXPECT_NEAR(ref::charlie_albedo(nv, p[1], ref::SheenVisibility::EstevezKulla), ek, test::kAnalytic) << nv;
    EXPECT_NEAR(ref::charlie_albedo(nv, p[1], ref::SheenVisibility::Neubelt), neubelt, test::kAnalytic) << nv;
  }
}

TEST(CharlieAlbedo, VanishesForASharpBandSeenFromAbove) {
  // At small alpha the lobe is a band of width sqrt(alpha) around th_h = 90 degrees; from n.v = 0.5
  // only h with n.h > n.v / 2 reflect above the horizon, where D ~ (1 - 1/16)^(1/(2 alpha)) ~ 0.
  for (auto visibility : {ref::SheenVisibility::EstevezKulla, ref::SheenVisibility::Neubelt}) {
    EXPECT_LT(ref::charlie_albedo(0.5, 0.01, visibility), 1e-12);
    EXPECT_GE(ref::charlie_albedo(0.5, 0.01, visibility), 0.0);
  }
}

TEST(Convergence, DoubledResolutionAgreesAtTheCorners) {
  // Every integral against itself at twice the Gauss order and twice the panel refinement. The
  // Charlie albedo exceeds 1 at grazing small-roughness corners (up to ~1e3): relative there.
  const ref::Quadrature doubled{2 * ref::Quadrature{}.order, 2 * ref::Quadrature{}.refinement};
  for (double nv : kViewCorners) {
    for (double r : kRoughCorners) {
      const ref::DfgGgx d = ref::dfg_ggx(nv, r);
      const ref::DfgGgx d2 = ref::dfg_ggx(nv, r, doubled);
      EXPECT_NEAR(d.scale, d2.scale, test::kSelfConvergence) << nv << " " << r;
      EXPECT_NEAR(d.bias, d2.bias, test::kSelfConvergence) << nv << " " << r;
      EXPECT_NEAR(ref::burley_albedo(nv, r), ref::burley_albedo(nv, r, doubled), test::kSelfConvergence);
      for (auto visibility : {ref::SheenVisibility::EstevezKulla, ref::SheenVisibility::Neubelt}) {
        const double c = ref::charlie_albedo(nv, r, visibility);
        const double c2 = ref::charlie_albedo(nv, r, visibility, doubled);
        EXPECT_NEAR(c, c2, test::kSelfConvergence * std::max(1.0, c2)) << nv << " " << r;
      }
    }
  }
}

TEST(EdgeCases, EveryIntegralIsFiniteAtTheCorners) {
  for (double nv : kViewCorners) {
    for (double r : kRoughCorners) {
      const ref::DfgGgx d = ref::dfg_ggx(nv, r);
      EXPECT_TRUE(std::isfinite(d.scale) && std::isfinite(d.bias)) << nv << " " << r;
      EXPECT_TRUE(std::isfinite(ref::burley_albedo(nv, r))) << nv << " " << r;
      EXPECT_TRUE(std::isfinite(ref::charlie_albedo(nv, r, ref::SheenVisibility::EstevezKulla))) << nv << " " << r;
      EXPECT_TRUE(std::isfinite(ref::charlie_albedo(nv, r, ref::SheenVisibility::Neubelt))) << nv << " " << r;
    }
  }
  EXPECT_THROW(ref::dfg_ggx(std::nan(""), 0.5), std::invalid_argument);
  EXPECT_THROW(ref::charlie_albedo(0.5, std::nan(""), ref::SheenVisibility::Neubelt), std::invalid_argument);
  EXPECT_THROW(ref::dfg_ggx(0.5, 0.5, ref::Quadrature{0, 1}), std::invalid_argument);
}

TEST(LutTable, CellCentresLayoutAndThreads) {
  const int w = 4;
  const int h = 3;
  const std::vector<double> ggx = ref::lut_table(ref::LutKind::Ggx, w, h, ref::SheenVisibility::EstevezKulla, 2);
  const std::vector<double> multi = ref::lut_table(ref::LutKind::GgxMultiscatter, w, h);
  const std::vector<double> sheen = ref::lut_table(ref::LutKind::Charlie, w, h, ref::SheenVisibility::Neubelt, 1);
  ASSERT_EQ(ggx.size(), static_cast<std::size_t>(w * h * 3));
  ASSERT_EQ(sheen.size(), static_cast<std::size_t>(w * h));
  EXPECT_EQ(ref::lut_channels(ref::LutKind::Ggx), 3);
  EXPECT_EQ(ref::lut_channels(ref::LutKind::Charlie), 1);
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      const double nv = (i + 0.5) / w;
      const double r = (j + 0.5) / h;
      const auto texel = static_cast<std::size_t>(j * w + i);
      const ref::DfgGgx d = ref::dfg_ggx(nv, r);
      EXPECT_EQ(ggx[3 * texel + 0], d.scale);
      EXPECT_EQ(ggx[3 * texel + 1], d.bias);
      EXPECT_EQ(ggx[3 * texel + 2], ref::burley_albedo(nv, r));
      EXPECT_EQ(multi[3 * texel + 0], d.bias);
      EXPECT_EQ(multi[3 * texel + 1], d.scale + d.bias);
      EXPECT_EQ(multi[3 * texel + 2], ggx[3 * texel + 2]);
      EXPECT_EQ(sheen[texel], ref::charlie_albedo(nv, r, ref::SheenVisibility::Neubelt));
    }
  }
  // Deterministic whatever the thread count.
  EXPECT_EQ(ref::lut_table(ref::LutKind::Ggx, w, h, ref::SheenVisibility::EstevezKulla, 1), ggx);
  EXPECT_THROW(ref::lut_table(ref::LutKind::Ggx, 0, 4), std::invalid_argument);
}
