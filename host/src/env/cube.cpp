// The environment families' cubes: texel solid angles, the metadata every cube records, and the
// opt-in luminance clamp.
#include "env/cube.hpp"

#include <cmath>
#include <string>
#include <vector>

#include "brdfbake/version.hpp"

namespace brdfbake {

// The exact solid angle of every texel (i, j) of a face of `size`, row-major: math::cube_texel_solid_angle
// from one grid of its antiderivative F(a, b) = atan2(a b, sqrt(1 + a^2 + b^2)) at the texel corners
// ((size + 1)^2 atan2, not 4 size^2; the same values, summed in the same order).
std::vector<double> detail::texel_solid_angles(int size) {
  const size_t n = size_t(size) + 1;
  std::vector<double> corner(n * n);
  for (size_t j = 0; j < n; ++j)
    for (size_t i = 0; i < n; ++i) {
      const double a = 2.0 * double(i) / size - 1.0, b = 2.0 * double(j) / size - 1.0;
      corner[j * n + i] = std::atan2(a * b, std::sqrt(1.0 + a * a + b * b));
    }
  std::vector<double> omega(size_t(size) * size_t(size));
  for (size_t j = 0; j < size_t(size); ++j)
    for (size_t i = 0; i < size_t(size); ++i)
      omega[j * size_t(size) + i] =
          corner[(j + 1) * n + i + 1] - corner[(j + 1) * n + i] - corner[j * n + i + 1] + corner[j * n + i];
  return omega;
}

// Biased, opt-in: luminance above `limit` is compressed to limit (1 + log(lum / limit)).
void detail::clamp_luminance(std::vector<float>& rgba, double limit) {
  for (size_t t = 0; t < rgba.size(); t += 4) {
    const double lum = luminance(&rgba[t]);
    if (lum <= limit) continue;
    const double scale = limit * (1.0 + std::log(lum / limit)) / lum;
    for (size_t c = 0; c < 3; ++c) rgba[t + c] = static_cast<float>(double(rgba[t + c]) * scale);
  }
}

std::string detail::comma_join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& e : v) s += (s.empty() ? "" : ",") + e;
  return s;
}

void detail::cube_conventions_metadata(CubeLevels& cube) {
  cube.set_meta("generator", std::string("brdfbake ") + kVersion);
  cube.set_meta("faces", "+X,-X,+Y,-Y,+Z,-Z (KTX / OpenGL cube map order)");
  cube.set_meta("face_orientation",
                "OpenGL cube map convention (OpenGL 4.6 table 8.19): texel (i, j), row j = 0 stored first, "
                "a = 2 (i + 0.5) / S - 1, b = 2 (j + 0.5) / S - 1 look along +X: (1, -b, -a), -X: (-1, -b, a), "
                "+Y: (a, 1, b), -Y: (a, -1, -b), +Z: (a, -b, 1), -Z: (-a, -b, -1)");
  cube.set_meta("up", "+Y");
  cube.set_meta("equirect_mapping",
                "u = (x + 0.5) / W, v = (y + 0.5) / H, phi = 2 pi (0.5 - u), theta = pi (0.5 - v), "
                "direction (sin phi cos theta, sin theta, cos phi cos theta): top row +Y, centre +Z, u = 1/4 +X "
                "(OpenEXR LatLongMap orientation)");
  cube.set_meta("texels", "linear radiance (RGB, alpha 1)");
}

void detail::environment_source_metadata(CubeLevels& out, const EnvImage& env) {
  out.set_meta("source", env.source);
  if (!env.description.empty()) out.set_meta("source_description", env.description);
  if (env.sanitize.replaced)
    out.set_meta("sanitized", std::to_string(env.sanitize.nan) + " NaN, " + std::to_string(env.sanitize.infinite) +
                                  " infinite, " + std::to_string(env.sanitize.negative) + " negative values replaced");
}

}  // namespace brdfbake
