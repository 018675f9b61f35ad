// Scalar double-precision Fresnel reflectance. See fresnel.hpp for the conventions.
#include "brdfbake/reference/fresnel.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <string>

namespace brdfbake::reference {
namespace {

// Cosines a hair outside [0, 1] come from rounding upstream (a normalised dot product); clamping
// them keeps every sqrt and pow below in its real domain (docs/CONVENTIONS.md).
double clamp_cos(double cos_theta) { return std::clamp(cos_theta, 0.0, 1.0); }

double pow5(double x) {
  const double x2 = x * x;
  return x2 * x2 * x;
}

double pow6(double x) {
  const double x3 = x * x * x;
  return x3 * x3;
}

Rgb map3(const Rgb& a, const Rgb& b, double (*f)(double, double)) { return {f(a.r, b.r), f(a.g, b.g), f(a.b, b.b)}; }

}  // namespace

// ---- Schlick and its parameterisations -------------------------------------------------------

// Schlick 1994: F = F0 + (F90 - F0) (1 - cos)^5.
double fresnel_schlick(double cos_theta, double f0, double f90) {
  return f0 + (f90 - f0) * pow5(1.0 - clamp_cos(cos_theta));
}

double F_Schlick(double f0, double f90, double v_dot_h) { return fresnel_schlick(v_dot_h, f0, f90); }

Rgb fresnel_schlick(double cos_theta, const Rgb& f0, const Rgb& f90) {
  return {fresnel_schlick(cos_theta, f0.r, f90.r), fresnel_schlick(cos_theta, f0.g, f90.g),
          fresnel_schlick(cos_theta, f0.b, f90.b)};
}

// Born & Wolf 1.5.2 at normal incidence, where s and p coincide: r = (n1 - n2) / (n1 + n2).
double f0_from_ior(double n1, double n2) {
  const double r = (n1 - n2) / (n1 + n2);
  return r * r;
}

// Burley 2012 / glTF 2.0 appendix B: metals take F0 from the base colour, dielectrics a constant.
Rgb schlick_metallic_f0(const Rgb& base_color, double metallic, double dielectric_f0) {
  const auto mix = [&](double c) { return dielectric_f0 + (c - dielectric_f0) * metallic; };
  return {mix(base_color.r), mix(base_color.g), mix(base_color.b)};
}

// ---- Exact Fresnel equations -----------------------------------------------------------------
//
// Derivation shared by both interfaces. With c = cos(theta_i) and Snell's law
// n_i sin(theta_i) = n_t sin(theta_t), Born & Wolf's amplitude ratios for relative index eta are
//     r_s = (c - eta cos_t) / (c + eta cos_t),      r_p = (eta c - cos_t) / (eta c + cos_t).
// Substitute w = eta cos_t = sqrt(eta^2 - sin^2 theta_i) = sqrt(eta^2 - 1 + c^2) and multiply r_p
// through by eta:
//     r_s = (c - w) / (c + w),                      r_p = (eta^2 c - w) / (eta^2 c + w).
// This form never divides by eta, keeps one square root, and computes w^2 as (eta-1)(eta+1) + c^2
// (no 1 - c^2 cancellation near normal incidence; exact for eta = 1). The unpolarised reflectance
// is the mean of the intensities |r_s|^2 and |r_p|^2.

// Born & Wolf 1.5.2, real eta = n_t / n_i > 0.
Polarized fresnel_dielectric_sp(double cos_theta_i, double eta) {
  const double c = clamp_cos(cos_theta_i);
  if (eta == 1.0) return {0.0, 0.0};  // no interface; also avoids 0/0 at grazing (w = c = 0)
  const double w2 = (eta - 1.0) * (eta + 1.0) + c * c;
  // Total internal reflection: sin(theta_t) = sin(theta_i) / eta >= 1. At w2 = 0 exactly (the
  // critical angle) both formulas above give r = 1 too, so F is continuous there; approaching it
  // from inside, 1 - F falls like sqrt(w2) (a square-root branch point, not a jump).
  if (w2 <= 0.0) return {1.0, 1.0};
  const double w = std::sqrt(w2);
  const double rs = (c - w) / (c + w);  // c + w > 0 since w > 0
  const double eta2c = eta * eta * c;
  const double rp = (eta2c - w) / (eta2c + w);
  return {rs * rs, rp * rp};
}

double fresnel_dielectric(double cos_theta_i, double eta) {
  const Polarized r = fresnel_dielectric_sp(cos_theta_i, eta);
  return 0.5 * (r.s + r.p);
}

// Born & Wolf 14.2: the same equations with the complex index eta + i k.
//
// Why std::complex rather than the textbook real closed form (a^2 + b^2 =
// sqrt((n^2 - k^2 - sin^2)^2 + 4 n^2 k^2), a = sqrt((a^2 + b^2 + n^2 - k^2 - sin^2) / 2), ...):
// those a, b are exactly Re w and Im w, so both are the same computation; the complex form keeps
// the derivation above one line long and std::sqrt(complex) (C99 csqrt) is accurate without
// overflow. Branch: Im(eta^2) = 2 n k >= 0, so w^2 lies in the closed upper half-plane and the
// principal root has Re w >= 0, Im w >= 0, the transmitted wave that decays into the metal. For
// k = 0 and eta < 1 past the critical angle, w^2 < 0 and w = i|w|: |r_s| = |r_p| = 1, total internal
// reflection falls out without a special case.
// Intensities are taken as |num|^2 / |den|^2 (two real squared moduli), never a complex division:
// at grazing (c = 0) num = -den exactly, so F = 1 exactly, and |c - w| <= |c + w| survives rounding.
Polarized fresnel_conductor_sp(double cos_theta_i, double eta, double k) {
  const double c = clamp_cos(cos_theta_i);
  if (k == 0.0 && eta == 1.0) return {0.0, 0.0};  // no interface, as fresnel_dielectric_sp
  const std::complex<double> eta2(eta * eta - k * k, 2.0 * eta * k);
  const std::complex<double> w2((eta - 1.0) * (eta + 1.0) - k * k + c * c, eta2.imag());
  const std::complex<double> w = std::sqrt(w2);
  const double rs = std::norm(c - w) / std::norm(c + w);
  const std::complex<double> eta2c = eta2 * c;
  // |r_p| <= 1 holds exactly for any passive medium (Im eta^2 >= 0); the clamp only absorbs a
  // last-bit rounding excess. 0/0 is impossible: eta2c + w = 0 needs c = 0 and w = 0, i.e. k = 0
  // and eta = 1, returned above.
  const double rp = std::min(1.0, std::norm(eta2c - w) / std::norm(eta2c + w));
  return {rs, rp};
}

double fresnel_conductor(double cos_theta_i, double eta, double k) {
  const Polarized r = fresnel_conductor_sp(cos_theta_i, eta, k);
  return 0.5 * (r.s + r.p);
}

Rgb fresnel_conductor(double cos_theta_i, const Rgb& eta, const Rgb& k) {
  return {fresnel_conductor(cos_theta_i, eta.r, k.r), fresnel_conductor(cos_theta_i, eta.g, k.g),
          fresnel_conductor(cos_theta_i, eta.b, k.b)};
}

// ---- Artist-facing approximations --------------------------------------------------------------
//
// F82-tint (Hoffman 2023; OpenPBR 1.x "Metal"; Kutz et al. 2021, Adobe Standard Material).
// Model, with mu = cos(theta), Schlick's S(mu) = F0 + (1 - F0)(1 - mu)^5 and the pinned cosine
// mu_bar = 1/7:
//     F82(mu) = S(mu) - a mu (1 - mu)^6.
// The correction lobe mu (1 - mu)^6 vanishes at mu = 1 (F0 is kept) and at mu = 0 (grazing stays 1),
// and d/dmu [mu (1 - mu)^6] = (1 - mu)^5 (1 - 7 mu) = 0 puts its peak exactly at mu_bar = 1/7: the
// "82 degree" angle is where the correction has most authority. Requiring
// F82(mu_bar) = tint * S(mu_bar):
//     S(mu_bar) - a mu_bar (1 - mu_bar)^6 = tint S(mu_bar)
//     a = (1 - tint) S(mu_bar) / (mu_bar (1 - mu_bar)^6),   mu_bar (1 - mu_bar)^6 = 6^6 / 7^7.
// This is OpenPBR's b coefficient with F(mu_bar) = specular_color * S(mu_bar). tint = 1 gives a = 0.
// The result is clamped to [0, 1]: with a dark F0 and a low tint the lobe overshoots (F0 = 0,
// tint = 0 gives S - a mu (1-mu)^6 = (1-mu)^5 (1 - 49/6 mu (1-mu)) < 0 near mu = 0.5), and a
// tint > 1 (a fit above Schlick) could lift it over 1; no measured metal comes near either.
namespace {
constexpr double kF82LobeAtPin = 46656.0 / 823543.0;  // (1/7)(6/7)^6 = 6^6 / 7^7
}  // namespace

double fresnel_f82_tint(double cos_theta, double f0, double f82_tint) {
  const double mu = clamp_cos(cos_theta);
  const double s_pin = fresnel_schlick(kF82Cos, f0, 1.0);
  const double a = (1.0 - f82_tint) * s_pin / kF82LobeAtPin;
  const double f = fresnel_schlick(mu, f0, 1.0) - a * mu * pow6(1.0 - mu);
  return std::clamp(f, 0.0, 1.0);
}

Rgb fresnel_f82_tint(double cos_theta, const Rgb& f0, const Rgb& f82_tint) {
  return {fresnel_f82_tint(cos_theta, f0.r, f82_tint.r), fresnel_f82_tint(cos_theta, f0.g, f82_tint.g),
          fresnel_f82_tint(cos_theta, f0.b, f82_tint.b)};
}

// Fernando & Kilgard 2003, eq. 7-3, with 1 + I.N = 1 - cos_theta for I pointing at the surface.
double fresnel_empirical(double cos_theta, double bias, double scale, double power) {
  const double r = bias + scale * std::pow(1.0 - clamp_cos(cos_theta), power);
  return std::clamp(r, 0.0, 1.0);
}

// ---- Fits --------------------------------------------------------------------------------------

// Born & Wolf 14.2 at normal incidence: r = (1 - (n + i k)) / (1 + n + i k), |r|^2 as below.
double schlick_f0_from_conductor(double eta, double k) {
  const double k2 = k * k;
  return ((eta - 1.0) * (eta - 1.0) + k2) / ((eta + 1.0) * (eta + 1.0) + k2);
}

Rgb schlick_f0_from_conductor(const Rgb& eta, const Rgb& k) {
  return map3(eta, k, [](double e, double kk) { return schlick_f0_from_conductor(e, kk); });
}

// Solve F82(1/7) = tint * S(1/7) = exact(1/7) for tint; S(1/7) >= (6/7)^5 > 0.46, never 0.
double fit_f82_tint(double eta, double k) {
  const double f0 = schlick_f0_from_conductor(eta, k);
  return fresnel_conductor(kF82Cos, eta, k) / fresnel_schlick(kF82Cos, f0, 1.0);
}

Rgb fit_f82_tint(const Rgb& eta, const Rgb& k) {
  return map3(eta, k, [](double e, double kk) { return fit_f82_tint(e, kk); });
}

FresnelFitError fresnel_fit_error(const std::function<double(double)>& approx,
                                  const std::function<double(double)>& exact, int samples) {
  if (samples < 2)
    throw std::invalid_argument("fresnel_fit_error: samples must be >= 2, got " + std::to_string(samples));
  FresnelFitError e{0.0, 0.0, 0.0};
  double sum = 0.0;
  const double last = static_cast<double>(samples - 1);
  for (int i = 0; i < samples; ++i) {
    const double c = static_cast<double>(i) / last;
    const double d = std::fabs(approx(c) - exact(c));
    sum += d;
    if (d > e.max_abs) {
      e.max_abs = d;
      e.cos_at_max = c;
    }
  }
  e.mean_abs = sum / static_cast<double>(samples);
  return e;
}

}  // namespace brdfbake::reference
