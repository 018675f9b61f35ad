// One body of Fresnel identities, run on every backend: closed forms (normal incidence, Schlick's and
// the Cg tutorial's spot values, 45 degrees by hand), limits (grazing, index 1, total internal
// reflection), relations between models (a conductor with k = 0 is the dielectric, F82 with tint 1
// is Schlick, F82 at its pin is tint x Schlick), clamping and boundedness.
//
// tests/reference/test_fresnel_reference.cpp instantiates it on the scalar double reference
// (host/reference/src/fresnel.cpp), tests/device/test_fresnel.cpp on the OpenCL kernels
// (kernels/fresnel.cl) in fp32 and fp64: the same assertions, with each backend's tolerances
// (tests/support/tolerances.hpp). Each executable defines make_fresnel_backend for its backends.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "identities/backend.hpp"
#include "support/tolerances.hpp"

namespace brdfbake::test {

// A Fresnel model with its parameters, one channel (every parameter grey), in the order of the
// kernels (kernels/fresnel.cl) and of FresnelSpec:
//   Schlick {f0, f90}, SchlickMetallic {base_color, metallic, dielectric_f0}, SchlickIor and
//   Dielectric {ior_outside, ior} (eta = ior / ior_outside), Conductor {n, k} (seen from air),
//   F82Tint {f0, tint}, Empirical {bias, scale, power}.
struct FresnelCurve {
  enum class Kind { Schlick, SchlickMetallic, SchlickIor, Dielectric, Conductor, F82Tint, Empirical };
  Kind kind;
  std::vector<double> p;
  std::string what;
};

inline std::string fmt_params(const std::vector<double>& p) {
  std::string s;
  for (double v : p) s += (s.empty() ? "" : ", ") + std::to_string(v);
  return s;
}
inline FresnelCurve schlick(double f0, double f90 = 1.0) {
  return {FresnelCurve::Kind::Schlick, {f0, f90}, "schlick(" + fmt_params({f0, f90}) + ")"};
}
inline FresnelCurve schlick_metallic(double base, double metallic, double dielectric_f0 = 0.04) {
  return {FresnelCurve::Kind::SchlickMetallic,
          {base, metallic, dielectric_f0},
          "schlick-metallic(" + fmt_params({base, metallic, dielectric_f0}) + ")"};
}
inline FresnelCurve schlick_ior(double ior, double outside = 1.0) {
  return {FresnelCurve::Kind::SchlickIor, {outside, ior}, "schlick-ior(" + fmt_params({outside, ior}) + ")"};
}
inline FresnelCurve dielectric(double ior, double outside = 1.0) {
  return {FresnelCurve::Kind::Dielectric, {outside, ior}, "dielectric(" + fmt_params({outside, ior}) + ")"};
}
inline FresnelCurve conductor(double n, double k) {
  return {FresnelCurve::Kind::Conductor, {n, k}, "conductor(" + fmt_params({n, k}) + ")"};
}
inline FresnelCurve f82_tint(double f0, double tint) {
  return {FresnelCurve::Kind::F82Tint, {f0, tint}, "f82-tint(" + fmt_params({f0, tint}) + ")"};
}
inline FresnelCurve empirical(double bias, double scale, double power) {
  return {FresnelCurve::Kind::Empirical, {bias, scale, power}, "empirical(" + fmt_params({bias, scale, power}) + ")"};
}

// What a backend provides: F of a curve at each cosine.
class FresnelBackend {
 public:
  virtual ~FresnelBackend() = default;
  virtual std::vector<double> eval(const FresnelCurve& curve, const std::vector<double>& cosines) = 0;
};

// Defined by each test executable for the backends it instantiates: sets `out`, or skips (a device
// without fp64, no device where that is allowed) or fails (no device) the test.
void make_fresnel_backend(Backend backend, std::unique_ptr<FresnelBackend>& out);

// The tolerances of a backend, each from tests/support/tolerances.hpp.
struct FresnelTolerances {
  double value;           // closed forms and identities of values <= 1
  double grazing_one;     // cos_theta = 0 gives 1
  double critical_angle;  // identities evaluated next to a critical angle (internal reflection)
  double spot;            // published spot values, quoted to 5 decimals
};
inline FresnelTolerances fresnel_tolerances(Backend b) {
  switch (b) {
    case Backend::Reference:
      return {kFresnelReferenceRounding, kFresnelReferenceRounding, kFresnelReferenceRounding, kFresnelSpotValue};
    case Backend::Fp32:
      return {kFresnelFp32, kFresnelGrazingOne, kFresnelCriticalAngleFp32, kFresnelSpotValue};
    case Backend::Fp64:
      return {kFresnelFp64, kFresnelGrazingOne, kFresnelFp64, kFresnelSpotValue};
    // the reference in double, stored as float32 like an fp64 table
    case Backend::ReferenceBackend:
      return {kFresnelFp64, kFresnelGrazingOne, kFresnelFp64, kFresnelSpotValue};
  }
  return {};
}

class FresnelIdentities : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override { make_fresnel_backend(GetParam(), backend_); }
  std::vector<double> at(const FresnelCurve& c, const std::vector<double>& cosines) {
    return backend_->eval(c, cosines);
  }
  double at(const FresnelCurve& c, double cosine) { return at(c, std::vector<double>{cosine})[0]; }
  FresnelTolerances tol() const { return fresnel_tolerances(GetParam()); }

