#include "brdfbake/math/sh.hpp"

#include <cmath>
#include <stdexcept>

#include "brdfbake/math/conventions.hpp"

namespace brdfbake::math {

// Real spherical harmonics as polynomials in (x, y, z) on the unit sphere, without the
// Condon-Shortley phase (the table of docs/CONVENTIONS.md; Sloan 2008, "Stupid Spherical Harmonics
// (SH) Tricks", appendix A2, gives the same polynomials).
std::vector<double> sh_basis(int order, const Vec3& d) {
  if (order < 1 || order > kMaxShOrder) throw std::invalid_argument("SH order must be 1..5");
  const double x = d.x, y = d.y, z = d.z;
  const double x2 = x * x, y2 = y * y, z2 = z * z;
  const double ip = 1.0 / kPi;
  std::vector<double> v = {
      0.5 * std::sqrt(ip),
      std::sqrt(0.75 * ip) * y,
      std::sqrt(0.75 * ip) * z,
      std::sqrt(0.75 * ip) * x,
      0.5 * std::sqrt(15.0 * ip) * x * y,
      0.5 * std::sqrt(15.0 * ip) * y * z,
      0.25 * std::sqrt(5.0 * ip) * (3.0 * z2 - 1.0),
      0.5 * std::sqrt(15.0 * ip) * x * z,
      0.25 * std::sqrt(15.0 * ip) * (x2 - y2),
      0.25 * std::sqrt(17.5 * ip) * y * (3.0 * x2 - y2),
      0.5 * std::sqrt(105.0 * ip) * x * y * z,
      0.25 * std::sqrt(10.5 * ip) * y * (5.0 * z2 - 1.0),
      0.25 * std::sqrt(7.0 * ip) * z * (5.0 * z2 - 3.0),
      0.25 * std::sqrt(10.5 * ip) * x * (5.0 * z2 - 1.0),
      0.25 * std::sqrt(105.0 * ip) * z * (x2 - y2),
      0.25 * std::sqrt(17.5 * ip) * x * (x2 - 3.0 * y2),
      0.75 * std::sqrt(35.0 * ip) * x * y * (x2 - y2),
      0.75 * std::sqrt(17.5 * ip) * y * z * (3.0 * x2 - y2),
      0.75 * std::sqrt(5.0 * ip) * x * y * (7.0 * z2 - 1.0),
      0.75 * std::sqrt(2.5 * ip) * y * z * (7.0 * z2 - 3.0),
      (3.0 / 16.0) * std::sqrt(ip) * (35.0 * z2 * z2 - 30.0 * z2 + 3.0),
      0.75 * std::sqrt(2.5 * ip) * x * z * (7.0 * z2 - 3.0),
      (3.0 / 8.0) * std::sqrt(5.0 * ip) * (x2 - y2) * (7.0 * z2 - 1.0),
      0.75 * std::sqrt(17.5 * ip) * x * z * (x2 - 3.0 * y2),
      (3.0 / 16.0) * std::sqrt(35.0 * ip) * (x2 * (x2 - 3.0 * y2) - y2 * (3.0 * x2 - y2)),
  };
  v.resize(static_cast<size_t>(order * order));
  return v;
}

double sh_cosine_lobe(int l) {
  switch (l) {
    case 0:
      return kPi;
    case 1:
      return 2.0 * kPi / 3.0;
    case 2:
      return kPi / 4.0;
    case 3:
      return 0.0;
    case 4:
      return -kPi / 24.0;
    default:
      throw std::invalid_argument("sh_cosine_lobe: band must be 0..4");
  }
}

}  // namespace brdfbake::math
