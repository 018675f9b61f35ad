// SH windows: the fixed ones (Sloan 2008, "Stupid Spherical Harmonics (SH) Tricks", "Windowing") and
// the deringing window that cmgen applies by default (`--sh-window auto`), chosen from the data.
//
// cmgen's automatic window (Filament's libs/ibl, described in Sloan 2017, "Deringing Spherical
// Harmonics"): band l is weighted by sinc(pi l / w)^4 (0 from l >= w on), where the cutoff w, in
// bands, is searched by bisection between `order` and 4 order + 1, one colour channel after the
// other (each search starting from the cutoff the previous channels allowed), at most 16 halvings
// and until the interval is under 0.1 band: the widest cutoff for which the windowed irradiance is
// nowhere negative. We rebuild that search as described, so that a Filament user who swaps cmgen for
// brdfbake gets the same coefficients. "Nowhere negative" is decided as cmgen decides it, for 3
// bands: with Sloan's estimate of the minimum (sh_minimum_estimate below), which treats the band-2
// terms around the linear part's axis each at its own worst phase, and so calls some functions
// negative that are not (on studio_small_03 the exact minimum would allow a cutoff of 12.8 bands,
// cmgen's estimate allows 7.8: the estimate is what makes the look). For 5 bands, which cmgen does not
// window automatically, the exact minimum is used (sh_minimum: a dense near-uniform set of
// directions, then a local refinement of the lowest ones).
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/sh.hpp"
#include "families/irradiance/model.hpp"

