// Filament's built-in DFG table (filament_dfg.hpp).
#include "engines/filament_dfg.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

#include "io/half.hpp"

namespace brdfbake::detail {
namespace {

constexpr int kGgxSamples = 1024;
constexpr int kCharlieSamples = 4096;
constexpr double kPi = 3.14159265358979323846;

// libs/ibl/include/ibl/utilities.h hammersley(i, 1/n): (i / n, radicalInverse(i)), each in float.
void hammersley(uint32_t i, int n, double* u, double* v) {
  uint32_t bits = i;
  bits = (bits << 16u) | (bits >> 16u);
  bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
  bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
  bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
  bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
  *u = double(float(i) * (1.0f / float(n)));
  *v = double(float(bits) * (0.5f / float(0x80000000u)));
}

// CubemapIBL.cpp Visibility: the height-correlated Smith term G / (4 NoL NoV).
double visibility(double nov, double nol, double a) {
  const double a2 = a * a;
  const double ggxl = nov * std::sqrt((nol - nol * a2) * nol + a2);
  const double ggxv = nol * std::sqrt((nov - nov * a2) * nov + a2);
  return 0.5 / (ggxv + ggxl);
}

// V = (sqrt(1 - NoV^2), 0, NoV) and the half vector h: (VoH clamped, NoL clamped, NoH clamped).
struct Half {
  double voh, nol, noh;
};
Half half_vector(double nov, double hx, double hz) {
  const double vx = std::sqrt(1.0 - nov * nov);
  const double voh = vx * hx + nov * hz;
  const double lz = 2.0 * voh * hz - nov;
  return {std::clamp(voh, 0.0, 1.0), std::clamp(lz, 0.0, 1.0), std::clamp(hz, 0.0, 1.0)};
}

// DFV_Multiscatter: (x, y) = 4/N sum (Fc v, v), v = V NoL VoH / NoH, over GGX importance samples.
void dfv_multiscatter(double nov, double a, double* x, double* y) {
  double rx = 0.0, ry = 0.0;
  for (int i = 0; i < kGgxSamples; ++i) {
    double u = 0, w = 0;
    hammersley(uint32_t(i), kGgxSamples, &u, &w);
    const double phi = 2.0 * kPi * u;
    const double cos2 = (1.0 - w) / (1.0 + (a + 1.0) * ((a - 1.0) * w));  // hemisphereImportanceSampleDggx
    const double sin_t = std::sqrt(1.0 - cos2);
    const Half h = half_vector(nov, sin_t * std::cos(phi), std::sqrt(cos2));
    if (h.nol > 0.0) {
      const double v = visibility(nov, h.nol, a) * h.nol * (h.voh / h.noh);
      const double fc = std::pow(1.0 - h.voh, 5.0);
      rx += v * fc;
      ry += v;
    }
  }
  *x = rx * 4.0 / kGgxSamples;
  *y = ry * 4.0 / kGgxSamples;
}

// DFV_Charlie_Uniform: 8 pi/N sum V_Ashikhmin D_Charlie NoL VoH over uniform samples of h.
double dfv_charlie(double nov, double a) {
  double r = 0.0;
  for (int i = 0; i < kCharlieSamples; ++i) {
    double u = 0, w = 0;
    hammersley(uint32_t(i), kCharlieSamples, &u, &w);
    const double phi = 2.0 * kPi * u, cos_t = 1.0 - w, sin_t = std::sqrt(1.0 - cos_t * cos_t);
    const Half h = half_vector(nov, sin_t * std::cos(phi), cos_t);
    if (h.nol > 0.0) {
      const double vis = 1.0 / (4.0 * (h.nol + nov - h.nol * nov));
      const double inv_a = 1.0 / a, sin2h = 1.0 - h.noh * h.noh;
      const double d = (2.0 + inv_a) * std::pow(sin2h, inv_a * 0.5) / (2.0 * kPi);
      r += vis * d * h.nol * h.voh;
    }
  }
  return r * 4.0 * 2.0 * kPi / kCharlieSamples;
}

float as_half(double v) { return io::half_bits_to_float(io::float_to_half_bits(float(v))); }

Table compute() {
  const int n = kFilamentDfgSize;
  Table t;
  t.width = t.height = n;
  t.channels = {"bias", "albedo", "charlie"};
  t.x_name = "n_dot_v";
  t.y_name = "perceptual_roughness";
  t.data.assign(size_t(n) * size_t(n) * 3, 0.0f);
  for (int s = 0; s < n; ++s) t.x.push_back((s + 0.5) / n);
  for (int row = 0; row < n; ++row) t.y.push_back((row + 0.5) / n);
  // rows on every core (each row's values are its own: the same bytes whatever the thread count)
  auto rows = [&](int first, int step) {
    for (int row = first; row < n; row += step) {
      const double coord = std::min((row + 1.5) / n, 1.0), a = coord * coord;
      for (int s = 0; s < n; ++s) {
        const double nov = (s + 0.5) / n;
        double x = 0, y = 0;
        dfv_multiscatter(nov, a, &x, &y);
        t.at(s, row, 0) = as_half(x);
        t.at(s, row, 1) = as_half(y);
        t.at(s, row, 2) = as_half(dfv_charlie(nov, a));
      }
    }
  };
  const int threads = int(std::clamp(std::thread::hardware_concurrency(), 1u, 16u));
  std::vector<std::thread> pool;
  for (int k = 1; k < threads; ++k) pool.emplace_back(rows, k, threads);
  rows(0, threads);
  for (auto& th : pool) th.join();
  t.set_meta("kind", "Filament's built-in DFG table (light_iblDFG), as its build's cmgen makes it");
  return t;
}

}  // namespace

const Table& filament_dfg_table() {
  static std::once_flag once;
  static Table table;
  std::call_once(once, [] { table = compute(); });
  return table;
}

}  // namespace brdfbake::detail
