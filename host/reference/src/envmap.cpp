// Environment-map reference: brute force over every source texel, in double.
//
// Every integral over the sphere is a sum over the source cube's texels, each split into q x q
// sub-cells. A sub-cell [a0, a1] x [b0, b1] of a face contributes f(d) * Omega, with d the unit
// direction of its centre and Omega its exact solid angle,
//   Omega = F(a1, b1) - F(a0, b1) - F(a1, b0) + F(a0, b0),  F(a, b) = atan2(a b, sqrt(1 + a^2 + b^2)),
// the antiderivative of the face's area element (1 + a^2 + b^2)^(-3/2) da db. The sub-cells tile
// the sphere exactly, so the sum is the midpoint rule of the integral on the sphere: it converges
// like 1/q^2 wherever f is smooth on the scale of a sub-cell, and q is chosen to resolve the lobe.
//
// This file: the sub-cells and the environment function (bilinear on a cube or an equirect), and
// the conversion of an environment to a cube, which both environment families use; the prefilter's
// lobes are prefilter.cpp's, the SH and irradiance irradiance.cpp's.
#include "brdfbake/reference/envmap.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <thread>

#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/math/equirect.hpp"
#include "brdfbake/reference/quadrature.hpp"
#include "envmap_internal.hpp"

namespace brdfbake::reference {

using detail::check_cube;
using detail::normalized;
using detail::parallel_ranges;
using math::cube_face_coords;
using math::cube_plane_point;
using math::cube_rect_solid_angle;
using math::cube_texel_direction;
using math::kPi;

void detail::check_cube(const EnvCube& cube) {
  if (cube.size < 1) throw std::invalid_argument("envmap reference: cube size must be at least 1");
  const size_t want = 18u * static_cast<size_t>(cube.size) * static_cast<size_t>(cube.size);
  if (cube.rgb.size() != want)
    throw std::invalid_argument("envmap reference: cube holds " + std::to_string(cube.rgb.size()) +
                                " values, expected " + std::to_string(want));
}

void detail::parallel_ranges(size_t n, unsigned threads, const std::function<void(size_t, size_t)>& body) {
  unsigned t = threads != 0 ? threads : std::max(1u, std::thread::hardware_concurrency());
  t = static_cast<unsigned>(std::min<size_t>(t, std::max<size_t>(n, 1)));
  if (t <= 1) {
    body(0, n);
    return;
  }
  std::vector<std::thread> pool;
  for (unsigned k = 0; k < t; ++k) {
    const size_t b = n * k / t, e = n * (k + 1) / t;
    pool.emplace_back(body, b, e);
  }
  for (auto& th : pool) th.join();
}

std::vector<detail::Cell> detail::face_cells(int face, int size, int q) {
  std::vector<Cell> cells;
  cells.reserve(static_cast<size_t>(size) * static_cast<size_t>(size) * static_cast<size_t>(q) *
                static_cast<size_t>(q));
  const int n = size * q;  // sub-cells per face side
  for (int j = 0; j < n; ++j) {
    const double b0 = -1.0 + 2.0 * j / n, b1 = -1.0 + 2.0 * (j + 1) / n;
    for (int i = 0; i < n; ++i) {
      const double a0 = -1.0 + 2.0 * i / n, a1 = -1.0 + 2.0 * (i + 1) / n;
      cells.push_back({normalized(cube_plane_point(face, 0.5 * (a0 + a1), 0.5 * (b0 + b1))),
                       cube_rect_solid_angle(a0, b0, a1, b1)});
    }
  }
  return cells;
}

int detail::auto_subdivision(int subdivision, int size) {
  return subdivision > 0 ? subdivision : std::max(1, (128 + size - 1) / size);
}

double detail::adaptive_integral(const std::function<double(double)>& f, double a, double b, double tol, int depth) {
  const auto& rule = gauss_legendre(20);
  auto gl = [&](double lo, double hi) {
    double s = 0.0;
    for (size_t k = 0; k < rule.nodes.size(); ++k)
      s += rule.weights[k] * f(0.5 * (lo + hi) + 0.5 * (hi - lo) * rule.nodes[k]);
    return 0.5 * (hi - lo) * s;
  };
  const double m = 0.5 * (a + b);
  const double whole = gl(a, b), halves = gl(a, m) + gl(m, b);
  // done when within the tolerance, or at the integrand's own noise: near R, n.h = sqrt((1 + c) / 2)
  // carries 1 - n.h ~ theta^2 / 8 with a relative rounding of 1e-16 / (1 - n.h), ~1e-12 where GGX's
  // narrowest lobes live
  if (std::fabs(whole - halves) <= std::max(tol, 1e-11 * std::fabs(halves)) || depth >= 24) return halves;
  return adaptive_integral(f, a, m, 0.5 * tol, depth + 1) + adaptive_integral(f, m, b, 0.5 * tol, depth + 1);
}

// ---- The environment function --------------------------------------------------------------------

std::array<double, 3> cube_fetch_extended(const EnvCube& cube, int face, int i, int j) {
  const int n = cube.size;
  const bool in_i = i >= 0 && i < n, in_j = j >= 0 && j < n;
  if (in_i && in_j) return {cube.at(face, i, j, 0), cube.at(face, i, j, 1), cube.at(face, i, j, 2)};
  if (!in_i && !in_j) {
    const int ci = std::clamp(i, 0, n - 1), cj = std::clamp(j, 0, n - 1);
    const auto p = cube_fetch_extended(cube, face, ci, j);
    const auto q = cube_fetch_extended(cube, face, i, cj);
    const auto r = cube_fetch_extended(cube, face, ci, cj);
    return {(p[0] + q[0] + r[0]) / 3.0, (p[1] + q[1] + r[1]) / 3.0, (p[2] + q[2] + r[2]) / 3.0};
  }
  // The extended texel centre lies just past the edge, on the neighbouring face's edge row.
  const Vec3 p = cube_plane_point(face, 2.0 * (i + 0.5) / n - 1.0, 2.0 * (j + 0.5) / n - 1.0);
  int f = 0;
  double a = 0, b = 0;
  cube_face_coords(p, f, a, b);
  const int ni = std::clamp(static_cast<int>(std::floor(0.5 * (a + 1.0) * n)), 0, n - 1);
  const int nj = std::clamp(static_cast<int>(std::floor(0.5 * (b + 1.0) * n)), 0, n - 1);
  return {cube.at(f, ni, nj, 0), cube.at(f, ni, nj, 1), cube.at(f, ni, nj, 2)};
}

std::array<double, 3> cube_bilinear(const EnvCube& cube, const Vec3& d) {
  int face = 0;
  double a = 0, b = 0;
  cube_face_coords(d, face, a, b);
  const double x = 0.5 * (a + 1.0) * cube.size - 0.5, y = 0.5 * (b + 1.0) * cube.size - 0.5;
  const double x0 = std::floor(x), y0 = std::floor(y);
  const double fx = x - x0, fy = y - y0;
  const int i0 = static_cast<int>(x0), j0 = static_cast<int>(y0);
  const auto t00 = cube_fetch_extended(cube, face, i0, j0);
  const auto t10 = cube_fetch_extended(cube, face, i0 + 1, j0);
  const auto t01 = cube_fetch_extended(cube, face, i0, j0 + 1);
  const auto t11 = cube_fetch_extended(cube, face, i0 + 1, j0 + 1);
  std::array<double, 3> out{};
  for (int c = 0; c < 3; ++c)
    out[size_t(c)] = (1.0 - fy) * ((1.0 - fx) * t00[size_t(c)] + fx * t10[size_t(c)]) +
                     fy * ((1.0 - fx) * t01[size_t(c)] + fx * t11[size_t(c)]);
  return out;
}

// ---- Conversion ----------------------------------------------------------------------------------

namespace {

// Every texel of an out_size cube as the solid-angle-weighted mean of f over its q x q sub-cells.
template <class F>
EnvCube texel_means(int out_size, int q, unsigned threads, F&& f) {
  if (out_size < 1) throw std::invalid_argument("envmap reference: output size must be at least 1");
  EnvCube out;
  out.size = out_size;
  out.rgb.assign(18u * static_cast<size_t>(out_size) * static_cast<size_t>(out_size), 0.0);
  const int n = out_size * q;  // sub-cells per face side
  parallel_ranges(6u * static_cast<size_t>(out_size), threads, [&](size_t begin, size_t end) {
    for (size_t row = begin; row < end; ++row) {
      const int face = static_cast<int>(row) / out_size, j = static_cast<int>(row) % out_size;
      for (int i = 0; i < out_size; ++i) {
        double sum[3] = {0.0, 0.0, 0.0}, weight = 0.0;
        for (int sj = j * q; sj < (j + 1) * q; ++sj) {
          const double b0 = -1.0 + 2.0 * sj / n, b1 = -1.0 + 2.0 * (sj + 1) / n;
          for (int si = i * q; si < (i + 1) * q; ++si) {
            const double a0 = -1.0 + 2.0 * si / n, a1 = -1.0 + 2.0 * (si + 1) / n;
            const double omega = cube_rect_solid_angle(a0, b0, a1, b1);
            const auto v = f(normalized(cube_plane_point(face, 0.5 * (a0 + a1), 0.5 * (b0 + b1))));
            for (size_t c = 0; c < 3; ++c) sum[c] += omega * v[c];
            weight += omega;
          }
        }
        for (int c = 0; c < 3; ++c) out.at(face, i, j, c) = sum[c] / weight;
      }
    }
  });
  return out;
}

// Sub-cells per output texel side: at least 4 samples per source pixel (or texel) side across the
// output texel, so that the mean of the bilinear function converges like 1/q^2 well below the
// source's own resolution; at least 2, at most 64.
int conversion_subdivision(int subdivision, double source_pixels_per_texel) {
  if (subdivision > 0) return subdivision;
  return static_cast<int>(std::clamp(std::ceil(4.0 * source_pixels_per_texel), 2.0, 64.0));
}

}  // namespace

std::array<double, 3> equirect_bilinear(const EnvEquirect& image, const Vec3& d) {
  double u = 0, v = 0;
  math::equirect_coords(d, u, v);
  const int w = image.width, h = image.height;
  const double fx = u * w - 0.5;
  const double fy = std::clamp(v * h - 0.5, 0.0, static_cast<double>(h - 1));
  const double x0f = std::floor(fx), y0f = std::floor(fy);
  const double tx = fx - x0f, ty = fy - y0f;
  int x0 = static_cast<int>(x0f) % w;
  if (x0 < 0) x0 += w;
  const int x1 = x0 + 1 == w ? 0 : x0 + 1;
  const int y0 = static_cast<int>(y0f), y1 = std::min(y0 + 1, h - 1);
  auto px = [&](int x, int y, size_t c) {
    return image.rgb[3 * (static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) + c];
  };
  std::array<double, 3> out{};
  for (size_t c = 0; c < 3; ++c)
    out[c] = (1.0 - ty) * ((1.0 - tx) * px(x0, y0, c) + tx * px(x1, y0, c)) +
             ty * ((1.0 - tx) * px(x0, y1, c) + tx * px(x1, y1, c));
  return out;
}

EnvCube equirect_to_cube(const EnvEquirect& source, int size, int subdivision, unsigned threads) {
  if (source.width < 1 || source.height < 1 ||
      source.rgb.size() != 3u * static_cast<size_t>(source.width) * static_cast<size_t>(source.height))
    throw std::invalid_argument("envmap reference: the equirect image is empty or the wrong size");
  // an output texel spans about (pi / 2) / size radians, an equirect pixel 2 pi / width at the equator
  const int q = conversion_subdivision(subdivision, 0.25 * source.width / size);
  return texel_means(size, q, threads, [&](const Vec3& d) { return equirect_bilinear(source, d); });
}

EnvCube cube_resample(const EnvCube& source, int size, int subdivision, unsigned threads) {
  check_cube(source);
  const int q = conversion_subdivision(subdivision, static_cast<double>(source.size) / size);
  return texel_means(size, q, threads, [&](const Vec3& d) { return cube_bilinear(source, d); });
}

}  // namespace brdfbake::reference
