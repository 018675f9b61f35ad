// Spherical-harmonic projection of an environment on the host, in double precision (no device):
// the SH of `brdfbake irradiance` (docs/CONVENTIONS.md, "Spherical harmonics and irradiance").
//
// An equirect is projected exactly as its pixels define it, each pixel constant over its cell
// (longitude phi in [phi0, phi1], latitude t in [t0, t1], dl = cos t dt dphi):
//
//   L_k = sum_pixels L_p int_cell Y_k dl.
//
// Y_k is a polynomial of degree <= order - 1 in (x, y, z) = (sin phi cos t, sin t, cos phi cos t),
// so along a row it is a trigonometric polynomial in phi of degree M = order - 1:
//   Y_k(t, phi) = sum_{m=0..M} A_km(t) cos(m phi) + B_km(t) sin(m phi),
// with A, B found exactly by a discrete Fourier transform of Y_k at 2M + 1 longitudes. The cell
// integral separates:
//   int_cell Y_k dl = sum_m [int A_km(t) cos t dt] [int cos(m phi) dphi] + (the same with B, sin),
// the phi integrals in closed form per column, the t integrals by Gauss-Legendre per row (smooth
// integrands over an interval of at most pi / 64: exact to rounding). Per pixel this costs
// (2M + 1) x 3 multiply-adds (15 for 3 bands), and a constant environment gives L_00 = 2 sqrt(pi) L
// and nothing else to rounding, at any resolution.
//
// A cube is projected at its texel centres with each texel's exact solid angle (the device's
// definition before; the cube's texels already are the samples). The irradiance family's SH, on
// every backend's host (the OpenCL kernel's for SH alone and for a cube alike).
#include <algorithm>
#include <array>
#include <cmath>
#include <thread>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/math/sh.hpp"

