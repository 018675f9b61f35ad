// The Charlie sheen distribution and the sheen visibilities. See charlie.hpp.
#include "brdfbake/reference/charlie.hpp"

#include <algorithm>
#include <cmath>

#include "brdfbake/math/conventions.hpp"

namespace brdfbake::reference {
namespace {

using math::kPi;

double clamp01(double x) { return std::clamp(x, 0.0, 1.0); }

double floor_alpha(double alpha) { return std::max(alpha, kMinAlpha); }

// Cosines of the visibility terms: in [kMinCosine, 1] (see kMinCosine).
double visibility_cosine(double c) { return std::clamp(c, kMinCosine, 1.0); }

// sin^2 from a cosine as (1 - c)(1 + c): exact near c = 1.
double sin2_from_cos(double c) { return (1.0 - c) * (1.0 + c); }

// Estevez & Kulla 2017, their fitted L(x) = a / (1 + b x^c) + d x + e at r = 0 and r = 1,
// interpolated with weight (1 - r)^2 on the r = 0 set (r = alpha here, as KHR_materials_sheen).
struct SheenFit {
  double a, b, c, d, e;
};
constexpr SheenFit kSheenFitR0{25.3245, 3.32435, 0.16801, -1.27393, -4.85967};
constexpr SheenFit kSheenFitR1{21.5473, 3.82987, 0.19823, -1.97760, -4.32054};

SheenFit sheen_fit(double alpha) {
  const double r = clamp01(alpha);
  const double t = (1.0 - r) * (1.0 - r);
  auto mix = [t](double at_r1, double at_r0) { return at_r1 + (at_r0 - at_r1) * t; };
  return SheenFit{mix(kSheenFitR1.a, kSheenFitR0.a), mix(kSheenFitR1.b, kSheenFitR0.b),
                  mix(kSheenFitR1.c, kSheenFitR0.c), mix(kSheenFitR1.d, kSheenFitR0.d),
                  mix(kSheenFitR1.e, kSheenFitR0.e)};
}

double sheen_L(const SheenFit& f, double x) { return f.a / (1.0 + f.b * std::pow(x, f.c)) + f.d * x + f.e; }

}  // namespace

// Estevez & Kulla 2017, "Production Friendly Microfacet Sheen BRDF":
// D = (2 + 1/alpha) sin(theta_h)^(1/alpha) / (2 pi), zero below the horizon.
// The power 1/alpha multiplies the relative error of sin^2 by 1/alpha (1e7 at the alpha floor), so
// ln sin^2 is formed without rounding sin^2 first: log1p(-c^2) in the band c < 1/2, where the lobe
// lives, ln((1 - c)(1 + c)) above.
double D_Charlie(double n_dot_h, double alpha) {
  if (!(n_dot_h >= 0.0)) return 0.0;
  const double inv_a = 1.0 / floor_alpha(alpha);
  const double c = std::min(n_dot_h, 1.0);
  const double log_sin2 = c < 0.5 ? std::log1p(-c * c) : std::log(sin2_from_cos(c));
  return (2.0 + inv_a) * std::exp(0.5 * inv_a * log_sin2) / (2.0 * kPi);
}

// Estevez & Kulla 2017, "Production Friendly Microfacet Sheen BRDF": the fitted Lambda, mirrored
// about cos = 1/2.
double Lambda_CharlieEstevezKulla(double n_dot_x, double alpha) {
  const SheenFit f = sheen_fit(alpha);
  const double c = clamp01(n_dot_x);
  if (c < 0.5) return std::exp(sheen_L(f, c));
  return std::exp(2.0 * sheen_L(f, 0.5) - sheen_L(f, 1.0 - c));
}

// Estevez & Kulla 2017, "Production Friendly Microfacet Sheen BRDF": c of the fit above.
double SheenFitExponent(double alpha) { return sheen_fit(alpha).c; }

// Estevez & Kulla 2017, "Production Friendly Microfacet Sheen BRDF":
// V = 1 / ((1 + Lambda(v) + Lambda(l)) 4 n.v n.l), without the terminator softening.
double V_CharlieEstevezKulla(double n_dot_v, double n_dot_l, double alpha) {
  const double cv = visibility_cosine(n_dot_v);
  const double cl = visibility_cosine(n_dot_l);
  const double lambdas = 1.0 + Lambda_CharlieEstevezKulla(cv, alpha) + Lambda_CharlieEstevezKulla(cl, alpha);
  return 1.0 / (lambdas * 4.0 * cv * cl);
}

// Neubelt & Pettineo 2013, "Crafting a Next-Gen Material Pipeline for The Order: 1886", cloth
// visibility 1 / (4 (n.l + n.v - n.l n.v)).
double V_Neubelt(double n_dot_v, double n_dot_l) {
  const double cv = visibility_cosine(n_dot_v);
  const double cl = visibility_cosine(n_dot_l);
  return 1.0 / (4.0 * (cl + cv - cl * cv));
}

}  // namespace brdfbake::reference
