// Internal: what the environment references share (envmap.cpp defines them): the sub-cells every
// integral over the sphere sums, and the threads and quadrature they run on. The prefilter's lobe
// integrals are prefilter.cpp's, the SH and irradiance irradiance.cpp's.
#pragma once

#include <cmath>
#include <cstddef>
#include <functional>
#include <vector>

#include "brdfbake/reference/envmap.hpp"

namespace brdfbake::reference::detail {

inline Vec3 normalized(const Vec3& d) {
  const double n = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
  return {d.x / n, d.y / n, d.z / n};
}

// Throws std::invalid_argument for a cube whose size or data do not agree.
void check_cube(const EnvCube& cube);
// Runs body(begin, end) over [0, n) split into contiguous ranges, one per thread.
void parallel_ranges(size_t n, unsigned threads, const std::function<void(size_t, size_t)>& body);

// One sub-cell of the sphere: unit centre direction and exact solid angle.
struct Cell {
  Vec3 d;
  double omega;
};
// The q x q sub-cells of every texel of one face of `size`.
std::vector<Cell> face_cells(int face, int size, int q);
// q for the smooth integrands (SH, cosine): the given one, or ceil(128 / size).
int auto_subdivision(int subdivision, int size);
// Integral of f over [a, b] by adaptive bisection of a 20-point Gauss-Legendre rule, to `tol`
// absolute.
double adaptive_integral(const std::function<double(double)>& f, double a, double b, double tol, int depth = 0);

}  // namespace brdfbake::reference::detail