namespace brdfbake {
namespace {

using brdfbake::math::kPi;
constexpr int kMaxOrder = 5;
constexpr int kMaxHarmonic = kMaxOrder - 1;
constexpr int kMaxBasis = kMaxOrder * kMaxOrder;
// Latitude pieces per row: at most pi / 64 wide, each integrated with this many Gauss-Legendre
// nodes (degree 11: the integrands are polynomials of degree <= 5 in sin t and cos t).
constexpr double kMaxPiece = kPi / 64.0;
constexpr int kGaussNodes = 6;
// Rows are summed in this many fixed chunks, then the chunks in order: the result does not depend
// on how many threads ran them.
constexpr int kChunks = 16;
// Below this many pixels one thread does it all.
constexpr size_t kThreadedPixels = size_t(1) << 19;

// Gauss-Legendre nodes and weights on [-1, 1] (Abramowitz & Stegun, table 25.4, n = 6).
constexpr std::array<double, kGaussNodes> kGaussX = {-0.9324695142031521, -0.6612093864662645, -0.2386191860831969,
                                                     0.2386191860831969,  0.6612093864662645,  0.9324695142031521};
constexpr std::array<double, kGaussNodes> kGaussW = {0.1713244923791704, 0.3607615730481386, 0.4679139345726910,
                                                     0.4679139345726910, 0.3607615730481386, 0.1713244923791704};

// The real SH basis of docs/CONVENTIONS.md (without the Condon-Shortley phase) at the unit
// direction (x, y, z), bands 0..order-1, index l (l + 1) + m.
void sh_basis(int order, double x, double y, double z, double* out) {
  const double x2 = x * x, y2 = y * y, z2 = z * z, ip = 1.0 / kPi;
  out[0] = 0.5 * std::sqrt(ip);
  if (order < 2) return;
  out[1] = std::sqrt(0.75 * ip) * y;
  out[2] = std::sqrt(0.75 * ip) * z;
  out[3] = std::sqrt(0.75 * ip) * x;
  if (order < 3) return;
  out[4] = 0.5 * std::sqrt(15.0 * ip) * x * y;
  out[5] = 0.5 * std::sqrt(15.0 * ip) * y * z;
  out[6] = 0.25 * std::sqrt(5.0 * ip) * (3.0 * z2 - 1.0);
  out[7] = 0.5 * std::sqrt(15.0 * ip) * x * z;
  out[8] = 0.25 * std::sqrt(15.0 * ip) * (x2 - y2);
  if (order < 4) return;
  out[9] = 0.25 * std::sqrt(17.5 * ip) * y * (3.0 * x2 - y2);
  out[10] = 0.5 * std::sqrt(105.0 * ip) * x * y * z;
  out[11] = 0.25 * std::sqrt(10.5 * ip) * y * (5.0 * z2 - 1.0);
  out[12] = 0.25 * std::sqrt(7.0 * ip) * z * (5.0 * z2 - 3.0);
  out[13] = 0.25 * std::sqrt(10.5 * ip) * x * (5.0 * z2 - 1.0);
  out[14] = 0.25 * std::sqrt(105.0 * ip) * z * (x2 - y2);
  out[15] = 0.25 * std::sqrt(17.5 * ip) * x * (x2 - 3.0 * y2);
  if (order < 5) return;
  out[16] = 0.75 * std::sqrt(35.0 * ip) * x * y * (x2 - y2);
  out[17] = 0.75 * std::sqrt(17.5 * ip) * y * z * (3.0 * x2 - y2);
  out[18] = 0.75 * std::sqrt(5.0 * ip) * x * y * (7.0 * z2 - 1.0);
  out[19] = 0.75 * std::sqrt(2.5 * ip) * y * z * (7.0 * z2 - 3.0);
  out[20] = (3.0 / 16.0) * std::sqrt(ip) * (35.0 * z2 * z2 - 30.0 * z2 + 3.0);
  out[21] = 0.75 * std::sqrt(2.5 * ip) * x * z * (7.0 * z2 - 3.0);
  out[22] = (3.0 / 8.0) * std::sqrt(5.0 * ip) * (x2 - y2) * (7.0 * z2 - 1.0);
  out[23] = 0.75 * std::sqrt(17.5 * ip) * x * z * (x2 - 3.0 * y2);
  out[24] = (3.0 / 16.0) * std::sqrt(35.0 * ip) * (x2 * (x2 - 3.0 * y2) - y2 * (3.0 * x2 - y2));
}

// Runs body(chunk) for chunk = 0..kChunks-1 on up to hardware_concurrency threads.
template <typename Body>
void for_chunks(bool threaded, Body body) {
  const unsigned threads = threaded ? std::clamp(std::thread::hardware_concurrency(), 1u, unsigned(kChunks)) : 1u;
  if (threads == 1) {
    for (int c = 0; c < kChunks; ++c) body(c);
    return;
  }
  std::vector<std::thread> pool;
  for (unsigned t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      for (int c = int(t); c < kChunks; c += int(threads)) body(c);
    });
  for (auto& th : pool) th.join();
}

// The weights of harmonic m for every basis function k over a row of latitudes [t0, t1]:
// a[k][m] = int A_km(t) cos t dt and b[k][m] = int B_km(t) cos t dt.
void row_weights(int order, double t0, double t1, double (&a)[kMaxBasis][kMaxHarmonic + 1],
                 double (&b)[kMaxBasis][kMaxHarmonic + 1]) {
  const int n_basis = order * order, harmonics = order - 1, samples = 2 * harmonics + 1;
  for (int k = 0; k < n_basis; ++k)
    for (int m = 0; m <= harmonics; ++m) a[k][m] = b[k][m] = 0.0;
  const int pieces = std::max(1, int(std::ceil((t1 - t0) / kMaxPiece)));
  const double piece = (t1 - t0) / pieces;
  double y[kMaxBasis];
  for (int p = 0; p < pieces; ++p) {
    const double lo = t0 + p * piece;
    for (int g = 0; g < kGaussNodes; ++g) {
      const double t = lo + 0.5 * piece * (kGaussX[size_t(g)] + 1.0);
      const double w = 0.5 * piece * kGaussW[size_t(g)] * std::cos(t);
      for (int n = 0; n < samples; ++n) {
        const double phi = 2.0 * kPi * n / samples;
        sh_basis(order, std::sin(phi) * std::cos(t), std::sin(t), std::cos(phi) * std::cos(t), y);
        for (int m = 0; m <= harmonics; ++m) {
          // exact Fourier coefficients of a trigonometric polynomial of degree <= harmonics
          const double c = (m == 0 ? 1.0 : 2.0) / samples * std::cos(m * phi);
          const double s = 2.0 / samples * std::sin(m * phi);
          for (int k = 0; k < n_basis; ++k) {
            a[k][m] += w * c * y[k];
            b[k][m] += w * s * y[k];
          }
        }
      }
    }
  }
}

std::vector<double> project_equirect(const EnvImage& env, int order) {
  const int w = env.width, h = env.height, n_basis = order * order, harmonics = order - 1;
  // Column x spans u in [x / w, (x + 1) / w], phi = 2 pi (0.5 - u) (docs/CONVENTIONS.md): the
  // closed-form integrals of cos(m phi) and sin(m phi) over it, as
  // sin(m phi1) - sin(m phi0) = 2 cos(m mid) sin(m half) (no cancellation for narrow columns).
  const size_t stride = size_t(2 * harmonics + 1);
  std::vector<double> columns(size_t(w) * stride);
  for (int x = 0; x < w; ++x) {
    const double phi1 = 2.0 * kPi * (0.5 - double(x) / w), phi0 = 2.0 * kPi * (0.5 - double(x + 1) / w);
    const double mid = 0.5 * (phi0 + phi1), half = 0.5 * (phi1 - phi0);
    double* f = &columns[size_t(x) * stride];
    f[0] = phi1 - phi0;
    for (int m = 1; m <= harmonics; ++m) {
      f[2 * m - 1] = 2.0 * std::cos(m * mid) * std::sin(m * half) / m;  // int cos(m phi)
      f[2 * m] = 2.0 * std::sin(m * mid) * std::sin(m * half) / m;      // int sin(m phi)
    }
  }
  std::vector<std::vector<double>> partial(kChunks, std::vector<double>(3 * size_t(n_basis), 0.0));
  for_chunks(size_t(w) * size_t(h) >= kThreadedPixels, [&](int chunk) {
    std::vector<double>& out = partial[size_t(chunk)];
    double a[kMaxBasis][kMaxHarmonic + 1], b[kMaxBasis][kMaxHarmonic + 1];
    std::vector<double> sums(3 * stride);
    for (int y = chunk * h / kChunks; y < (chunk + 1) * h / kChunks; ++y) {
      // Row y spans v in [y / h, (y + 1) / h], latitude t = pi (0.5 - v).
      row_weights(order, kPi * (0.5 - double(y + 1) / h), kPi * (0.5 - double(y) / h), a, b);
      std::fill(sums.begin(), sums.end(), 0.0);
      const float* row = &env.rgb[3 * size_t(y) * size_t(w)];
      for (size_t x = 0; x < size_t(w); ++x) {
        const double* f = &columns[x * stride];
        const double r = row[3 * x], g = row[3 * x + 1], bl = row[3 * x + 2];
        for (size_t j = 0; j < stride; ++j) {
          sums[3 * j] += r * f[j];
          sums[3 * j + 1] += g * f[j];
          sums[3 * j + 2] += bl * f[j];
        }
      }
      for (int k = 0; k < n_basis; ++k)
        for (size_t c = 0; c < 3; ++c) {
          double v = a[k][0] * sums[c];
          for (int m = 1; m <= harmonics; ++m)
            v += a[k][m] * sums[3 * size_t(2 * m - 1) + c] + b[k][m] * sums[3 * size_t(2 * m) + c];
          out[3 * size_t(k) + c] += v;
        }
    }
  });
  std::vector<double> total(3 * size_t(n_basis), 0.0);
  for (const auto& p : partial)
    for (size_t i = 0; i < total.size(); ++i) total[i] += p[i];
  return total;
}

std::vector<double> project_cube(const EnvImage& env, int order) {
  const int s = env.width, n_basis = order * order;
  std::vector<double> omega(size_t(s) * size_t(s));
  for (int j = 0; j < s; ++j)
    for (int i = 0; i < s; ++i) omega[size_t(j) * size_t(s) + size_t(i)] = math::cube_texel_solid_angle(s, i, j);
  std::vector<double> total(3 * size_t(n_basis), 0.0);
  double y[kMaxBasis];
  for (int f = 0; f < 6; ++f)
    for (int j = 0; j < s; ++j)
      for (int i = 0; i < s; ++i) {
        const auto d = math::cube_texel_direction(f, s, i, j);
        sh_basis(order, d.x, d.y, d.z, y);
        const double o = omega[size_t(j) * size_t(s) + size_t(i)];
        const float* l = &env.rgb[3 * ((size_t(f) * size_t(s) + size_t(j)) * size_t(s) + size_t(i))];
        for (int k = 0; k < n_basis; ++k)
          for (size_t c = 0; c < 3; ++c) total[3 * size_t(k) + c] += double(l[c]) * y[k] * o;
      }
  return total;
}

}  // namespace

