// The plain value types of the whole project: a direction and a linear RGB triple, in double.
//
// They are brdfbake:: types (the public API's Rgb and Vec3), defined here, in the lowest layer, so
// that the public headers, the engine, the shared maths and the reference all speak them without
// depending on one another. Plain aggregates: no invariants, no behaviour beyond arithmetic helpers.
#pragma once

namespace brdfbake {

// A direction or a point in a right-handed frame (not necessarily normalised; a function that needs
// a unit vector says so).
struct Vec3 {
  double x, y, z;
};

// A linear RGB triple: a colour, a reflectance, or a per-channel parameter such as an index of
// refraction.
struct Rgb {
  double r, g, b;
};

namespace math {

inline double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

}  // namespace math
}  // namespace brdfbake
