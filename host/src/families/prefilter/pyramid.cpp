// The prefilter quadrature's pyramid (kernels/common/env_sampling.clh, env_pyramid_sum): the moments
// of level 0 summed up a quadtree on the host, in double, and the refinement thresholds that say
// which of its texels a level's lobe opens.
#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "env/cube.hpp"
#include "families/prefilter/lobes.hpp"
#include "families/prefilter/model.hpp"

namespace brdfbake {

using detail::Pyramid;
using math::kPi;

namespace {

using detail::luminance;
using detail::texel_solid_angles;

// Quadtree order within a face (kernels/common/env_sampling.clh): texel (i, j) of a level `depth`
// levels below the top level (face size top_size) has index root * 4^depth + interleave(i, j) of
// its position in its root's block, with root = (j >> depth) top_size + (i >> depth); the four
// children of texel p are 4p .. 4p + 3.
size_t quadtree_index(int i, int j, int depth, int top_size) {
  const size_t root = size_t(j >> depth) * size_t(top_size) + size_t(i >> depth);
  size_t local = 0;
  for (int bit = 0; bit < depth; ++bit)
    local |= size_t((i >> bit) & 1) << (2 * bit) | size_t((j >> bit) & 1) << (2 * bit + 1);
  return (root << (2 * depth)) | local;
}

// Face sizes of the full pyramid of a cube of face size s0: s0, s0 / 2, ... down to 1 or the first
// odd size (the top level).
std::vector<int> pyramid_sizes(int s0) {
  std::vector<int> sizes = {s0};
  while (sizes.back() > 1 && sizes.back() % 2 == 0) sizes.push_back(sizes.back() / 2);
  return sizes;
}

// The moments of one face of one pyramid level, in double: 3, 3, 1, 3 values per texel, row-major.
struct Moments {
  std::vector<double> g, m, w, l;  // Omega d, lum Omega d, Omega, L Omega
  void assign(size_t n) {
    g.assign(3 * n, 0.0);
    m.assign(3 * n, 0.0);
    w.assign(n, 0.0);
    l.assign(3 * n, 0.0);
  }
};

// The base level of face f: each texel sums its 2^base x 2^base texels of level 0 (face size s0),
// with each texel's exact solid angle (omega) and centre direction; texels marked in `skip` add
// their solid angle but no radiance.
void base_moments(const std::vector<float>& rgba, int s0, int base, int f, int sb, const std::vector<double>& omega,
                  const std::vector<uint8_t>& skip, Moments& b) {
  b.assign(size_t(sb) * size_t(sb));
  for (int j = 0; j < s0; ++j)
    for (int i = 0; i < s0; ++i) {
      const size_t t = (size_t(f) * size_t(s0) + size_t(j)) * size_t(s0) + size_t(i);
      const size_t u = size_t(j >> base) * size_t(sb) + size_t(i >> base);
      const Vec3 d = math::cube_texel_direction(f, s0, i, j);
      const double w = omega[size_t(j) * size_t(s0) + size_t(i)];
      const double dv[3] = {d.x, d.y, d.z};
      b.w[u] += w;
      for (size_t c = 0; c < 3; ++c) b.g[3 * u + c] += w * dv[c];
      if (!skip.empty() && skip[t]) continue;
      const double lum = luminance(&rgba[4 * t]) * w;
      for (size_t c = 0; c < 3; ++c) {
        b.m[3 * u + c] += lum * dv[c];
        b.l[3 * u + c] += double(rgba[4 * t + c]) * w;
      }
    }
}

// A coarser level of a face (size h): the sums of 2 x 2 children of `cur` (size sc).
void coarser_moments(const Moments& cur, int sc, int h, Moments& next) {
  next.assign(size_t(h) * size_t(h));
  for (int j = 0; j < sc; ++j)
    for (int i = 0; i < sc; ++i) {
      const size_t t = size_t(j) * size_t(sc) + size_t(i);
      const size_t u = size_t(j / 2) * size_t(h) + size_t(i / 2);
      for (size_t c = 0; c < 3; ++c) {
        next.g[3 * u + c] += cur.g[3 * t + c];
        next.m[3 * u + c] += cur.m[3 * t + c];
        next.l[3 * u + c] += cur.l[3 * t + c];
      }
      next.w[u] += cur.w[t];
    }
}

// Face f of pyramid level k, in quadtree order, as floats; directions normalised.
void write_face(Pyramid& p, int k, int f, const Moments& cur) {
  const int top_size = p.sizes.back();
  const int sk = p.sizes[size_t(k)];
  const size_t n_face = size_t(sk) * size_t(sk), a = 6 * n_face + 8, offset = size_t(p.info[2 * size_t(k)]);
  for (int j = 0; j < sk; ++j)
    for (int i = 0; i < sk; ++i) {
      const size_t t = size_t(j) * size_t(sk) + size_t(i);
      const size_t at = offset + size_t(f) * n_face + quadtree_index(i, j, p.levels - 1 - k, top_size);
      const double* g = &cur.g[3 * t];
      const double* m = &cur.m[3 * t];
      const double gn = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
      const double mn = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
      for (size_t c = 0; c < 3; ++c) {
        p.data[at + c * a] = static_cast<float>(g[c] / gn);
        p.data[at + (3 + c) * a] = static_cast<float>(mn > 0.0 ? m[c] / mn : g[c] / gn);
        p.data[at + (7 + c) * a] = static_cast<float>(cur.l[3 * t + c]);
      }
      p.data[at + 6 * a] = static_cast<float>(cur.w[t]);
    }
}

// The pyramid's levels from `base` of the full pyramid of face s0 up, with their offsets; the data
// allocated, zero.
Pyramid pyramid_layout(int s0, int base) {
  const std::vector<int> full = pyramid_sizes(s0);
  base = std::clamp(base, 0, static_cast<int>(full.size()) - 1);
  Pyramid p;
  p.sizes.assign(full.begin() + base, full.end());
  p.levels = static_cast<int>(p.sizes.size());
  size_t total = 0;
  for (int sk : p.sizes) {
    p.info.push_back(static_cast<cl_int>(total));
    p.info.push_back(sk);
    total += 10 * (6 * size_t(sk) * size_t(sk) + 8);
  }
  if (total > static_cast<size_t>(std::numeric_limits<cl_int>::max()))
    throw Error("cube of size " + std::to_string(s0) + " is too large for the quadrature's pyramid");
  p.data.assign(total, 0.0f);
  return p;
}

}  // namespace

// The pyramid of an RGBA cube, in double, from level `base` of the full pyramid up (the levels
// below it are never visited: pyramid_base_level): each texel of the base level sums its
// 2^base x 2^base texels of level 0 (the moments Omega d and lum Omega d, Omega, L Omega, with each
// texel's exact solid angle and centre direction; texels marked in `skip`, the bright ones, add their
// solid angle but no radiance), each coarser level sums 2 x 2 children, down to the top level.
// Directions are normalised on output. A face at a time (the faces' pyramids are independent), so
// that only one face's moments are held in double: a 1024^2 cube with base 2 needs 5 MiB for them.
detail::Pyramid detail::build_pyramid(const std::vector<float>& rgba, int s0, int base,
                                      const std::vector<uint8_t>& skip) {
  Pyramid p = pyramid_layout(s0, base);
  base = std::clamp(base, 0, static_cast<int>(pyramid_sizes(s0).size()) - 1);
  const std::vector<double> omega = texel_solid_angles(s0);
  // faces 0-2 on a second thread, 3-5 here (independent moments, disjoint parts of p.data)
  auto faces = [&](int f_begin, int f_end) {
    std::vector<Moments> moments(size_t(p.levels));
    for (int f = f_begin; f < f_end; ++f) {
      base_moments(rgba, s0, base, f, p.sizes[0], omega, skip, moments[0]);
      for (int k = 1; k < p.levels; ++k)
        coarser_moments(moments[size_t(k - 1)], p.sizes[size_t(k - 1)], p.sizes[size_t(k)], moments[size_t(k)]);
      for (int k = 0; k < p.levels; ++k) write_face(p, k, f, moments[size_t(k)]);
    }
  };
  if (s0 >= 64) {
    std::exception_ptr failed;
    std::thread second([&] {
      try {
        faces(0, 3);
      } catch (...) {
        failed = std::current_exception();
      }
    });
    faces(3, 6);
    second.join();
    if (failed) std::rethrow_exception(failed);
  } else {
    faces(0, 6);
  }
  return p;
}

// The refinement thresholds of one output level (env_pyramid_sum). Texel angular size
// h_k = 2 / S_k (its largest, at a face's centre).
//   GGX: the core is the lobe of width w = 2 alpha around R; levels coarser than m0 (the coarsest
//        with h <= w / core_refinement) refine within refinement * h of R: cos_core[k] =
//        cos(refinement h_k). Where the kernel's kink at n.l = 0 matters (K'(0) / K(1) =
//        4 alpha^4 / (1 + alpha^2)^2 > 1e-3), levels with h_k > horizon_texel also refine the band
//        |c| < 2 h_k.
//   Charlie: no core (D_Charlie vanishes at R); its lobe is a ring at R.l = c* (the maximum of K).
//        Levels coarser than m0 (h <= 4 half-maximum widths / core_refinement) refine the band where
//        K > 1e-3 K_max, widened by 2 h_k, joined with the horizon band.
// band holds (lo, hi) per level; (2, 2) is empty.
void detail::pyramid_thresholds(const Pyramid& p, EnvDistribution dist, double alpha, const PrefilterSpec& s,
                                double refinement, std::vector<double>& cos_core, std::vector<double>& band) {
  cos_core.assign(size_t(p.levels), 2.0);
  band.assign(2 * size_t(p.levels), 2.0);
  auto finest_level = [&](double width) {
    int m0 = 0;
    while (m0 + 1 < p.levels && 2.0 / p.sizes[size_t(m0 + 1)] <= width / s.core_refinement) ++m0;
    return m0;
  };
  if (dist == EnvDistribution::Ggx) {
    const int m0 = finest_level(2.0 * alpha);
    const double a4 = alpha * alpha * alpha * alpha;
    const bool horizon = 4.0 * a4 / ((1.0 + alpha * alpha) * (1.0 + alpha * alpha)) > 1e-3;
    for (int k = 1; k < p.levels; ++k) {
      const double h = 2.0 / p.sizes[size_t(k)];
      if (k > m0) cos_core[size_t(k)] = refinement * h >= kPi ? -2.0 : std::cos(refinement * h);
      if (horizon && h > s.horizon_texel) {
        band[2 * size_t(k)] = -2.0 * h;
        band[2 * size_t(k) + 1] = 2.0 * h;
      }
    }
    return;
  }
  // Charlie: the ring's extent in theta from the kernel's profile
  constexpr int kSteps = 4096;
  double k_max = 0.0;
  std::vector<double> profile(kSteps + 1);
  for (int t = 0; t <= kSteps; ++t) {
    profile[size_t(t)] = env_lobe_kernel(dist, alpha, std::cos(0.5 * kPi * t / kSteps));
    k_max = std::max(k_max, profile[size_t(t)]);
  }
  double theta_lo = 0.5 * kPi, theta_hi = 0.0, half_lo = 0.5 * kPi, half_hi = 0.0;
  for (int t = 0; t <= kSteps; ++t) {
    const double theta = 0.5 * kPi * t / kSteps;
    if (profile[size_t(t)] > 1e-3 * k_max) {
      theta_lo = std::min(theta_lo, theta);
      theta_hi = std::max(theta_hi, theta);
    }
    if (profile[size_t(t)] > 0.5 * k_max) {
      half_lo = std::min(half_lo, theta);
      half_hi = std::max(half_hi, theta);
    }
  }
  // the ring is broad and smooth on the scale of its half-maximum width: a quarter of the core
  // refinement resolves it (docs/BENCHMARKS.md)
  int m0 = 0;
  while (m0 + 1 < p.levels &&
         2.0 / p.sizes[size_t(m0 + 1)] <= std::max(half_hi - half_lo, 1e-3) * 4.0 / s.core_refinement)
    ++m0;
  for (int k = 1; k < p.levels; ++k) {
    const double h = 2.0 / p.sizes[size_t(k)];
    double lo = 2.0, hi = 2.0;
    if (k > m0) {
      lo = std::cos(std::min(0.5 * kPi, theta_hi + 2.0 * h));
      hi = std::cos(std::max(0.0, theta_lo - 2.0 * h));
    }
    if (h > s.horizon_texel) {
      lo = lo > 1.5 ? -2.0 * h : std::min(lo, -2.0 * h);
      hi = hi > 1.5 ? 2.0 * h : std::max(hi, 2.0 * h);
    }
    band[2 * size_t(k)] = lo;
    band[2 * size_t(k) + 1] = hi;
  }
  (void)refinement;
}

// The finest level of the full pyramid of a cube of face size s0 that the quadrature visits for
// any of the lobes `alphas`: one below the finest level it refines (core, horizon band or Charlie's
// ring). Levels below it are never read, so build_pyramid starts there; the thresholds do not
// depend on the refinement's value (only on the lobe, core_refinement and horizon_texel), so every
// run of a --chain-max-error search visits the same levels.
int detail::pyramid_base_level(int s0, EnvDistribution dist, const std::vector<double>& alphas,
                               const PrefilterSpec& s) {
  Pyramid shape;
  shape.sizes = pyramid_sizes(s0);
  shape.levels = static_cast<int>(shape.sizes.size());
  int base = shape.levels - 1;
  std::vector<double> cos_core, band;
  for (double alpha : alphas) {
    pyramid_thresholds(shape, dist, alpha, s, s.refinement, cos_core, band);
    for (int k = 1; k < shape.levels; ++k)
      if (cos_core[size_t(k)] <= 1.0 || band[2 * size_t(k)] < band[2 * size_t(k) + 1]) {
        base = std::min(base, k - 1);
        break;
      }
  }
  return base;
}

}  // namespace brdfbake