  std::unique_ptr<FresnelBackend> backend_;
};

// Uniform cosine grid over [0, 1], both ends included.
inline std::vector<double> endpoints_grid(int n) {
  std::vector<double> g;
  for (int i = 0; i < n; ++i) g.push_back(static_cast<double>(i) / (n - 1));
  return g;
}

// Born & Wolf 1.5.2 at normal incidence: ((n - 1) / (n + 1))^2, the same from either side
// (reciprocity), and Schlick's F0 from the index pair; 14.2 for a conductor:
// ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2).
TEST_P(FresnelIdentities, NormalIncidenceClosedForms) {
  EXPECT_NEAR(at(dielectric(1.5), 1.0), 0.04, tol().value);
  for (double n : {1.0001, 1.333, 1.5, 2.417, 4.0, 10.0}) {
    const double r = (n - 1.0) / (n + 1.0);
    EXPECT_NEAR(at(dielectric(n), 1.0), r * r, tol().value) << "dielectric n = " << n;
    EXPECT_NEAR(at(dielectric(1.0, n), 1.0), r * r, tol().value) << "from inside, n = " << n;
    EXPECT_NEAR(at(schlick_ior(n), 1.0), r * r, tol().value) << "schlick-ior n = " << n;
    EXPECT_NEAR(at(schlick_ior(1.0, n), 1.0), r * r, tol().value) << "schlick-ior from inside, n = " << n;
  }
  for (const auto& [n, k] : std::vector<std::pair<double, double>>{
           {0.188, 3.403}, {0.057, 4.254}, {2.892, 3.065}, {1.5, 0.0}, {10.0, 100.0}, {0.01, 0.01}}) {
    const double want = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
    EXPECT_NEAR(at(conductor(n, k), 1.0), want, tol().value) << n << " + " << k << "i";
  }
}

// cos_theta = 0 gives 1 for every physical model and every Schlick variant (F90 = 1).
TEST_P(FresnelIdentities, GrazingIsOneForEveryModel) {
  std::vector<FresnelCurve> curves;
  for (double n : {1.0001, 1.333, 1.5, 2.417, 10.0}) curves.push_back(dielectric(n));
  curves.push_back(dielectric(1.0, 1.5));  // internal
  for (const auto& [n, k] : std::vector<std::pair<double, double>>{
           {0.188, 3.403}, {1.5, 0.0}, {10.0, 100.0}, {0.01, 100.0}, {1.0, 1e-6}, {0.01, 0.01}, {2.9, 3.1}})
    curves.push_back(conductor(n, k));
  for (double f0 : {0.0, 0.04, 0.5, 0.95}) {
    curves.push_back(schlick(f0));
    for (double tint : {0.0, 0.5, 0.8, 1.0, 1.2}) curves.push_back(f82_tint(f0, tint));
  }
  for (double metallic : {0.0, 0.5, 1.0}) curves.push_back(schlick_metallic(0.6, metallic));
  for (double n : {1.5, 10.0}) curves.push_back(schlick_ior(n));
  curves.push_back(empirical(0.0, 1.0, 5.0));
  for (const FresnelCurve& c : curves) EXPECT_NEAR(at(c, 0.0), 1.0, tol().grazing_one) << c.what;
}

// The empirical rim term is not a reflectance: at grazing it gives clamp(bias + scale, 0, 1), so 1
// only where bias + scale >= 1 (power > 0).
TEST_P(FresnelIdentities, EmpiricalAtGrazingIsBiasPlusScaleClamped) {
  for (const auto& [b, sc] :
       std::vector<std::pair<double, double>>{{0.0, 1.0}, {0.3, 0.7}, {0.5, 1.0}, {0.2, 0.5}, {-0.1, 0.6}})
    EXPECT_NEAR(at(empirical(b, sc, 5.0), 0.0), std::clamp(b + sc, 0.0, 1.0), tol().value) << b << " + " << sc;
}

