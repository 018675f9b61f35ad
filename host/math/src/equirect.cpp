#include "brdfbake/math/equirect.hpp"

#include <algorithm>
#include <cmath>

#include "brdfbake/math/conventions.hpp"

namespace brdfbake::math {

Vec3 equirect_direction(double u, double v) {
  const double phi = 2.0 * kPi * (0.5 - u), theta = kPi * (0.5 - v);
  return {std::sin(phi) * std::cos(theta), std::sin(theta), std::cos(phi) * std::cos(theta)};
}

void equirect_coords(const Vec3& d, double& u, double& v) {
  const double n = std::sqrt(dot(d, d));
  u = 0.5 - std::atan2(d.x / n, d.z / n) / (2.0 * kPi);
  v = 0.5 - std::asin(std::clamp(d.y / n, -1.0, 1.0)) / kPi;
}

}  // namespace brdfbake::math
