// The GGX microfacet terms. See ggx.hpp.
#include "brdfbake/reference/ggx.hpp"

#include <algorithm>
#include <cmath>

#include "brdfbake/math/conventions.hpp"

namespace brdfbake::reference {
namespace {

using math::kPi;

double floor_alpha(double alpha) { return std::max(alpha, kMinAlpha); }

// Cosines of the visibility terms: in [kMinCosine, 1] (see kMinCosine).
double visibility_cosine(double c) { return std::clamp(c, kMinCosine, 1.0); }

// sin^2 from a cosine as (1 - c)(1 + c): exact near c = 1, where 1 - c^2 would lose the digits the
// narrow lobes live on.
double sin2_from_cos(double c) { return (1.0 - c) * (1.0 + c); }

// sqrt(c^2 + alpha^2 s^2) = c sqrt(1 + alpha^2 tan^2): the square root in GGX's Lambda, written
// without the tangent so that it is finite at c = 0.
double ggx_root(double c, double alpha) { return std::sqrt(c * c + alpha * alpha * sin2_from_cos(c)); }

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

// Burley 2012, "Physically-Based Shading at Disney", appendix B eq. 13 (GTR2 anisotropic; Heitz
// 2014 eq. 85): D = 1 / (pi ax ay ((h.t / ax)^2 + (h.b / ay)^2 + (h.n)^2)^2). Written from the
// components of h, the sum has no cancellation at the peak.
double D_GGXAniso(const Vec3& h, double alpha_x, double alpha_y) {
  if (!(h.z > 0.0)) return 0.0;
  const double tx = h.x / alpha_x, ty = h.y / alpha_y;
  const double s = tx * tx + ty * ty + h.z * h.z;
  return 1.0 / (kPi * alpha_x * alpha_y * s * s);
}

// Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs", eq. 86:
// anisotropic GGX Lambda = (-1 + sqrt(1 + alpha_o^2 tan^2)) / 2 with alpha_o^2 tan^2 =
// ((ax x.t)^2 + (ay x.b)^2) / (x.n)^2, so G1 = 1 / (1 + Lambda) = 2 c / (c + sqrt((ax x.t)^2 + (ay x.b)^2 + c^2))
// (disney.brdf's smithG_GGX_aniso is G1 / (2 c)).
double G1_SmithGGXAniso(double n_dot_x, double t_dot_x, double b_dot_x, double alpha_x, double alpha_y) {
  const double c = n_dot_x;
  const double a = alpha_x * t_dot_x, b = alpha_y * b_dot_x;
  return 2.0 * c / (c + std::sqrt(a * a + b * b + c * c));
}

}  // namespace brdfbake::reference
