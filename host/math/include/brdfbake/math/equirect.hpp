// The equirectangular (latitude-longitude) mapping of docs/CONVENTIONS.md: OpenEXR's LatLongMap
// orientation, texel centres at ((x + 0.5) / width, (y + 0.5) / height), +Y up, the image centre
// looking down +Z.
#pragma once

#include "brdfbake/math/types.hpp"

namespace brdfbake::math {

// u, v in [0, 1]: longitude phi = 2 pi (0.5 - u), latitude theta = pi (0.5 - v), unit direction
// (sin phi cos theta, sin theta, cos phi cos theta).
Vec3 equirect_direction(double u, double v);
// The inverse: u in (0, 1], v in [0, 1] of a direction (any length > 0).
void equirect_coords(const Vec3& d, double& u, double& v);

}  // namespace brdfbake::math
