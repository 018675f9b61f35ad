#include "brdfbake/math/cubemap.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace brdfbake::math {

// The KTX / OpenGL cube map table (OpenGL 4.6, table 8.19), with a = 2 s - 1 and b = 2 t - 1: the
// major axis ma and the face coordinates sc = a |ma|, tc = b |ma| of a direction (x, y, z) are
//   +X: sc = -z, tc = -y    -X: sc = +z, tc = -y    +Y: sc = +x, tc = +z
//   -Y: sc = +x, tc = -z    +Z: sc = +x, tc = -y    -Z: sc = -x, tc = -y
Vec3 cube_plane_point(int face, double a, double b) {
  switch (face) {
    case 0:
      return {1.0, -b, -a};
    case 1:
      return {-1.0, -b, a};
    case 2:
      return {a, 1.0, b};
    case 3:
      return {a, -1.0, -b};
    case 4:
      return {a, -b, 1.0};
    case 5:
      return {-a, -b, -1.0};
    default:
      throw std::invalid_argument("cube face must be 0..5, not " + std::to_string(face));
  }
}

void cube_face_coords(const Vec3& d, int& face, double& a, double& b) {
  const double ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
  if (ax >= ay && ax >= az) {
    face = d.x >= 0.0 ? 0 : 1;
    a = (d.x >= 0.0 ? -d.z : d.z) / ax;
    b = -d.y / ax;
  } else if (ay >= az) {
    face = d.y >= 0.0 ? 2 : 3;
    a = d.x / ay;
    b = (d.y >= 0.0 ? d.z : -d.z) / ay;
  } else {
    face = d.z >= 0.0 ? 4 : 5;
    a = (d.z >= 0.0 ? d.x : -d.x) / az;
    b = -d.y / az;
  }
}

Vec3 cube_texel_direction(int face, int size, int i, int j) {
  const Vec3 p = cube_plane_point(face, 2.0 * (i + 0.5) / size - 1.0, 2.0 * (j + 0.5) / size - 1.0);
  const double n = std::sqrt(dot(p, p));
  return {p.x / n, p.y / n, p.z / n};
}

double cube_rect_solid_angle(double a0, double b0, double a1, double b1) {
  auto F = [](double a, double b) { return std::atan2(a * b, std::sqrt(1.0 + a * a + b * b)); };
  return F(a1, b1) - F(a0, b1) - F(a1, b0) + F(a0, b0);
}

double cube_texel_solid_angle(int size, int i, int j) {
  return cube_rect_solid_angle(2.0 * i / size - 1.0, 2.0 * j / size - 1.0, 2.0 * (i + 1) / size - 1.0,
                               2.0 * (j + 1) / size - 1.0);
}

}  // namespace brdfbake::math