ShCoefficients project_sh(const EnvImage& env, int order, ShWindow window) {
  if (order != 3 && order != 5)
    throw Error("SH order must be 3 (9 coefficients) or 5 (25), not " + std::to_string(order));
  const bool cube = env.layout == EnvImage::Layout::Cube;
  const size_t texels = cube ? 6u * size_t(env.width) * size_t(env.width) : size_t(env.width) * size_t(env.height);
  if (env.width < 1 || env.height < 1 || (cube && env.width != env.height) || env.rgb.size() != 3 * texels)
    throw Error("SH projection: environment '" + env.source + "' holds " + std::to_string(env.rgb.size()) +
                " values for its " + std::to_string(env.width) + "x" + std::to_string(env.height) + " layout");
  ShCoefficients sh;
  sh.order = order;
  sh.radiance = cube ? project_cube(env, order) : project_equirect(env, order);
  apply_sh_window(sh, window);
  sh.projection = cube ? "the " + std::to_string(env.width) +
                             "^2 cube's texels at their centres, each with its "
                             "exact solid angle, in double precision on the host"
                       : "exact integral of the " + std::to_string(env.width) + "x" + std::to_string(env.height) +
                             " equirect's pixels (each constant over its cell) against the basis, in double "
                             "precision on the host";
  return sh;
}

}  // namespace brdfbake
