// The engine's conversions of a conductor's (n, k): its normal-incidence reflectance (Schlick's F0)
// and the F82 tint that reproduces it at cos = 1/7.
#include <algorithm>
#include <cmath>

#include "families/fresnel/model.hpp"

namespace brdfbake {

// Written here, not taken from the reference: the kernels receive these parameters, and a mistake
// in them must show against the reference's own fit (tests/device/test_fresnel.cpp).

// The exact unpolarised reflectance of a conductor n + ik seen from air at incidence cos c, in real
// arithmetic (Born & Wolf 14.2; the form of Cook & Torrance 1982, appendix): with s^2 = 1 - c^2,
// t0 = n^2 - k^2 - s^2 and a^2 + b^2 = sqrt(t0^2 + 4 n^2 k^2), a = sqrt((a^2 + b^2 + t0) / 2),
//   R_s = (a^2 + b^2 + c^2 - 2 a c) / (a^2 + b^2 + c^2 + 2 a c),
//   R_p = R_s ((a^2 + b^2) c^2 + s^4 - 2 a c s^2) / ((a^2 + b^2) c^2 + s^4 + 2 a c s^2).
namespace {
double conductor_reflectance(double c, double n, double k) {
  const double c2 = c * c, s2 = 1.0 - c2;
  const double t0 = n * n - k * k - s2;
  const double ab2 = std::sqrt(t0 * t0 + 4.0 * n * n * k * k);
  const double a = std::sqrt(std::max(0.0, 0.5 * (ab2 + t0)));
  const double two_ac = 2.0 * a * c;
  const double rs = (ab2 + c2 - two_ac) / (ab2 + c2 + two_ac);
  const double q = ab2 * c2 + s2 * s2, r = two_ac * s2;
  const double rp = rs * (q - r) / (q + r);
  return 0.5 * (rs + rp);
}
}  // namespace

Rgb detail::conductor_f0(const Rgb& n, const Rgb& k) {
  const auto f0 = [](double nn, double kk) {
    const double k2 = kk * kk;
    return ((nn - 1.0) * (nn - 1.0) + k2) / ((nn + 1.0) * (nn + 1.0) + k2);
  };
  return {f0(n.r, k.r), f0(n.g, k.g), f0(n.b, k.b)};
}

// F82(1/7) = tint * Schlick(1/7) = exact(1/7) (Hoffman 2023): tint = exact(1/7) / Schlick(1/7, F0),
// Schlick(1/7) = F0 + (1 - F0)(6/7)^5 >= (6/7)^5 > 0.46, never 0.
Rgb detail::fit_f82_tint(const Rgb& n, const Rgb& k) {
  const Rgb f0 = conductor_f0(n, k);
  const double pin = 1.0 / 7.0, w = std::pow(6.0 / 7.0, 5.0);
  const auto tint = [&](double nn, double kk, double f) {
    return conductor_reflectance(pin, nn, kk) / (f + (1.0 - f) * w);
  };
  return {tint(n.r, k.r, f0.r), tint(n.g, k.g, f0.g), tint(n.b, k.b, f0.b)};
}

}  // namespace brdfbake
