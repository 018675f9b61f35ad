// Burley's diffuse lobes. See burley.hpp.
#include "brdfbake/reference/burley.hpp"

#include <algorithm>
#include <cmath>

#include "brdfbake/math/conventions.hpp"

namespace brdfbake::reference {
namespace {

using math::kPi;
constexpr double kInvPi = 1.0 / kPi;

double clamp01(double x) { return std::clamp(x, 0.0, 1.0); }

double pow5(double x) {
  const double x2 = x * x;
  return x2 * x2 * x;
}

}  // namespace

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

// Burley 2012 (disney.brdf, after Hanrahan & Krueger 1993): F_ss90 = roughness (l.h)^2,
// F_ss = (1 + (F_ss90 - 1)(1 - n.l)^5)(1 + (F_ss90 - 1)(1 - n.v)^5),
// f_ss = (1.25 / pi) (F_ss (1 / (n.l + n.v) - 0.5) + 0.5). n.l + n.v > 0 is the caller's guard
// (both cosines floored at kBrdfMinCosine, docs/CONVENTIONS.md).
double Fd_DisneySubsurface(double n_dot_v, double n_dot_l, double l_dot_h, double roughness) {
  const double f90 = roughness * l_dot_h * l_dot_h;
  const double fss = (1.0 + (f90 - 1.0) * pow5(1.0 - n_dot_l)) * (1.0 + (f90 - 1.0) * pow5(1.0 - n_dot_v));
  return 1.25 * kInvPi * (fss * (1.0 / (n_dot_l + n_dot_v) - 0.5) + 0.5);
}

}  // namespace brdfbake::reference