// Fernando & Kilgard 2003, eq. 7-3: bias + scale (1 - cos)^power; bias = F0, scale = 1 - F0,
// power = 5 is Schlick; the clamps are exact.
TEST_P(FresnelIdentities, EmpiricalCgTutorialModel) {
  // 0.1 + 0.9 * 0.59049 = 0.631441
  EXPECT_NEAR(at(empirical(0.1, 0.9, 5.0), 0.1), 0.631441, tol().spot);
  const std::vector<double> g = endpoints_grid(65);
  const std::vector<double> e = at(empirical(0.04, 0.96, 5.0), g), s = at(schlick(0.04), g);
  for (size_t i = 0; i < g.size(); ++i) EXPECT_NEAR(e[i], s[i], tol().value) << g[i];
  EXPECT_EQ(at(empirical(0.5, 1.0, 1.0), 0.0), 1.0);   // 1.5 clamped
  EXPECT_EQ(at(empirical(-0.5, 1.0, 1.0), 1.0), 0.0);  // -0.5 clamped
}

TEST_P(FresnelIdentities, ConductorWithZeroExtinctionIsDielectric) {
  const std::vector<double> g = endpoints_grid(1025);
  for (double eta : {1.0001, 1.333, 1.5, 2.417, 4.0, 1.0 / 1.5}) {
    const std::vector<double> a = at(conductor(eta, 0.0), g);
    const std::vector<double> b = at(eta < 1.0 ? dielectric(1.0, 1.0 / eta) : dielectric(eta), g);
    double worst = 0.0, where = 0.0;
    for (size_t i = 0; i < g.size(); ++i)
      if (std::fabs(a[i] - b[i]) > worst) {
        worst = std::fabs(a[i] - b[i]);
        where = g[i];
      }
    EXPECT_LE(worst, eta < 1.0 ? tol().critical_angle : tol().value) << "eta " << eta << " worst at cos " << where;
  }
}

// eta = 1 is no interface: nothing reflects, exactly. Schlick from an IOR pair has F0 = 0 exactly but
// still rises to F90 = 1 at grazing: "nothing reflects" is a property of the exact equations, one
// that the approximation does not keep.
TEST_P(FresnelIdentities, IndexOneReflectsNothing) {
  const std::vector<double> g = endpoints_grid(257);
  for (const FresnelCurve& c : {dielectric(1.0), dielectric(1.5, 1.5), conductor(1.0, 0.0)}) {
    const std::vector<double> f = at(c, g);
    for (size_t i = 0; i < g.size(); ++i) ASSERT_EQ(f[i], 0.0) << c.what << " at " << g[i];
  }
  for (const FresnelCurve& c : {schlick_ior(1.0), schlick_ior(1.5, 1.5)}) {
    EXPECT_EQ(at(c, 1.0), 0.0) << c.what;
    EXPECT_EQ(at(c, 0.0), 1.0) << c.what;
  }
}

// eta = 1/1.5 (glass to air): exactly 1 past the critical angle, continuous at it (F = 1 - C sqrt(d)
// at a distance d inside: a step of 1e-9 moves it by O(sqrt(1e-9)), a jump would be O(1)), and never
// above 1. The conductor with k = 0 falls into total reflection without a special case.
TEST_P(FresnelIdentities, InternalReflectionIsTotalPastTheCriticalAngle) {
  const double eta = 1.0 / 1.5;
  const double cos_critical = std::sqrt((1.0 - eta) * (1.0 + eta));  // sin = eta
  std::vector<double> past;                                          // strictly past the critical angle, in fp32 too
  for (int i = 0; i < 1024; ++i) past.push_back(cos_critical * i / 1024.0 * (1.0 - 1e-6));
  const std::vector<double> f = at(dielectric(1.0, 1.5), past), k0 = at(conductor(eta, 0.0), past);
  for (size_t i = 0; i < past.size(); ++i) {
    ASSERT_EQ(f[i], 1.0) << "cos " << past[i];
    ASSERT_NEAR(k0[i], 1.0, tol().value) << "conductor k = 0 at cos " << past[i];
  }
  for (double c : {cos_critical - 1e-9, cos_critical, cos_critical + 1e-9})
    EXPECT_NEAR(at(dielectric(1.0, 1.5), c), 1.0, kFresnelCriticalAngleStep) << c;
  for (double v : at(dielectric(1.0, 1.5), endpoints_grid(1025))) EXPECT_LE(v, 1.0);
}

// Born & Wolf by hand, n = 1.5 at 45 degrees: R_s = (137 - 36 sqrt 14) / 25 = 0.0920134,
// R_p = R_s^2 = 0.0084665 (Abeles 1950), F = (R_s + R_p) / 2 = 0.0502399.
TEST_P(FresnelIdentities, DielectricAt45DegreesByHand) {
  const double rs = (137.0 - 36.0 * std::sqrt(14.0)) / 25.0;
  EXPECT_NEAR(at(dielectric(1.5), std::sqrt(0.5)), 0.5 * (rs + rs * rs), tol().value);
  EXPECT_NEAR(at(dielectric(1.5), std::sqrt(0.5)), 0.0502399, tol().spot);
}

