// The prefilter family's reference: the lobe of each level (its kernel and normalisation, by
// adaptive quadrature) and the prefiltered radiance, every source sub-cell summed in double
// (envmap.cpp explains the sub-cells).
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
using math::cube_texel_direction;
using math::dot;
using math::kPi;

// ---- Lobes -----------------------------------------------------------------------------------------

// With n = v = R, h bisects R and l: n.h = cos(theta_l / 2) = sqrt((1 + c) / 2).
double env_lobe_kernel(EnvLobe lobe, double alpha, double cos_rl) {
  if (!(cos_rl > 0.0)) return 0.0;
  const double c = std::min(cos_rl, 1.0);
  const double n_dot_h = std::sqrt(0.5 * (1.0 + c));
  const double d = lobe == EnvLobe::Ggx ? D_GGX(n_dot_h, alpha) : D_Charlie(n_dot_h, alpha);
  return d * c;
}

// W = 2 pi int_0^(pi/2) K(cos theta) sin theta d theta. GGX's kernel peaks at theta ~ 2 alpha and
// Charlie's just below pi/2 with a width ~ alpha; geometric breakpoints towards both ends let the
// adaptive rule find either peak at any alpha.
double env_lobe_normalization(EnvLobe lobe, double alpha) {
  const double a = std::max(alpha, kMinAlpha);
  auto f = [&](double theta) { return 2.0 * kPi * env_lobe_kernel(lobe, a, std::cos(theta)) * std::sin(theta); };
  std::vector<double> breaks = {0.0, 0.5 * kPi};
  for (double s = a / 64.0; s < 0.5 * kPi; s *= 4.0) {
    breaks.push_back(s);
    breaks.push_back(0.5 * kPi - s);
  }
  std::sort(breaks.begin(), breaks.end());
  breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
  // a first pass fixes the absolute tolerance, the second meets it
  double rough = 0.0;
  for (size_t k = 0; k + 1 < breaks.size(); ++k)
    if (breaks[k] >= 0.0 && breaks[k + 1] <= 0.5 * kPi) rough += adaptive_integral(f, breaks[k], breaks[k + 1], 1e-6);
  double total = 0.0;
  for (size_t k = 0; k + 1 < breaks.size(); ++k)
    if (breaks[k] >= 0.0 && breaks[k + 1] <= 0.5 * kPi)
      total += adaptive_integral(f, breaks[k], breaks[k + 1], 1e-14 * std::fabs(rough));
  return total;
}

int env_default_subdivision(EnvLobe lobe, double alpha, int source_size) {
  const double width = lobe == EnvLobe::Ggx ? 2.0 * std::max(alpha, kMinAlpha) : 1.0;
  // resolve the lobe, and on small sources the bilinear interpolation itself (a bright texel's
  // tent, cut by the horizon): at least 64 sub-cells per face side
  const double q = std::max(std::ceil(8.0 * (2.0 / source_size) / width), std::ceil(64.0 / source_size));
  return static_cast<int>(std::clamp(q, 1.0, 32.0));
}

// ---- Prefiltered radiance ---------------------------------------------------------------------------

std::vector<double> prefilter_directions(const EnvCube& source, EnvLobe lobe, double roughness,
                                         const std::vector<Vec3>& dirs, int subdivision, unsigned threads) {
  check_cube(source);
  if (!(roughness >= 0.0 && roughness <= 1.0))
    throw std::invalid_argument("envmap reference: roughness must be in [0, 1]");
  std::vector<double> out(3 * dirs.size(), 0.0);
  if (roughness == 0.0) {  // the mirror: the environment itself
    for (size_t k = 0; k < dirs.size(); ++k) {
      const auto l = cube_bilinear(source, dirs[k]);
      for (size_t c = 0; c < 3; ++c) out[3 * k + c] = l[c];
    }
    return out;
  }
  const double alpha = roughness * roughness;
  const int q = subdivision > 0 ? subdivision : env_default_subdivision(lobe, alpha, source.size);
  std::vector<double> num(3 * dirs.size(), 0.0), den(dirs.size(), 0.0);
  for (int face = 0; face < 6; ++face) {
    const std::vector<Cell> cells = face_cells(face, source.size, q);
    std::vector<std::array<double, 3>> radiance(cells.size());
    for (size_t k = 0; k < cells.size(); ++k) radiance[k] = cube_bilinear(source, cells[k].d);
    parallel_ranges(dirs.size(), threads, [&](size_t begin, size_t end) {
      for (size_t k = begin; k < end; ++k) {
        double n0 = 0, n1 = 0, n2 = 0, w = 0;
        for (size_t m = 0; m < cells.size(); ++m) {
          const double c = dot(dirs[k], cells[m].d);
          if (c <= 0.0) continue;
          const double kw = env_lobe_kernel(lobe, alpha, c) * cells[m].omega;
          n0 += kw * radiance[m][0];
          n1 += kw * radiance[m][1];
          n2 += kw * radiance[m][2];
          w += kw;
        }
        num[3 * k] += n0;
        num[3 * k + 1] += n1;
        num[3 * k + 2] += n2;
        den[k] += w;
      }
    });
  }
  for (size_t k = 0; k < dirs.size(); ++k)
    for (size_t c = 0; c < 3; ++c) out[3 * k + c] = den[k] > 0.0 ? num[3 * k + c] / den[k] : 0.0;
  return out;
}

EnvCube prefilter_cube(const EnvCube& source, EnvLobe lobe, double roughness, int out_size, int subdivision,
                       unsigned threads) {
  if (out_size < 1) throw std::invalid_argument("envmap reference: output size must be at least 1");
  std::vector<Vec3> dirs;
  for (int f = 0; f < 6; ++f)
    for (int j = 0; j < out_size; ++j)
      for (int i = 0; i < out_size; ++i) dirs.push_back(cube_texel_direction(f, out_size, i, j));
  EnvCube out;
  out.size = out_size;
  out.rgb = prefilter_directions(source, lobe, roughness, dirs, subdivision, threads);
  return out;
}

}  // namespace brdfbake::reference
