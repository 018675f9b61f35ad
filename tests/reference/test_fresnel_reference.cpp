// Identities and hand-computed values of the scalar Fresnel reference, and checks of the preset data.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "brdfbake/reference/fresnel.hpp"
#include "brdfbake/reference/materials.hpp"

namespace brdfbake {
namespace {

using namespace reference;

// Named tolerances, each with the reason for its size.
// Two routes to the same closed form in double (different operation order, csqrt): a few ulps of
// values <= 1, ulp 2.2e-16.
constexpr double kRoundoff = 1e-15;
// Published spot values are quoted to 5 decimals.
constexpr double kFiveDecimals = 5e-6;
// F has a square-root branch point at the critical angle: a step of 1e-9 in cos moves it by
// O(sqrt(1e-9)), 3.4e-4 for eta = 1/1.5 (continuous, but not Lipschitz). A jump would be O(1).
constexpr double kCriticalAngleStep = 1e-3;
// Water's dispersion: n runs 1.332-1.339 from 630 to 465 nm, F0 0.0203-0.0210 around 0.0204 (n_D).
constexpr double kWaterF0Spread = 7e-4;
// Hard-coded F0 tables (RTR4 etc.) come from other measurements than our three-wavelength samples;
// the widest gap is titanium blue, 0.549 (Johnson & Christy 1974, 465 nm) against RTR4's 0.449.
// A swapped n/k or a typo moves F0 by far more.
constexpr double kCommonF0Gap = 0.11;
// F82-tint fitted (F0 and tint) to the preset metals stays within a few hundredths of the exact
// curve (worst: chromium red, 0.023); plain Schlick misses the dark metals by up to 0.2.
constexpr double kF82FitMaxError = 0.025;

// Uniform cosine grid over [0, 1], both ends included.
std::vector<double> cos_grid(int n) {
  std::vector<double> g;
  for (int i = 0; i < n; ++i) g.push_back(static_cast<double>(i) / static_cast<double>(n - 1));
  return g;
}

struct Channel {
  std::string what;
  double n, k;
};

std::vector<Channel> conductor_channels() {
  std::vector<Channel> out;
  for (const MaterialPreset& p : material_presets()) {
    if (p.kind != MaterialKind::Conductor) continue;
    out.push_back({p.name + ".r", p.n.r, p.k.r});
    out.push_back({p.name + ".g", p.n.g, p.k.g});
    out.push_back({p.name + ".b", p.n.b, p.k.b});
  }
  return out;
}

// ---- Closed forms and identities ----------------------------------------------------------------

TEST(FresnelReference, DielectricNormalIncidenceIsSquaredRatio) {
  // n = 1.5: ((1.5 - 1) / (1.5 + 1))^2 = 0.2^2 = 0.04.
  EXPECT_NEAR(fresnel_dielectric(1.0, 1.5), 0.04, kRoundoff);
  EXPECT_NEAR(f0_from_ior(1.0, 1.5), 0.04, kRoundoff);
  EXPECT_NEAR(f0_from_ior(1.5, 1.0), 0.04, kRoundoff);
  for (double n : {1.0001, 1.333, 1.5, 2.417, 4.0}) {
    const double r = (n - 1.0) / (n + 1.0);
    EXPECT_NEAR(fresnel_dielectric(1.0, n), r * r, kRoundoff) << n;
    // Reciprocity at normal incidence: from inside (eta = 1/n) reflects the same.
    EXPECT_NEAR(fresnel_dielectric(1.0, 1.0 / n), r * r, kRoundoff) << n;
  }
}

TEST(FresnelReference, ConductorNormalIncidenceClosedForm) {
  for (const auto& [n, k] : std::vector<std::pair<double, double>>{
           {0.188, 3.403}, {0.057, 4.254}, {2.892, 3.065}, {1.5, 0.0}, {10.0, 100.0}, {0.01, 0.01}}) {
    const double expected = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
    EXPECT_NEAR(fresnel_conductor(1.0, n, k), expected, kRoundoff) << n << " + " << k << "i";
    EXPECT_NEAR(schlick_f0_from_conductor(n, k), expected, kRoundoff) << n << " + " << k << "i";
  }
}

TEST(FresnelReference, GrazingIsOneForEveryModel) {
  for (double eta : {1.0001, 1.333, 1.5, 2.417, 1.0 / 1.5})
    EXPECT_NEAR(fresnel_dielectric(0.0, eta), 1.0, kRoundoff) << eta;
  for (const auto& [n, k] : std::vector<std::pair<double, double>>{
           {0.188, 3.403}, {1.5, 0.0}, {10.0, 100.0}, {0.01, 0.01}, {2.9, 3.1}})
    EXPECT_NEAR(fresnel_conductor(0.0, n, k), 1.0, kRoundoff) << n << " + " << k << "i";
  for (double f0 : {0.0, 0.04, 0.5, 0.95}) {
    EXPECT_NEAR(fresnel_schlick(0.0, f0), 1.0, kRoundoff) << f0;
    for (double tint : {0.0, 0.5, 0.8, 1.0})
      EXPECT_NEAR(fresnel_f82_tint(0.0, f0, tint), 1.0, kRoundoff) << f0 << " " << tint;
  }
  EXPECT_NEAR(fresnel_empirical(0.0, 0.0, 1.0, 5.0), 1.0, kRoundoff);
}

TEST(FresnelReference, ConductorWithZeroExtinctionIsDielectric) {
  for (double eta : {1.0001, 1.333, 1.5, 2.417, 4.0})
    for (double c : cos_grid(1025))
      ASSERT_NEAR(fresnel_conductor(c, eta, 0.0), fresnel_dielectric(c, eta), kRoundoff)
          << "eta " << eta << " cos " << c;
}

TEST(FresnelReference, IndexOneReflectsNothing) {
  for (double c : cos_grid(257)) {
    EXPECT_EQ(fresnel_dielectric(c, 1.0), 0.0) << c;
    EXPECT_EQ(fresnel_conductor(c, 1.0, 0.0), 0.0) << c;
  }
  EXPECT_EQ(f0_from_ior(1.5, 1.5), 0.0);
}

TEST(FresnelReference, InternalReflectionIsTotalPastCriticalAngleAndContinuous) {
  const double eta = 1.0 / 1.5;                                 // glass to air
  const double cos_critical = std::sqrt((1.0 - eta) * (1.0 + eta));  // sin = eta
  for (double c : cos_grid(1025)) {
    if (c < cos_critical) {
      EXPECT_EQ(fresnel_dielectric(c, eta), 1.0) << c;
      EXPECT_NEAR(fresnel_conductor(c, eta, 0.0), 1.0, kRoundoff) << c;  // falls out, w imaginary
    } else {
      EXPECT_LE(fresnel_dielectric(c, eta), 1.0) << c;
    }
  }
  EXPECT_EQ(fresnel_dielectric(cos_critical - 1e-9, eta), 1.0);
  EXPECT_NEAR(fresnel_dielectric(cos_critical + 1e-9, eta), 1.0, kCriticalAngleStep);
  EXPECT_NEAR(fresnel_dielectric(cos_critical, eta), 1.0, kCriticalAngleStep);
}

// Hand computation, n = 1.5 at 45 degrees: cos_i = sin_i = 1/sqrt(2); sin_t = sin_i / 1.5, so
// cos_t = sqrt(1 - 2/9) = sqrt(7)/3 and n cos_t = sqrt(7)/2, cos_i = sqrt(2)/2.
//   r_s = (cos_i - n cos_t) / (cos_i + n cos_t) = (sqrt2 - sqrt7) / (sqrt2 + sqrt7)
//   R_s = (sqrt7 - sqrt2)^4 / (7 - 2)^2 = (9 - 2 sqrt14)^2 / 25 = (137 - 36 sqrt14) / 25 = 0.0920134
//   r_p = (n cos_i - cos_t) / (n cos_i + cos_t) = (1.0606602 - 0.8819171) / 1.9425773 = 0.0920134
//   R_p = 0.0084665 = R_s^2 (Abeles 1950: at 45 degrees R_p = R_s^2 for any real index)
//   F = (R_s + R_p) / 2 = 0.0502399
TEST(FresnelReference, DielectricAt45DegreesByHand) {
  const double c = std::sqrt(0.5);
  const double rs = (137.0 - 36.0 * std::sqrt(14.0)) / 25.0;
  const Polarized r = fresnel_dielectric_sp(c, 1.5);
  EXPECT_NEAR(r.s, rs, kRoundoff);
  EXPECT_NEAR(r.p, rs * rs, kRoundoff);
  EXPECT_NEAR(fresnel_dielectric(c, 1.5), 0.0502399, kFiveDecimals);
  for (double eta : {1.333, 2.417, 4.0}) {  // Abeles' identity, other indices
    const Polarized q = fresnel_dielectric_sp(c, eta);
    EXPECT_NEAR(q.p, q.s * q.s, kRoundoff) << eta;
  }
}

TEST(FresnelReference, SchlickSpotValues) {
  // (1 - 0.1)^5 = 0.59049; F = F0 + (1 - F0) 0.59049.
  EXPECT_NEAR(fresnel_schlick(0.1, 0.04), 0.60687, kFiveDecimals);
  const Rgb f = fresnel_schlick(0.1, Rgb{0.85, 0.55, 0.25});
  EXPECT_NEAR(f.r, 0.93857, kFiveDecimals);
  EXPECT_NEAR(f.g, 0.81572, kFiveDecimals);
  EXPECT_NEAR(f.b, 0.69287, kFiveDecimals);
  // F90 other than 1: 0.04 + (0.5 - 0.04) 0.59049 = 0.31163.
  EXPECT_NEAR(fresnel_schlick(0.1, 0.04, 0.5), 0.31163, kFiveDecimals);
}

TEST(FresnelReference, MetallicWorkflowF0) {
  const Rgb base{0.9, 0.6, 0.3};
  const Rgb d = schlick_metallic_f0(base, 0.0);
  EXPECT_NEAR(d.r, 0.04, kRoundoff);
  EXPECT_NEAR(d.b, 0.04, kRoundoff);
  const Rgb m = schlick_metallic_f0(base, 1.0);
  EXPECT_NEAR(m.r, 0.9, kRoundoff);
  EXPECT_NEAR(m.g, 0.6, kRoundoff);
  const Rgb h = schlick_metallic_f0(base, 0.5);  // (0.04 + 0.9) / 2 = 0.47, ...
  EXPECT_NEAR(h.r, 0.47, kRoundoff);
  EXPECT_NEAR(h.g, 0.32, kRoundoff);
  EXPECT_NEAR(h.b, 0.17, kRoundoff);
}

TEST(FresnelReference, CosinesJustOutsideTheRangeAreClamped) {
  const double below = -1e-7, above = 1.0 + 1e-7;
  const std::vector<std::pair<std::string, std::function<double(double)>>> models = {
      {"schlick", [](double c) { return fresnel_schlick(c, 0.04); }},
      {"dielectric", [](double c) { return fresnel_dielectric(c, 1.5); }},
      {"dielectric internal", [](double c) { return fresnel_dielectric(c, 1.0 / 1.5); }},
      {"conductor", [](double c) { return fresnel_conductor(c, 0.188, 3.403); }},
      {"f82", [](double c) { return fresnel_f82_tint(c, 0.56, 0.8); }},
      {"empirical", [](double c) { return fresnel_empirical(c, 0.1, 0.9, 5.0); }},
  };
  for (const auto& [name, f] : models) {
    EXPECT_TRUE(std::isfinite(f(below))) << name;
    EXPECT_TRUE(std::isfinite(f(above))) << name;
    EXPECT_EQ(f(below), f(0.0)) << name;
    EXPECT_EQ(f(above), f(1.0)) << name;
  }
}

TEST(FresnelReference, ExtremeConductorsStayFiniteAndBounded) {
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

// ---- F82-tint and the fits ------------------------------------------------------------------------

TEST(FresnelReference, F82WithWhiteTintIsSchlick) {
  for (double f0 : {0.04, 0.56, 0.95})
    for (double c : cos_grid(1025))
      ASSERT_DOUBLE_EQ(fresnel_f82_tint(c, f0, 1.0), fresnel_schlick(c, f0)) << f0 << " " << c;
}

TEST(FresnelReference, F82AtItsPinIsTintTimesSchlick) {
  for (double f0 : {0.04, 0.56, 0.95})
    for (double tint : {0.0, 0.3, 0.8, 1.0})
      EXPECT_NEAR(fresnel_f82_tint(kF82Cos, f0, tint), tint * fresnel_schlick(kF82Cos, f0),
                  kRoundoff)
          << f0 << " " << tint;
  const Rgb f = fresnel_f82_tint(kF82Cos, Rgb{0.9, 0.6, 0.3}, Rgb{0.9, 0.8, 0.7});
  EXPECT_NEAR(f.g, 0.8 * fresnel_schlick(kF82Cos, 0.6), kRoundoff);
}

TEST(FresnelReference, FittedF82ReproducesTheConductorAtItsPin) {
  for (const Channel& ch : conductor_channels()) {
    const double f0 = schlick_f0_from_conductor(ch.n, ch.k);
    const double tint = fit_f82_tint(ch.n, ch.k);
    EXPECT_NEAR(fresnel_f82_tint(kF82Cos, f0, tint), fresnel_conductor(kF82Cos, ch.n, ch.k),
                kRoundoff)
        << ch.what;
  }
}

TEST(FresnelReference, FittedF82TracksTheExactConductor) {
  for (const Channel& ch : conductor_channels()) {
    const double f0 = schlick_f0_from_conductor(ch.n, ch.k);
    const double tint = fit_f82_tint(ch.n, ch.k);
    const FresnelFitError e =
        fresnel_fit_error([&](double c) { return fresnel_f82_tint(c, f0, tint); },
                          [&](double c) { return fresnel_conductor(c, ch.n, ch.k); });
    EXPECT_LE(e.max_abs, kF82FitMaxError) << ch.what << " worst at cos " << e.cos_at_max;
  }
}

TEST(FresnelReference, FitErrorMeasuresMaxAndMean) {
  const auto exact = [](double c) { return fresnel_dielectric(c, 1.5); };
  const FresnelFitError zero = fresnel_fit_error(exact, exact);
  EXPECT_EQ(zero.max_abs, 0.0);
  EXPECT_EQ(zero.mean_abs, 0.0);
  // An error of 0.01 cos: max 0.01 at cos = 1, mean 0.01 * mean(grid) = 0.005.
  const FresnelFitError ramp =
      fresnel_fit_error([&](double c) { return exact(c) + 0.01 * c; }, exact);
  EXPECT_NEAR(ramp.max_abs, 0.01, kRoundoff);
  EXPECT_NEAR(ramp.mean_abs, 0.005, kRoundoff);
  EXPECT_EQ(ramp.cos_at_max, 1.0);
  EXPECT_THROW(fresnel_fit_error(exact, exact, 1), std::invalid_argument);
}

TEST(FresnelReference, EmpiricalCgTutorialModel) {
  // bias + scale (1 - cos)^power: 0.1 + 0.9 * 0.59049 = 0.631441.
  EXPECT_NEAR(fresnel_empirical(0.1, 0.1, 0.9, 5.0), 0.631441, kFiveDecimals);
  // bias = F0, scale = 1 - F0, power = 5 is Schlick.
  for (double c : cos_grid(65))
    EXPECT_NEAR(fresnel_empirical(c, 0.04, 0.96, 5.0), fresnel_schlick(c, 0.04), kRoundoff) << c;
  EXPECT_EQ(fresnel_empirical(0.0, 0.5, 1.0, 1.0), 1.0);   // 1.5 clamped
  EXPECT_EQ(fresnel_empirical(1.0, -0.5, 1.0, 1.0), 0.0);  // -0.5 clamped
}

// ---- Presets ------------------------------------------------------------------------------------

TEST(MaterialPresets, TableIsWellFormed) {
  std::set<std::string> names;
  int conductors = 0, dielectrics = 0;
  for (const MaterialPreset& p : material_presets()) {
    EXPECT_TRUE(names.insert(p.name).second) << "duplicate " << p.name;
    EXPECT_EQ(find_material(p.name), &p);
    EXPECT_FALSE(p.nk_source.empty()) << p.name;
    EXPECT_EQ(p.common_f0.has_value(), !p.common_f0_source.empty()) << p.name;
    for (double n : {p.n.r, p.n.g, p.n.b}) EXPECT_GT(n, 0.0) << p.name;
    if (p.kind == MaterialKind::Conductor) {
      ++conductors;
      for (double k : {p.k.r, p.k.g, p.k.b}) EXPECT_GT(k, 1.0) << p.name;
    } else {
      ++dielectrics;
      EXPECT_EQ(p.k.r + p.k.g + p.k.b, 0.0) << p.name;
      for (double n : {p.n.r, p.n.g, p.n.b}) EXPECT_GT(n, 1.0) << p.name;
      EXPECT_GE(p.n.b, p.n.r) << p.name << ": normal dispersion, n falls with wavelength";
    }
  }
  for (const char* required : {"gold", "silver", "copper", "aluminium", "iron", "chromium",
                               "titanium", "nickel", "platinum", "water", "glass", "diamond",
                               "skin", "ice", "pmma", "polycarbonate"})
    EXPECT_NE(find_material(required), nullptr) << required;
  EXPECT_EQ(find_material("unobtainium"), nullptr);
  EXPECT_GE(conductors, 9);
  EXPECT_GE(dielectrics, 8);
}

TEST(MaterialPresets, ExactF0IsAReflectanceAndMatchesTheExactModel) {
  for (const MaterialPreset& p : material_presets()) {
    const Rgb f = exact_f0(p);
    const Rgb g = fresnel_conductor(1.0, p.n, p.k);
    for (const auto& [a, b] : {std::pair{f.r, g.r}, std::pair{f.g, g.g}, std::pair{f.b, g.b}}) {
      EXPECT_GE(a, 0.0) << p.name;
      EXPECT_LE(a, 1.0) << p.name;
      EXPECT_NEAR(a, b, kRoundoff) << p.name;
    }
  }
}

TEST(MaterialPresets, GoldIsYellowAndWaterIsTwoPercent) {
  const Rgb gold = exact_f0(*find_material("gold"));
  EXPECT_GT(gold.r, gold.b);
  EXPECT_GT(gold.r, 0.9);  // Johnson & Christy 1972 at 630 nm: 0.942
  EXPECT_LT(gold.b, 0.45);  // at 465 nm, above the interband edge: 0.404
  const Rgb water = exact_f0(*find_material("water"));
  for (double f : {water.r, water.g, water.b}) EXPECT_NEAR(f, 0.0204, kWaterF0Spread);
  // At the sodium D line, n = 1.333: ((0.333) / (2.333))^2 = 0.020373.
  EXPECT_NEAR(f0_from_ior(1.0, 1.333), 0.020373, kFiveDecimals);
}

TEST(MaterialPresets, HardCodedF0AgreesWithTheMeasuredIndices) {
  for (const MaterialPreset& p : material_presets()) {
    if (!p.common_f0) continue;
    const Rgb f = exact_f0(p);
    EXPECT_NEAR(f.r, p.common_f0->r, kCommonF0Gap) << p.name;
    EXPECT_NEAR(f.g, p.common_f0->g, kCommonF0Gap) << p.name;
    EXPECT_NEAR(f.b, p.common_f0->b, kCommonF0Gap) << p.name;
  }
}

}  // namespace
}  // namespace brdfbake