TEST_P(FresnelIdentities, SchlickSpotValues) {
  // (1 - 0.1)^5 = 0.59049; F = F0 + (1 - F0) 0.59049.
  EXPECT_NEAR(at(schlick(0.04), 0.1), 0.60687, tol().spot);
  EXPECT_NEAR(at(schlick(0.85), 0.1), 0.93857, tol().spot);
  EXPECT_NEAR(at(schlick(0.55), 0.1), 0.81572, tol().spot);
  EXPECT_NEAR(at(schlick(0.25), 0.1), 0.69287, tol().spot);
  // F90 other than 1: 0.04 + (0.5 - 0.04) 0.59049 = 0.31163.
  EXPECT_NEAR(at(schlick(0.04, 0.5), 0.1), 0.31163, tol().spot);
}

// Burley 2012 / glTF 2.0: F0 = mix(dielectric_f0, base_color, metallic), the value at cos = 1.
TEST_P(FresnelIdentities, MetallicWorkflowF0) {
  for (const auto& [base, half] : std::vector<std::pair<double, double>>{{0.9, 0.47}, {0.6, 0.32}, {0.3, 0.17}}) {
    EXPECT_NEAR(at(schlick_metallic(base, 0.0), 1.0), 0.04, tol().value) << base;
    EXPECT_NEAR(at(schlick_metallic(base, 1.0), 1.0), base, tol().value) << base;
    EXPECT_NEAR(at(schlick_metallic(base, 0.5), 1.0), half, tol().value) << base;  // (0.04 + base) / 2
  }
  EXPECT_NEAR(at(schlick_metallic(0.9, 0.0, 0.02), 1.0), 0.02, tol().value);
}

// Cosines a hair outside [0, 1] (rounding upstream) are clamped: the values at 0 and 1, not NaN.
TEST_P(FresnelIdentities, CosinesJustOutsideTheRangeAreClamped) {
  const std::vector<FresnelCurve> curves = {schlick(0.04),
                                            schlick(0.85, 0.9),
                                            schlick_metallic(0.9, 0.5),
                                            schlick_ior(1.5),
                                            dielectric(1.5),
                                            dielectric(1.0, 1.5),
                                            dielectric(10.0),
                                            conductor(0.188, 3.403),
                                            conductor(10.0, 100.0),
                                            conductor(0.01, 0.01),
                                            f82_tint(0.56, 0.8),
                                            f82_tint(0.0, 0.0),
                                            empirical(0.1, 0.9, 5.0),
                                            empirical(0.3, 0.5, 0.0)};
  for (const FresnelCurve& c : curves) {
    const std::vector<double> f = at(c, {-1e-7, 0.0, 1.0, 1.0 + 1e-7});
    EXPECT_TRUE(std::isfinite(f[0]) && std::isfinite(f[3])) << c.what;
    EXPECT_EQ(f[0], f[1]) << c.what;
    EXPECT_EQ(f[3], f[2]) << c.what;
  }
}

TEST_P(FresnelIdentities, ExtremeIndicesStayFiniteAndBounded) {
  const std::vector<double> g = endpoints_grid(4097);
  const std::vector<FresnelCurve> curves = {conductor(10.0, 100.0), conductor(0.01, 100.0), conductor(10.0, 0.0),
                                            conductor(10.0, 1e-6),  conductor(0.01, 0.01),  conductor(1.0, 1e-12),
                                            conductor(0.5, 1.0),    dielectric(10.0),       dielectric(1.0, 10.0),
                                            schlick_ior(10.0)};
  for (const FresnelCurve& c : curves)
    for (double v : at(c, g)) {
      ASSERT_TRUE(std::isfinite(v)) << c.what;
      ASSERT_GE(v, 0.0) << c.what;
      ASSERT_LE(v, 1.0) << c.what;
    }
}

// Hoffman 2023: the correction a mu (1 - mu)^6 vanishes at tint 1, and at the pin cos = 1/7
// F82 = tint * Schlick by construction.
TEST_P(FresnelIdentities, F82TintAgainstSchlick) {
  const std::vector<double> g = endpoints_grid(1025);
  for (double f0 : {0.04, 0.56, 0.95}) {
    const std::vector<double> f = at(f82_tint(f0, 1.0), g), s = at(schlick(f0), g);
    for (size_t i = 0; i < g.size(); ++i) ASSERT_NEAR(f[i], s[i], tol().value) << f0 << " " << g[i];
    for (double tint : {0.0, 0.3, 0.8, 1.0})
      EXPECT_NEAR(at(f82_tint(f0, tint), 1.0 / 7.0), tint * at(schlick(f0), 1.0 / 7.0), tol().value)
          << f0 << " " << tint;
  }
}

}  // namespace brdfbake::test
