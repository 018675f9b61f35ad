// The irradiance family's reference: the SH projection and the cosine convolution of an
// environment, every source sub-cell summed in double (envmap.cpp explains the sub-cells).
#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/math/sh.hpp"
#include "brdfbake/reference/charlie.hpp"
#include "brdfbake/reference/envmap.hpp"
#include "brdfbake/reference/ggx.hpp"
#include "envmap_internal.hpp"

namespace brdfbake::reference {

using detail::adaptive_integral;
using detail::auto_subdivision;
using detail::Cell;
using detail::check_cube;
using detail::face_cells;
using detail::normalized;
using detail::parallel_ranges;
using math::dot;
using math::kPi;

// ---- Spherical harmonics and irradiance ----------------------------------------------------------

std::vector<double> sh_project(const EnvCube& source, int order, int subdivision) {
  check_cube(source);
  const size_t n = static_cast<size_t>(order * order);
  std::vector<double> out(3 * n, 0.0);
  for (int face = 0; face < 6; ++face) {
    for (const Cell& cell : face_cells(face, source.size, auto_subdivision(subdivision, source.size))) {
      const auto l = cube_bilinear(source, cell.d);
      const auto y = math::sh_basis(order, cell.d);
      for (size_t k = 0; k < n; ++k)
        for (size_t c = 0; c < 3; ++c) out[3 * k + c] += l[c] * y[k] * cell.omega;
    }
  }
  return out;
}

std::vector<double> irradiance_directions(const EnvCube& source, const std::vector<Vec3>& normals, int subdivision,
                                          unsigned threads) {
  check_cube(source);
  std::vector<double> out(3 * normals.size(), 0.0);
  for (int face = 0; face < 6; ++face) {
    const std::vector<Cell> cells = face_cells(face, source.size, auto_subdivision(subdivision, source.size));
    std::vector<std::array<double, 3>> radiance(cells.size());
    for (size_t k = 0; k < cells.size(); ++k) radiance[k] = cube_bilinear(source, cells[k].d);
    parallel_ranges(normals.size(), threads, [&](size_t begin, size_t end) {
      for (size_t k = begin; k < end; ++k) {
        double e0 = 0, e1 = 0, e2 = 0;
        for (size_t m = 0; m < cells.size(); ++m) {
          const double c = dot(normals[k], cells[m].d);
          if (c <= 0.0) continue;
          const double w = c * cells[m].omega;
          e0 += w * radiance[m][0];
          e1 += w * radiance[m][1];
          e2 += w * radiance[m][2];
        }
        out[3 * k] += e0 / kPi;
        out[3 * k + 1] += e1 / kPi;
        out[3 * k + 2] += e2 / kPi;
      }
    });
  }
  return out;
}

}  // namespace brdfbake::reference