namespace brdfbake {
namespace {

using math::kPi;

// Directions of the first search: a spherical Fibonacci set, ~0.06 rad apart. The refinement then
// walks from the lowest of them, so the minimum is found to ~1e-9 rad whatever the spacing.
constexpr int kProbeDirections = 4096;
constexpr int kRefinedStarts = 8;

Vec3 from_angles(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

double sh_value(const std::vector<double>& c, int order, const Vec3& d) {
  const std::vector<double> y = math::sh_basis(order, d);
  double v = 0.0;
  for (size_t k = 0; k < c.size(); ++k) v += c[k] * y[k];
  return v;
}

struct Probe {
  std::vector<std::array<double, 2>> angles;  // theta, phi
  std::vector<double> basis;                  // order^2 values per direction
};

// The directions and their basis values per order, made once (a thread-safe static).
const Probe& probe(int order) {
  static const std::array<Probe, math::kMaxShOrder + 1> probes = [] {
    std::array<Probe, math::kMaxShOrder + 1> all;
    const double golden = kPi * (3.0 - std::sqrt(5.0));
    for (int o = 1; o <= math::kMaxShOrder; ++o)
      for (int i = 0; i < kProbeDirections; ++i) {
        const double z = 1.0 - (2.0 * i + 1.0) / kProbeDirections;
        const double theta = std::acos(z), phi = std::fmod(golden * i, 2.0 * kPi);
        all[size_t(o)].angles.push_back({theta, phi});
        const std::vector<double> y = math::sh_basis(o, from_angles(theta, phi));
        all[size_t(o)].basis.insert(all[size_t(o)].basis.end(), y.begin(), y.end());
      }
    return all;
  }();
  return probes[size_t(order)];
}

}  // namespace

double sh_minimum(const std::vector<double>& coefficients, int order) {
  const Probe& p = probe(order);
  const size_t n = size_t(order) * size_t(order);
  std::vector<std::pair<double, size_t>> values(p.angles.size());
  for (size_t i = 0; i < p.angles.size(); ++i) {
    double v = 0.0;
    for (size_t k = 0; k < n; ++k) v += coefficients[k] * p.basis[i * n + k];
    values[i] = {v, i};
  }
  std::partial_sort(values.begin(), values.begin() + kRefinedStarts, values.end());
  double lowest = values[0].first;
  // Compass search in (theta, phi) from each of the lowest directions: the function is smooth (a
  // polynomial of degree order - 1 on the sphere), so halving the step on failure converges to the
  // local minimum the start lies in; the starts are closer than any two minima of a few bands.
  for (int s = 0; s < kRefinedStarts; ++s) {
    double theta = p.angles[values[size_t(s)].second][0], phi = p.angles[values[size_t(s)].second][1];
    double best = values[size_t(s)].first;
    for (double step = 0.05; step > 1e-9;) {
      bool moved = false;
      for (const auto& [dt, dp] :
           std::array<std::array<double, 2>, 4>{{{step, 0}, {-step, 0}, {0, step}, {0, -step}}}) {
        const double v = sh_value(coefficients, order, from_angles(theta + dt, phi + dp));
        if (v < best) {
          best = v, theta += dt, phi += dp, moved = true;
          break;
        }
      }
      if (!moved) step *= 0.5;
    }
    lowest = std::min(lowest, best);
  }
  return lowest;
}

// Sloan 2017, "Deringing Spherical Harmonics", sec. 4 (as cmgen's CubemapSH::windowSH applies it):
// in a frame whose z axis is the linear part's direction u, a 3-band function is
//   f = k0 + b z + s (3 z^2 - 1) / 2 + D z sin(theta) cos(phi - phi1) + r sin^2(theta) cos(2 phi - phi2),
// with b = |linear part|, s = u^T S u, D and r the amplitudes of band 2's |m| = 1 and |m| = 2 parts
// about u (S the traceless matrix of band 2: Q(n) = n^T S n). The estimate takes the |m| = 2 part at
// its worst phase, -r (1 - z^2), which makes the rest a quadratic in z, a z^2 + b z + c; if that
// minus D / 2 (the |m| = 1 part's lowest value) may be negative, it minimises
// a z^2 + b z + c + D z sqrt(1 - z^2) by Newton's method from z = -1/sqrt(2), ending where a step is
// under 1e-5 or z leaves [-1, 1] (then the ends decide).
double sh_minimum_estimate(const std::vector<double>& c) {
  const double ip = 1.0 / kPi;
  const double k0 = 0.5 * std::sqrt(ip), k1 = std::sqrt(0.75 * ip);
  const double q1 = 0.5 * std::sqrt(15.0 * ip), q2 = 0.25 * std::sqrt(5.0 * ip), q3 = 0.25 * std::sqrt(15.0 * ip);
  // linear part L . n, L in (x, y, z)
  const double lx = k1 * c[3], ly = k1 * c[1], lz = k1 * c[2];
  const double b = std::sqrt(lx * lx + ly * ly + lz * lz);
  Vec3 u = b > 0.0 ? Vec3{lx / b, ly / b, lz / b} : Vec3{0.0, 0.0, 1.0};
  // band 2 as n^T S n on the unit sphere (3 z^2 - 1 = 2 z^2 - x^2 - y^2 there)
  const double S[3][3] = {{-q2 * c[6] + q3 * c[8], 0.5 * q1 * c[4], 0.5 * q1 * c[7]},
                          {0.5 * q1 * c[4], -q2 * c[6] - q3 * c[8], 0.5 * q1 * c[5]},
                          {0.5 * q1 * c[7], 0.5 * q1 * c[5], 2.0 * q2 * c[6]}};
  const double uv[3] = {u.x, u.y, u.z};
  double su[3] = {0, 0, 0};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) su[i] += S[i][j] * uv[j];
  const double s = su[0] * uv[0] + su[1] * uv[1] + su[2] * uv[2];
  // |m| = 1: 2 z sin(theta) (e . S u) over unit e in the plane: amplitude 2 |S u - s u|
  double perp2 = 0.0;
  for (int i = 0; i < 3; ++i) perp2 += (su[i] - s * uv[i]) * (su[i] - s * uv[i]);
  const double D = 2.0 * std::sqrt(perp2);
  // |m| = 2: the plane block of S has eigenvalues -s/2 +- r (S is traceless)
  const Vec3 helper = std::fabs(u.z) < 0.9 ? Vec3{0, 0, 1} : Vec3{1, 0, 0};
  Vec3 e1{helper.y * u.z - helper.z * u.y, helper.z * u.x - helper.x * u.z, helper.x * u.y - helper.y * u.x};
  const double n1 = std::sqrt(math::dot(e1, e1));
  e1 = {e1.x / n1, e1.y / n1, e1.z / n1};
  const Vec3 e2{u.y * e1.z - u.z * e1.y, u.z * e1.x - u.x * e1.z, u.x * e1.y - u.y * e1.x};
  auto quad = [&](const Vec3& p, const Vec3& q) {
    const double pv[3] = {p.x, p.y, p.z}, qv[3] = {q.x, q.y, q.z};
    double t = 0.0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) t += pv[i] * S[i][j] * qv[j];
    return t;
  };
  const double p11 = quad(e1, e1), p22 = quad(e2, e2), p12 = quad(e1, e2);
  const double r = std::sqrt(0.25 * (p11 - p22) * (p11 - p22) + p12 * p12);

