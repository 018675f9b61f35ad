// Environment sampling's bright texels: the brightest texels of a cube's level 0, which the
// prefilter and the irradiance cube sum exactly instead of through their estimators, and the points
// each one's footprint is summed at.
#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "env/cube.hpp"

namespace brdfbake {

using math::kPi;

std::vector<BrightTexel> find_bright_texels(const CubeLevels& cube, int max_count, double ratio) {
  std::vector<BrightTexel> out;
  if (max_count <= 0 || cube.levels.empty()) return out;
  const int s = cube.size;
  const size_t face = static_cast<size_t>(s) * static_cast<size_t>(s);
  const std::vector<double> omega = detail::texel_solid_angles(s);
  const size_t n = detail::face_texels(s);
  const std::vector<float>& level = cube.levels[0];
  double mean = 0.0;
  for (size_t t = 0; t < n; ++t) mean += detail::luminance(&level[4 * t]) * omega[t % face];
  mean /= 4.0 * kPi;
  // Only the texels above ratio x mean can be chosen: their luminances alone are ranked (the
  // (max_count + 1)-th brightest of them is the (max_count + 1)-th brightest of all whenever there
  // are more than max_count), not a copy of every texel's.
  double threshold = ratio * mean;
  std::vector<double> above;
  for (size_t t = 0; t < n; ++t) {
    const double lum = detail::luminance(&level[4 * t]);
    if (lum > threshold) above.push_back(lum);
  }
  if (above.size() > static_cast<size_t>(max_count)) {
    std::nth_element(above.begin(), above.begin() + max_count, above.end(), std::greater<double>());
    threshold = std::max(threshold, above[size_t(max_count)]);  // the (max_count + 1)-th brightest
  }
  above = {};
  for (size_t t = 0; t < n; ++t) {
    if (!(detail::luminance(&level[4 * t]) > threshold)) continue;
    BrightTexel b;
    b.face = static_cast<int>(t / face);
    b.j = static_cast<int>(t % face / size_t(s));
    b.i = static_cast<int>(t % size_t(s));
    for (size_t c = 0; c < 3; ++c) b.rgb[c] = level[4 * t + c];
    out.push_back(b);
  }
  return out;
}

std::vector<double> bright_texel_points(const std::vector<BrightTexel>& bright, int size, int q, double scale,
                                        int* count) {
  std::vector<double> px, py, pz, pr, pg, pb;
  const double h = 2.0 / size;  // a texel in face coordinates
  for (const BrightTexel& t : bright) {
    const double ca = -1.0 + h * (t.i + 0.5), cb = -1.0 + h * (t.j + 0.5);  // the texel's centre
    for (int sj = 0; sj < 2 * q; ++sj)
      for (int si = 0; si < 2 * q; ++si) {
        // sub-cell [x0, x1] x [y0, y1] of the tent's support [-1, 1]^2 (in texels from the centre)
        const double x0 = -1.0 + double(si) / q, x1 = x0 + 1.0 / q, y0 = -1.0 + double(sj) / q, y1 = y0 + 1.0 / q;
        const double xm = 0.5 * (x0 + x1), ym = 0.5 * (y0 + y1);
        // the tent's exact mean over the sub-cell (it is linear there: the cells do not straddle 0)
        const double tent = (1.0 - std::fabs(xm)) * (1.0 - std::fabs(ym));
        const Vec3 p = math::cube_plane_point(t.face, ca + h * xm, cb + h * ym);
        const double len = std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
        const double omega =
            math::cube_rect_solid_angle(ca + h * x0, cb + h * y0, ca + h * x1, cb + h * y1) * tent * scale;
        px.push_back(p.x / len);
        py.push_back(p.y / len);
        pz.push_back(p.z / len);
        pr.push_back(double(t.rgb[0]) * omega);
        pg.push_back(double(t.rgb[1]) * omega);
        pb.push_back(double(t.rgb[2]) * omega);
      }
  }
  *count = static_cast<int>(px.size());
  while (px.size() % detail::kEnvVectorWidth != 0 || px.empty()) {
    px.push_back(0.0);
    py.push_back(0.0);
    pz.push_back(1.0);
    pr.push_back(0.0);
    pg.push_back(0.0);
    pb.push_back(0.0);
  }
  std::vector<double> out;
  for (const auto* v : {&px, &py, &pz, &pr, &pg, &pb}) out.insert(out.end(), v->begin(), v->end());
  return out;
}

}  // namespace brdfbake
