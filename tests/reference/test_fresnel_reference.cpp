// The Fresnel identities (tests/identities/fresnel_identities.hpp) on the scalar double reference, and
// what only the reference's API offers: the polarised reflectances, the fits and their error measure.
// The preset data is checked in tests/host/test_material_presets.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include "brdfbake/reference/fresnel.hpp"
#include "identities/fresnel_identities.hpp"
#include "support/tolerances.hpp"

namespace brdfbake {
namespace test {
namespace {

// The oracle's own functions, in double.
class ReferenceFresnel : public FresnelBackend {
 public:
  std::vector<double> eval(const FresnelCurve& c, const std::vector<double>& cosines) override {
    std::vector<double> out;
    const std::vector<double>& p = c.p;
    for (double x : cosines) {
      switch (c.kind) {
        case FresnelCurve::Kind::Schlick:
          out.push_back(reference::fresnel_schlick(x, p[0], p[1]));
          break;
        case FresnelCurve::Kind::SchlickMetallic:
          out.push_back(
              reference::fresnel_schlick(x, reference::schlick_metallic_f0({p[0], p[0], p[0]}, p[1], p[2]).r));
          break;
        case FresnelCurve::Kind::SchlickIor:
          out.push_back(reference::fresnel_schlick(x, reference::f0_from_ior(p[0], p[1])));
          break;
        case FresnelCurve::Kind::Dielectric:
          out.push_back(reference::fresnel_dielectric(x, p[1] / p[0]));
          break;
        case FresnelCurve::Kind::Conductor:
          out.push_back(reference::fresnel_conductor(x, p[0], p[1]));
          break;
        case FresnelCurve::Kind::F82Tint:
          out.push_back(reference::fresnel_f82_tint(x, p[0], p[1]));
          break;
        case FresnelCurve::Kind::Empirical:
          out.push_back(reference::fresnel_empirical(x, p[0], p[1], p[2]));
          break;
      }
    }
    return out;
  }
};

}  // namespace

void make_fresnel_backend(Backend, std::unique_ptr<FresnelBackend>& out) { out = std::make_unique<ReferenceFresnel>(); }

INSTANTIATE_TEST_SUITE_P(Reference, FresnelIdentities, ::testing::Values(Backend::Reference), BackendName());

}  // namespace test

namespace {

using namespace reference;

constexpr double kRoundoff = test::kFresnelReferenceRounding;

// Uniform cosine grid over [0, 1], both ends included.
std::vector<double> cos_grid(int n) {
  std::vector<double> g;
  for (int i = 0; i < n; ++i) g.push_back(static_cast<double>(i) / static_cast<double>(n - 1));
  return g;
}

// ---- The reference's own API ----------------------------------------------------------------------

TEST(FresnelReference, SchlickF0FromConductorIsTheNormalIncidenceReflectance) {
  EXPECT_NEAR(f0_from_ior(1.0, 1.5), 0.04, kRoundoff);
  EXPECT_NEAR(f0_from_ior(1.5, 1.0), 0.04, kRoundoff);
  EXPECT_EQ(f0_from_ior(1.5, 1.5), 0.0);
  for (const auto& [n, k] : std::vector<std::pair<double, double>>{
           {0.188, 3.403}, {0.057, 4.254}, {2.892, 3.065}, {1.5, 0.0}, {10.0, 100.0}, {0.01, 0.01}}) {
    const double expected = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
    EXPECT_NEAR(schlick_f0_from_conductor(n, k), expected, kRoundoff) << n << " + " << k << "i";
  }
}

// Hand computation, n = 1.5 at 45 degrees: cos_i = sin_i = 1/sqrt(2); sin_t = sin_i / 1.5, so
// cos_t = sqrt(1 - 2/9) = sqrt(7)/3 and n cos_t = sqrt(7)/2, cos_i = sqrt(2)/2.
//   r_s = (cos_i - n cos_t) / (cos_i + n cos_t) = (sqrt2 - sqrt7) / (sqrt2 + sqrt7)
//   R_s = (sqrt7 - sqrt2)^4 / (7 - 2)^2 = (9 - 2 sqrt14)^2 / 25 = (137 - 36 sqrt14) / 25 = 0.0920134
//   R_p = R_s^2 (Abeles 1950: at 45 degrees R_p = R_s^2 for any real index)
TEST(FresnelReference, PolarisedAt45DegreesAbelesIdentity) {
  const double c = std::sqrt(0.5);
  const double rs = (137.0 - 36.0 * std::sqrt(14.0)) / 25.0;
  const Polarized r = fresnel_dielectric_sp(c, 1.5);
  EXPECT_NEAR(r.s, rs, kRoundoff);
  EXPECT_NEAR(r.p, rs * rs, kRoundoff);
  for (double eta : {1.333, 2.417, 4.0}) {  // Abeles' identity, other indices
    const Polarized q = fresnel_dielectric_sp(c, eta);
    EXPECT_NEAR(q.p, q.s * q.s, kRoundoff) << eta;
  }
}

// Exactly 1 just past the critical angle (the identity body checks exactness on a grid and
// continuity at the angle; a float cosine cannot come this close to it).
TEST(FresnelReference, JustPastTheCriticalAngleIsExactlyOne) {
  const double eta = 1.0 / 1.5;
  const double cos_critical = std::sqrt((1.0 - eta) * (1.0 + eta));
  EXPECT_EQ(fresnel_dielectric(cos_critical - 1e-9, eta), 1.0);
  EXPECT_LT(fresnel_dielectric(cos_critical + 1e-9, eta), 1.0);
}

TEST(FresnelReference, ExtremeConductorsPolarisedStayFiniteAndBounded) {
  for (const auto& [n, k] : std::vector<std::pair<double, double>>{
           {10.0, 100.0}, {0.01, 100.0}, {10.0, 0.0}, {10.0, 1e-6}, {0.01, 0.01}, {1.0, 1e-12}})
    for (double c : cos_grid(4097)) {
      const Polarized r = fresnel_conductor_sp(c, n, k);
      ASSERT_TRUE(std::isfinite(r.s) && std::isfinite(r.p)) << n << " + " << k << "i at " << c;
      ASSERT_GE(r.s, 0.0);
      ASSERT_GE(r.p, 0.0);
      ASSERT_LE(r.s, 1.0) << n << " + " << k << "i at " << c;
      ASSERT_LE(r.p, 1.0) << n << " + " << k << "i at " << c;
    }
}

TEST(FresnelReference, RgbOverloadsAreChannelByChannel) {
  const Rgb f = fresnel_schlick(0.1, Rgb{0.85, 0.55, 0.25});
  EXPECT_EQ(f.g, fresnel_schlick(0.1, 0.55));
  const Rgb g = fresnel_f82_tint(kF82Cos, Rgb{0.9, 0.6, 0.3}, Rgb{0.9, 0.8, 0.7});
  EXPECT_NEAR(g.g, 0.8 * fresnel_schlick(kF82Cos, 0.6), kRoundoff);
  const Rgb m = schlick_metallic_f0(Rgb{0.9, 0.6, 0.3}, 0.5);  // (0.04 + base) / 2
  EXPECT_NEAR(m.r, 0.47, kRoundoff);
  EXPECT_NEAR(m.b, 0.17, kRoundoff);
}

TEST(FresnelReference, FSchlickEndsAndMidpoint) {
  EXPECT_EQ(F_Schlick(0.04, 1.0, 1.0), 0.04);
  EXPECT_EQ(F_Schlick(0.04, 1.0, 0.0), 1.0);
  EXPECT_NEAR(F_Schlick(0.04, 1.0, 0.5), 0.04 + 0.96 / 32.0, test::kRounding);
  EXPECT_NEAR(F_Schlick(0.5, 0.25, 0.5), 0.5 - 0.25 / 32.0, test::kRounding);
}

// The fitted tint makes F82-tint exact at its pin, for any conductor (the preset metals' fits are
// bounded in tests/host/test_material_presets.cpp).
TEST(FresnelReference, FittedF82ReproducesTheConductorAtItsPin) {
  for (const auto& [n, k] : std::vector<std::pair<double, double>>{
           {0.188, 3.403}, {3.145, 3.312}, {1.43, 7.508}, {2.5, 0.5}, {10.0, 100.0}}) {
    const double f0 = schlick_f0_from_conductor(n, k);
    EXPECT_NEAR(fresnel_f82_tint(kF82Cos, f0, fit_f82_tint(n, k)), fresnel_conductor(kF82Cos, n, k), kRoundoff)
        << n << " + " << k << "i";
  }
}

TEST(FresnelReference, FitErrorMeasuresMaxAndMean) {
  const auto exact = [](double c) { return fresnel_dielectric(c, 1.5); };
  const FresnelFitError zero = fresnel_fit_error(exact, exact);
  EXPECT_EQ(zero.max_abs, 0.0);
  EXPECT_EQ(zero.mean_abs, 0.0);
  // An error of 0.01 cos: max 0.01 at cos = 1, mean 0.01 * mean(grid) = 0.005.
  const FresnelFitError ramp = fresnel_fit_error([&](double c) { return exact(c) + 0.01 * c; }, exact);
  EXPECT_NEAR(ramp.max_abs, 0.01, kRoundoff);
  EXPECT_NEAR(ramp.mean_abs, 0.005, kRoundoff);
  EXPECT_EQ(ramp.cos_at_max, 1.0);
  EXPECT_THROW(fresnel_fit_error(exact, exact, 1), std::invalid_argument);
}

}  // namespace
}  // namespace brdfbake