  const double a = 1.5 * s + r;
  const double cc = k0 * c[0] - 0.5 * s - r;
  const double zq = -b / (2.0 * a);
  const double ends = std::min(a + b + cc, a - b + cc);
  const double zonal_min = (a > 0.0 && zq >= -1.0 && zq <= 1.0) ? a * zq * zq + b * zq + cc : ends;
  double minimum = zonal_min - 0.5 * D;
  if (minimum >= 0.0) return minimum;
  auto f = [&](double z) { return a * z * z + b * z + cc + D * z * std::sqrt(1.0 - z * z); };
  auto f1 = [&](double z) { return 2.0 * a * z + b + D * (1.0 - 2.0 * z * z) / std::sqrt(1.0 - z * z); };
  auto f2 = [&](double z) { return 2.0 * a + D * z * (2.0 * z * z - 3.0) / std::pow(1.0 - z * z, 1.5); };
  double z = -std::sqrt(0.5), dz = 0.0;
  do {
    minimum = f(z);
    dz = f1(z) / f2(z);
    z -= dz;
  } while (std::fabs(z) <= 1.0 && std::fabs(dz) > 1e-5);
  if (std::fabs(z) > 1.0) minimum = std::min(f(1.0), f(-1.0));
  return minimum;
}

std::vector<double> sh_sinc4_window_weights(double cutoff, int order) {
  std::vector<double> w(size_t(order), 1.0);
  for (int l = 1; l < order; ++l) {
    if (l >= cutoff) {
      w[size_t(l)] = 0.0;
      continue;
    }
    const double x = kPi * l / cutoff;
    w[size_t(l)] = std::pow(std::sin(x) / x, 4);
  }
  return w;
}

double sh_auto_window_cutoff(const std::vector<double>& irradiance, int order) {
  const size_t n = size_t(order) * size_t(order);
  if (irradiance.size() != 3 * n)
    throw Error("SH window: " + std::to_string(irradiance.size()) + " coefficients for order " + std::to_string(order));
  double cutoff = 4.0 * order + 1.0;
  for (size_t c = 0; c < 3; ++c) {
    std::vector<double> channel(n);
    for (size_t k = 0; k < n; ++k) channel[k] = irradiance[3 * k + c];
    double lo = order, hi = cutoff;
    for (int i = 0; i < 16 && lo + 0.1 < hi; ++i) {
      const double mid = 0.5 * (lo + hi);
      const std::vector<double> w = sh_sinc4_window_weights(mid, order);
      std::vector<double> windowed = channel;
      for (int l = 0; l < order; ++l)
        for (int m = -l; m <= l; ++m) windowed[size_t(math::sh_index(l, m))] *= w[size_t(l)];
      const double lowest = order == 3 ? sh_minimum_estimate(windowed) : sh_minimum(windowed, order);
      if (lowest < 0.0)
        hi = mid;
      else
        lo = mid;
    }
    cutoff = std::min(cutoff, lo);
  }
  return cutoff;
}

ShWindow sh_window_from_name(const std::string& n) {
  return detail::enum_from_name(detail::kShWindowNames, n, "SH window");
}

const char* sh_window_name(ShWindow w) { return detail::enum_name(detail::kShWindowNames, w); }

// The fixed windows, with the band count `order` as the window width.
std::vector<double> sh_window_weights(ShWindow w, int order) {
  if (w == ShWindow::Auto) throw Error("the auto SH window depends on the coefficients (apply_sh_window)");
  std::vector<double> out(size_t(order), 1.0);
  for (int l = 1; l < order; ++l) {
    const double x = static_cast<double>(l) / order;
    if (w == ShWindow::Hanning) out[size_t(l)] = 0.5 * (1.0 + std::cos(kPi * x));
    if (w == ShWindow::Lanczos) out[size_t(l)] = std::sin(kPi * x) / (kPi * x);
  }
  return out;
}

void apply_sh_window(ShCoefficients& sh, ShWindow window) {
  const int order = sh.order;
  sh.window = window;
  sh.irradiance_over_pi.assign(sh.radiance.size(), 0.0);
  for (int l = 0; l < order; ++l)
    for (int m = -l; m <= l; ++m) {
      const size_t k = size_t(math::sh_index(l, m));
      for (size_t c = 0; c < 3; ++c)
        sh.irradiance_over_pi[3 * k + c] = sh.radiance[3 * k + c] * math::sh_cosine_lobe(l) / kPi;
    }
  sh.window_cutoff = 0.0;
  if (window == ShWindow::Auto) {
    sh.window_cutoff = sh_auto_window_cutoff(sh.irradiance_over_pi, order);
    sh.window_weights = sh_sinc4_window_weights(sh.window_cutoff, order);
  } else {
    sh.window_weights = sh_window_weights(window, order);
  }
  for (int l = 0; l < order; ++l)
    for (int m = -l; m <= l; ++m) {
      const size_t k = size_t(math::sh_index(l, m));
      for (size_t c = 0; c < 3; ++c) sh.irradiance_over_pi[3 * k + c] *= sh.window_weights[size_t(l)];
    }
}

}  // namespace brdfbake
