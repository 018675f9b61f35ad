// How far the SH's irradiance is from the exact irradiance of the map it was projected from
// (issue 35: the default bake's irradiance_sh3.json recorded "not measured"). The projection itself
// is exact to rounding (sh_projection.cpp); what the coefficients cannot hold is the irradiance's
// bands past the order (and what the window takes away). Measured directly: at K directions n of a
// Fibonacci sphere, the exact E(n) / pi = (1 / pi) sum_pixels L_p max(0, n . d_p) omega_p (every
// pixel at its centre with its exact solid angle) against sum_k c_k Y_k(n), as the relative RMS of
// the luminance over the directions.
#include <algorithm>
#include <cmath>
#include <thread>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/math/sh.hpp"
#include "families/irradiance/model.hpp"

namespace brdfbake::detail {
namespace {

using math::kPi;

double luminance(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

// Every pixel's direction and solid angle, with its luminance (the error is of the luminance).
struct Samples {
  std::vector<double> x, y, z, weight;  // weight: luminance x solid angle / pi
};

Samples samples_of(const EnvImage& env) {
  Samples s;
  const auto add = [&s](const Vec3& d, double omega, const float* rgb) {
    const double l = luminance(rgb[0], rgb[1], rgb[2]);
    if (l == 0.0) return;
    s.x.push_back(d.x);
    s.y.push_back(d.y);
    s.z.push_back(d.z);
    s.weight.push_back(l * omega / kPi);
  };
  if (env.layout == EnvImage::Layout::Cube) {
    const int n = env.width;
    for (int f = 0; f < 6; ++f)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
          add(math::cube_texel_direction(f, n, i, j), math::cube_texel_solid_angle(n, i, j),
              &env.rgb[3 * ((size_t(f) * size_t(n) + size_t(j)) * size_t(n) + size_t(i))]);
    return s;
  }
  const int w = env.width, h = env.height;
  for (int y = 0; y < h; ++y) {
    // row y: latitude t in [pi (0.5 - (y + 1) / h), pi (0.5 - y / h)]; column x: phi = 2 pi (0.5 - u)
    const double t0 = kPi * (0.5 - double(y + 1) / h), t1 = kPi * (0.5 - double(y) / h), t = 0.5 * (t0 + t1);
    const double omega = (2.0 * kPi / w) * (std::sin(t1) - std::sin(t0));
    for (int x = 0; x < w; ++x) {
      const double phi = 2.0 * kPi * (0.5 - (double(x) + 0.5) / w);
      add({std::sin(phi) * std::cos(t), std::sin(t), std::cos(phi) * std::cos(t)}, omega,
          &env.rgb[3 * (size_t(y) * size_t(w) + size_t(x))]);
    }
  }
  return s;
}

}  // namespace

ShErrorMeasure sh_irradiance_error(const EnvImage& env, const ShCoefficients& sh) {
  ShErrorMeasure m;
  const Samples s = samples_of(env);
  // Directions: as many as keep the work near 2^27 pixel-direction pairs, 16 to 128.
  const size_t pixels = std::max<size_t>(1, s.weight.size());
  m.directions = int(std::clamp<size_t>((size_t(1) << 27) / pixels, 16, 128));
  std::vector<double> exact(size_t(m.directions)), approx(size_t(m.directions));
  const unsigned threads = std::max(1u, std::min(8u, std::thread::hardware_concurrency()));
  std::vector<std::thread> pool;
  for (unsigned t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      for (int k = int(t); k < m.directions; k += int(threads)) {
        // Fibonacci sphere: z uniform, the golden angle around it
        const double zk = 1.0 - (2.0 * k + 1.0) / m.directions, r = std::sqrt(std::max(0.0, 1.0 - zk * zk));
        const double a = k * kPi * (3.0 - std::sqrt(5.0));
        const Vec3 n{r * std::cos(a), zk, r * std::sin(a)};
        double e = 0.0;
        for (size_t i = 0; i < s.weight.size(); ++i) {
          const double c = n.x * s.x[i] + n.y * s.y[i] + n.z * s.z[i];
          if (c > 0.0) e += s.weight[i] * c;
        }
        const std::vector<double> y = math::sh_basis(sh.order, n);
        double rgb[3] = {0.0, 0.0, 0.0};
        for (size_t b = 0; b < y.size(); ++b)
          for (size_t ch = 0; ch < 3; ++ch) rgb[ch] += sh.irradiance_over_pi[3 * b + ch] * y[b];
        exact[size_t(k)] = e;
        approx[size_t(k)] = luminance(rgb[0], rgb[1], rgb[2]);
      }
    });
  for (auto& th : pool) th.join();
  double num = 0.0, den = 0.0;
  for (int k = 0; k < m.directions; ++k) {
    num += (approx[size_t(k)] - exact[size_t(k)]) * (approx[size_t(k)] - exact[size_t(k)]);
    den += exact[size_t(k)] * exact[size_t(k)];
  }
  m.relative_rms = den > 0.0 ? std::sqrt(num / den) : 0.0;
  return m;
}

// The projection against the converged projection of the same pixels (issue 35): an equirect's
// coefficients are its cells' exact integrals (sh_projection.cpp), so only rounding remains; a cube
// is projected at its texel centres with each texel's exact solid angle, which the converged
// projection refines: every texel split into kSub x kSub sub-texels, each at its own centre with its
// own exact solid angle and the texel's radiance (the error of centre sampling falls as 1 / kSub^2,
// so the reference's own residual is 1/16 of the measured one). The measure is the relative RMS of
// the luminance of the radiance coefficients, which is the relative RMS over the sphere of the
// difference of the two SH functions (Parseval: the basis is orthonormal).
ShProjectionMeasure sh_projection_error(const EnvImage& env, const ShCoefficients& sh) {
  ShProjectionMeasure m;
  if (env.layout != EnvImage::Layout::Cube) return m;
  constexpr int kSub = 4;
  m.subdivision = kSub;
  const int n = env.width, fine = n * kSub, bands = sh.order * sh.order;
  std::vector<std::vector<double>> per_face(6, std::vector<double>(size_t(bands) * 3, 0.0));
  std::vector<std::thread> pool;
  for (int f = 0; f < 6; ++f)
    pool.emplace_back([&, f] {
      std::vector<double>& acc = per_face[size_t(f)];
      for (int j = 0; j < fine; ++j)
        for (int i = 0; i < fine; ++i) {
          const float* rgb = &env.rgb[3 * ((size_t(f) * size_t(n) + size_t(j / kSub)) * size_t(n) + size_t(i / kSub))];
          if (rgb[0] == 0.0f && rgb[1] == 0.0f && rgb[2] == 0.0f) continue;
          const double w = math::cube_texel_solid_angle(fine, i, j);
          const std::vector<double> y = math::sh_basis(sh.order, math::cube_texel_direction(f, fine, i, j));
          for (int b = 0; b < bands; ++b)
            for (int c = 0; c < 3; ++c) acc[3 * size_t(b) + size_t(c)] += double(rgb[c]) * y[size_t(b)] * w;
        }
    });
  for (auto& th : pool) th.join();
  double num = 0.0, den = 0.0;
  for (int b = 0; b < bands; ++b) {
    double conv[3] = {0.0, 0.0, 0.0};
    for (int f = 0; f < 6; ++f)
      for (int c = 0; c < 3; ++c) conv[c] += per_face[size_t(f)][3 * size_t(b) + size_t(c)];
    const double* got = &sh.radiance[3 * size_t(b)];
    const double l = luminance(conv[0], conv[1], conv[2]), d = luminance(got[0], got[1], got[2]) - l;
    num += d * d;
    den += l * l;
  }
  m.relative_rms = den > 0.0 ? std::sqrt(num / den) : 0.0;
  return m;
}

}  // namespace brdfbake::detail
