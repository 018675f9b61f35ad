#include "brdfbake/reference/microfacet.hpp"

#include <algorithm>
#include <cmath>

namespace brdfbake::reference {
namespace {

constexpr double kPi = 3.14159265358979323846;

double clamp01(double x) { return std::clamp(x, 0.0, 1.0); }

double floor_alpha(double alpha) { return std::max(alpha, kMinAlpha); }

// Cosines of the visibility terms: in [kMinCosine, 1] (see kMinCosine).
double visibility_cosine(double c) { return std::clamp(c, kMinCosine, 1.0); }

// sin^2 from a cosine as (1 - c)(1 + c): exact near c = 1, where 1 - c^2 would lose the digits the
// narrow lobes live on.
double sin2_from_cos(double c) { return (1.0 - c) * (1.0 + c); }

double pow5(double x) {
  const double x2 = x * x;
  return x2 * x2 * x;
}

// sqrt(c^2 + alpha^2 s^2) = c sqrt(1 + alpha^2 tan^2): the square root in GGX's Lambda, written
// without the tangent so that it is finite at c = 0.
double ggx_root(double c, double alpha) { return std::sqrt(c * c + alpha * alpha * sin2_from_cos(c)); }

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

// Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces", eq. 33:
// D = alpha^2 / (pi cos^4 (alpha^2 + tan^2)^2)
//   = alpha^2 / (pi (alpha^2 cos^2 + sin^2)^2), zero below the horizon.
double D_GGX(double n_dot_h, double alpha) {
  if (!(n_dot_h >= 0.0)) return 0.0;
  const double a = floor_alpha(alpha);
  const double c = std::min(n_dot_h, 1.0);
  const double denom = a * a * c * c + sin2_from_cos(c);
  return a * a / (kPi * denom * denom);
}

// Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs": GGX's
// Lambda = (-1 + sqrt(1 + alpha^2 tan^2)) / 2, written as
// alpha^2 s^2 / (2 c (c + sqrt(c^2 + alpha^2 s^2))) to avoid the cancellation at small alpha tan.
double Lambda_GGX(double n_dot_x, double alpha) {
  const double a = floor_alpha(alpha);
  const double c = visibility_cosine(n_dot_x);
  return a * a * sin2_from_cos(c) / (2.0 * c * (c + ggx_root(c, a)));
}

// Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs":
// G1 = 1 / (1 + Lambda).
double G1_SmithGGX(double n_dot_x, double alpha) { return 1.0 / (1.0 + Lambda_GGX(n_dot_x, alpha)); }

// Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs":
// height-correlated G2 = 1 / (1 + Lambda(v) + Lambda(l)).
double G2_SmithGGXCorrelated(double n_dot_v, double n_dot_l, double alpha) {
  return 1.0 / (1.0 + Lambda_GGX(n_dot_v, alpha) + Lambda_GGX(n_dot_l, alpha));
}

// Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs",
// G2 / (4 n.l n.v): with c (1 + 2 Lambda(c)) = sqrt(c^2 + alpha^2 s^2) =: S(c),
// 4 n.l n.v (1 + Lambda_v + Lambda_l) = 2 (n.l S(n.v) + n.v S(n.l)).
double V_SmithGGXCorrelated(double n_dot_v, double n_dot_l, double alpha) {
  const double a = floor_alpha(alpha);
  const double cv = visibility_cosine(n_dot_v);
  const double cl = visibility_cosine(n_dot_l);
  return 0.5 / (cl * ggx_root(cv, a) + cv * ggx_root(cl, a));
}

// Schlick 1994, "An Inexpensive BRDF Model for Physically-based Rendering", with F90.
double F_Schlick(double f0, double f90, double v_dot_h) {
  return f0 + (f90 - f0) * pow5(1.0 - clamp01(v_dot_h));
}

// Burley 2012, "Physically-Based Shading at Disney": F_D90 = 0.5 + 2 roughness cos^2(theta_d).
double Fd_Burley(double n_dot_v, double n_dot_l, double l_dot_h, double roughness) {
  const double f_d90 = 0.5 + 2.0 * roughness * l_dot_h * l_dot_h;
  return Fd_BurleyF90(n_dot_v, n_dot_l, f_d90);
}

// Burley 2012, "Physically-Based Shading at Disney":
// f_d = (1/pi) (1 + (F_D90 - 1)(1 - n.l)^5)(1 + (F_D90 - 1)(1 - n.v)^5).
double Fd_BurleyF90(double n_dot_v, double n_dot_l, double f_d90) {
  const double light = 1.0 + (f_d90 - 1.0) * pow5(1.0 - clamp01(n_dot_l));
  const double view = 1.0 + (f_d90 - 1.0) * pow5(1.0 - clamp01(n_dot_v));
  return light * view / kPi;
}

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
