// The prefiltered levels' lobes on the host (lobes.hpp).
#include "families/prefilter/lobes.hpp"

#include <algorithm>
#include <cmath>

#include "brdfbake/math/conventions.hpp"

namespace brdfbake::detail {
namespace {

using math::kPi;

// Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces", eq. 33, with
// tan^2 = sin^2 / cos^2: D = alpha^2 / (pi (alpha^2 cos^2 + sin^2)^2), sin^2 = (1 - c)(1 + c)
// (exact near the peak c = 1).
double d_ggx(double c, double alpha) {
  const double a2 = alpha * alpha;
  const double t = a2 * c * c + (1.0 - c) * (1.0 + c);
  return a2 / (kPi * t * t);
}

// Estevez & Kulla 2017, "Production Friendly Microfacet Sheen BRDF", eq. 2:
// D = (2 + 1/alpha) sin^(1/alpha) / (2 pi), formed as exp(ln(sin^2) / (2 alpha)); ln sin^2 as
// log1p(-c^2) where the lobe lives (c < 1/2), ln((1 - c)(1 + c)) above.
double d_charlie(double c, double alpha) {
  const double inv_a = 1.0 / alpha;
  const double log_sin2 = c < 0.5 ? std::log1p(-c * c) : std::log((1.0 - c) * (1.0 + c));
  return (2.0 + inv_a) * std::exp(0.5 * inv_a * log_sin2) / (2.0 * kPi);
}

}  // namespace

double env_lobe_d(EnvDistribution distribution, double n_dot_h, double alpha) {
  if (!(n_dot_h >= 0.0)) return 0.0;
  const double c = std::min(n_dot_h, 1.0), a = std::max(alpha, math::kMinAlpha);
  return distribution == EnvDistribution::Ggx ? d_ggx(c, a) : d_charlie(c, a);
}

double env_lobe_kernel(EnvDistribution distribution, double alpha, double cos_rl) {
  if (!(cos_rl > 0.0)) return 0.0;
  const double c = std::min(cos_rl, 1.0);
  return env_lobe_d(distribution, std::sqrt(0.5 * (1.0 + c)), alpha) * c;
}

// W = int K(R.l) dl with n = v = R, so l = 2 (n.h) h - n, n.l = 2 (n.h)^2 - 1 > 0 for n.h > 1/sqrt 2,
// and dl = 4 (n.h) dh (Walter et al. 2007, the reflection Jacobian with v.h = n.h):
//   W = 4 int D(h) (n.h) (2 (n.h)^2 - 1) dh.
// GGX: D (n.h) dh is the distribution of normals, whose CDF in theta is xi = tan^2 / (alpha^2 +
// tan^2), so (n.h)^2 = (1 - xi) / (1 - b xi), b = 1 - alpha^2, and n.h = 1/sqrt 2 at
// X = 1 / (1 + alpha^2):
//   W = 4 int_0^X (2 (1 - xi) / (1 - b xi) - 1) dxi,
//   int_0^X (1 - xi) / (1 - b xi) dxi = X / b + (alpha^2 / b^2) ln(1 - b X),  1 - b X = 2 alpha^2 / (1 + alpha^2),
// which cancels as b -> 0 (alpha -> 1); there the series sum_k b^k (X^(k+1) / (k+1) - X^(k+2) / (k+2))
// converges instead (ratio b X = (1 - alpha^2) / (1 + alpha^2) <= 1/2 for alpha^2 >= 1/3).
// Charlie: with c = n.l, sin^2(theta_h) = (1 - c) / 2 and dl = 2 pi dc about R:
//   W = (2 + 1/alpha) int_0^1 c ((1 - c) / 2)^p dc = (2 + 1/alpha) 2^-p / ((p + 1)(p + 2)),  p = 1 / (2 alpha)
// (a Beta integral, B(2, p + 1)), formed in logarithms (2^-p underflows for alpha < 1e-3).
double env_lobe_normalization(EnvDistribution distribution, double alpha) {
  const double a = std::max(alpha, math::kMinAlpha), a2 = a * a;
  if (distribution == EnvDistribution::Charlie) {
    const double p = 0.5 / a;
    return std::exp(std::log(2.0 + 1.0 / a) - p * std::log(2.0) - std::log((p + 1.0) * (p + 2.0)));
  }
  const double b = 1.0 - a2, x = 1.0 / (1.0 + a2);
  double integral = 0.0;  // int_0^X (1 - xi) / (1 - b xi) dxi
  if (3.0 * a2 >= 1.0) {
    double bk = 1.0, xk1 = x;  // b^k, X^(k+1)
    for (int k = 0; k < 200; ++k) {
      const double term = bk * (xk1 / (k + 1.0) - xk1 * x / (k + 2.0));
      integral += term;
      if (std::fabs(term) < 1e-17 * integral) break;
      bk *= b;
      xk1 *= x;
    }
  } else {
    integral = x / b + (a2 / (b * b)) * std::log(2.0 * a2 / (1.0 + a2));
  }
  return 4.0 * (2.0 * integral - x);
}

}  // namespace brdfbake::detail
