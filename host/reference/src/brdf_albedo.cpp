// Integrals of the reference BRDF models: the directional albedo of any model, and the sheen albedo
// E(x) that KHR_materials_sheen's albedo scaling needs.
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "brdf_internal.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/reference/brdf.hpp"
#include "brdfbake/reference/charlie.hpp"
#include "brdfbake/reference/dfg_lut.hpp"
#include "brdfbake/reference/ggx.hpp"
#include "brdfbake/reference/quadrature.hpp"

namespace brdfbake::reference {
namespace {

using brdfbake::math::kPi;

// ---------------------------------------------------------------------------------------------
// Sheen albedo E(mu).
//
// charlie_albedo is a converged 2-D quadrature (~1-3 ms a call); the glTF model needs E at both
// cosines of every evaluation. So E is represented, per sheen roughness, by Chebyshev series of
// order kSheenSeriesOrder on panels of a variable in which E is smooth (brdf.hpp, SheenAlbedoSeries):
//   - mu < 1/2: w = ln(mu) on [ln 1e-7, ln 1/2]. E grows like 1/mu as mu -> 0, which is analytic in
//     w, and the fitted Lambda's x^c at x -> 0 is e^(c w).
//   - mu >= 1/2: s = (1 - mu)^c on [0, (1/2)^c]: the fit mirrors Lambda about 1/2 as
//     exp(2 L(1/2) - L(1 - mu)), L(x) = a / (1 + b x^c) + d x + e, which is smooth in s (x = s^(1/c)
//     with 1/c > 5), not in mu. The split at 1/2 is also the fit's C1 seam.
// The coefficients come from converged charlie_albedo values at the Chebyshev points of the first
// kind (c_k = (2/N) sum_j f_j cos(k (2j + 1) pi / 2N), Trefethen, "Approximation Theory and
// Approximation Practice", ch. 3); E is summed by Clenshaw's recurrence. tests/reference measures
// the series against charlie_albedo at a finer quadrature.
// The upper panels' nodes take charlie_albedo at refinement 2: at the default resolution the nodes
// within ~1e-6 of mu = 1 (v at the normal, where Lambda's cusp at l = n meets the lobe) are off by
// up to 4.4e-9 (sheen roughness 1; 2e-9 at 0.5), which the series carries to E(1) and the glTF sheen's
// albedo scaling to f; at refinement 2 the nodes are within 1.1e-10 (against an independent
// quadrature over l, host/src/families/brdf_eval/sheen_albedo.cpp), at 2.5 times the cost of those 64 nodes. The lower
// panels' nodes are within 1e-9 relative at the default (measured at sheen roughness 0 to 1).
// ---------------------------------------------------------------------------------------------
constexpr Quadrature kSheenUpperQuadrature{10, 2};

SheenAlbedoSeries make_sheen_series(double sheen_roughness) {
  SheenAlbedoSeries s;
  s.exponent = SheenFitExponent(sheen_roughness * sheen_roughness);
  s.w_low = std::log(kBrdfMinCosine);
  s.w_seam = std::log(0.5);
  s.s_seam = std::pow(0.5, s.exponent);
  const int n = kSheenSeriesOrder;
  std::vector<double> x(static_cast<size_t>(n)), f(static_cast<size_t>(n));
  for (int j = 0; j < n; ++j) x[size_t(j)] = std::cos((2.0 * j + 1.0) * kPi / (2.0 * n));
  auto panel = [&](double a, double b, bool upper) {
    for (int j = 0; j < n; ++j) {
      const double y = 0.5 * (a + b) + 0.5 * (b - a) * x[size_t(j)];
      const double mu = upper ? 1.0 - std::pow(y, 1.0 / s.exponent) : std::exp(y);
      f[size_t(j)] = charlie_albedo(mu, sheen_roughness, SheenVisibility::EstevezKulla,
                                    upper ? kSheenUpperQuadrature : Quadrature{});
    }
    for (int k = 0; k < n; ++k) {
      double c = 0.0;
      for (int j = 0; j < n; ++j) c += f[size_t(j)] * std::cos(k * (2.0 * j + 1.0) * kPi / (2.0 * n));
      c *= 2.0 / n;
      s.coefficients.push_back(k == 0 ? 0.5 * c : c);
    }
  };
  for (int p = 0; p < kSheenLowerPanels; ++p)
    panel(s.w_low + (s.w_seam - s.w_low) * p / kSheenLowerPanels,
          s.w_low + (s.w_seam - s.w_low) * (p + 1) / kSheenLowerPanels, false);
  for (int p = 0; p < kSheenUpperPanels; ++p)
    panel(s.s_seam * p / kSheenUpperPanels, s.s_seam * (p + 1) / kSheenUpperPanels, true);
  return s;
}

// Clenshaw's recurrence for sum_k c_k T_k(x) (c_0 already halved).
double clenshaw(const double* c, int n, double x) {
  double b1 = 0.0, b2 = 0.0;
  for (int k = n - 1; k >= 1; --k) {
    const double b0 = c[k] + 2.0 * x * b1 - b2;
    b2 = b1;
    b1 = b0;
  }
  return c[0] + x * b1 - b2;
}

// ---------------------------------------------------------------------------------------------
// Directional albedo.
//
// Over the half vector h = (sin t cos p, sin t sin p, cos t): l = 2 (v.h) h - v, dl = 4 (v.h) dh
// (Walter et al. 2007, the reflection Jacobian), dh = sin t dt dp, so
//   a(v) = integral of f(l, v) (n.l) 4 (v.h) sin t dt dp   over the h whose l is above the horizon.
// With v = (sin_v, 0, n.v): n.l = A + B cos p, A = n.v cos 2t, B = sin_v sin 2t, so
// A - B = cos(2t + theta_v) and A + B = cos(2t - theta_v): every p is valid for
// t < t1 = pi/4 - theta_v/2, none beyond t2 = pi/4 + theta_v/2, and |p| < acos(-A/B) in between.
// Every model is even in p (v lies in the xz plane; Disney's anisotropy depends on (h.y)^2, (l.y)^2),
// so p runs over [0, p_e] and the result is doubled.
// Between t1 and t2 the p-range shrinks like sqrt(t - t1) and sqrt(t2 - t): t = t1 + (t2 - t1)
// (1 - cos(pi x)) / 2 flattens both ends. Narrow lobes sit at t ~ alpha: the initial t panels are
// graded geometrically (ratio 3) from 1e-3 alpha up. Then every panel is bisected until an 8-point
// Gauss-Legendre rule on it agrees with the rule on its two halves (per channel, absolute).
// ---------------------------------------------------------------------------------------------
constexpr int kGaussOrder = 8;
constexpr int kMaxDepth = 40;
constexpr double kGradingRatio = 3.0;
constexpr double kGradingStart = 1e-3;  // the first break point, in units of the narrowest lobe width
constexpr int kPhiInitialPanels = 8;

Rgb operator+(const Rgb& a, const Rgb& b) { return {a.r + b.r, a.g + b.g, a.b + b.b}; }
Rgb operator*(const Rgb& a, double s) { return {a.r * s, a.g * s, a.b * s}; }
double max_abs_diff(const Rgb& a, const Rgb& b) {
  return std::max(std::fabs(a.r - b.r), std::max(std::fabs(a.g - b.g), std::fabs(a.b - b.b)));
}

template <class F>
Rgb gauss(const F& f, double a, double b) {
  const GaussLegendreRule& rule = gauss_legendre(kGaussOrder);
  Rgb sum{0.0, 0.0, 0.0};
  const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
  for (size_t k = 0; k < rule.nodes.size(); ++k) sum = sum + f(mid + half * rule.nodes[k]) * rule.weights[k];
  return sum * half;
}

template <class F>
Rgb refine(const F& f, double a, double b, const Rgb& whole, double tol, int depth) {
  const double m = 0.5 * (a + b);
  const Rgb left = gauss(f, a, m), right = gauss(f, m, b);
  const Rgb sum = left + right;
  if (depth == 0 || max_abs_diff(sum, whole) <= tol) return sum;
  const double sub = tol / std::sqrt(2.0);
  return refine(f, a, m, left, sub, depth - 1) + refine(f, m, b, right, sub, depth - 1);
}

// Adaptive integral of f over the panels between consecutive `breaks`, `tol` for the whole.
template <class F>
Rgb adaptive(const F& f, const std::vector<double>& breaks, double tol) {
  Rgb sum{0.0, 0.0, 0.0};
  const double panel_tol = tol / std::sqrt(static_cast<double>(std::max<size_t>(1, breaks.size() - 1)));
  for (size_t k = 0; k + 1 < breaks.size(); ++k) {
    const double a = breaks[k], b = breaks[k + 1];
    if (!(b > a)) continue;
    sum = sum + refine(f, a, b, gauss(f, a, b), panel_tol, kMaxDepth);
  }
  return sum;
}

// The narrowest feature of the model's lobes, in radians of the half vector's polar angle.
double narrowest_lobe(BrdfModel model, const BrdfMaterial& m) {
  const double r2 = std::max(m.roughness * m.roughness, kMinAlpha);
  switch (model) {
    case BrdfModel::Disney: {
      const double aspect = std::sqrt(1.0 - 0.9 * m.anisotropic);
      double w = std::max(kDisneyMinAlpha, std::min(r2 * aspect, r2 / aspect));
      if (m.clearcoat > 0.0) w = std::min(w, 0.1 + (0.001 - 0.1) * m.clearcoat_gloss);
      return w;
    }
    case BrdfModel::Gltf:
    case BrdfModel::GltfCorrelated: {
      double w = r2;
      if (m.clearcoat > 0.0) w = std::min(w, std::max(m.clearcoat_roughness * m.clearcoat_roughness, kMinAlpha));
      return w;
    }
    case BrdfModel::CookTorrance:
      return r2;
    case BrdfModel::Phong:
    case BrdfModel::BlinnPhong:
      return 1.0 / std::sqrt(classic_shininess(m) + 1.0);
    case BrdfModel::BlinnPhongFromPbr:
      return 1.0 / std::sqrt(std::pow(2048.0, 1.0 - m.roughness) + 1.0);
    case BrdfModel::Lambert:
      break;
  }
  return 1.0;
}

}  // namespace

const SheenAlbedoSeries& sheen_albedo_series(double sheen_roughness) {
  if (!(sheen_roughness >= 0.0 && sheen_roughness <= 1.0))
    throw std::invalid_argument("sheen_albedo_series: sheen_roughness must be in [0, 1]");
  static std::mutex mutex;
  static std::map<double, std::unique_ptr<const SheenAlbedoSeries>> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  auto& slot = cache[sheen_roughness];
  if (!slot) slot = std::make_unique<const SheenAlbedoSeries>(make_sheen_series(sheen_roughness));
  return *slot;
}

double sheen_albedo(double n_dot_x, double sheen_roughness) {
  if (std::isnan(n_dot_x)) throw std::invalid_argument("sheen_albedo: n_dot_x is NaN");
  const SheenAlbedoSeries& s = sheen_albedo_series(sheen_roughness);
  const double mu = std::clamp(n_dot_x, kBrdfMinCosine, 1.0);
  double t = 0.0;
  int p = 0;
  if (mu < 0.5) {
    t = (std::log(mu) - s.w_low) / (s.w_seam - s.w_low) * kSheenLowerPanels;
    p = std::clamp(static_cast<int>(t), 0, kSheenLowerPanels - 1);
  } else {
    t = std::pow(1.0 - mu, s.exponent) / s.s_seam * kSheenUpperPanels;
    p = std::clamp(static_cast<int>(t), 0, kSheenUpperPanels - 1);
    t -= p;
    p += kSheenLowerPanels;
    t += p;
  }
  const double x = std::clamp(2.0 * (t - p) - 1.0, -1.0, 1.0);
  return clenshaw(s.coefficients.data() + static_cast<size_t>(p) * kSheenSeriesOrder, kSheenSeriesOrder, x);
}

Rgb directional_albedo(BrdfModel model, const BrdfMaterial& m, double theta_o, double tolerance) {
  if (!(theta_o >= 0.0 && theta_o < 0.5 * kPi))
    throw std::invalid_argument("directional_albedo: theta_o must be in [0, pi/2) (got " + std::to_string(theta_o) +
                                ")");
  if (!(tolerance > 0.0)) throw std::invalid_argument("directional_albedo: tolerance must be positive");
  const double nv = std::cos(theta_o), sv = std::sin(theta_o);
  const Vec3 v{sv, 0.0, nv};
  const double t1 = 0.25 * kPi - 0.5 * theta_o, t2 = 0.25 * kPi + 0.5 * theta_o;

  // f(l, v) (n.l) 4 (v.h) sin t at the half vector (t, p).
  auto integrand = [&](double t, double p) -> Rgb {
    const double st = std::sin(t), ct = std::cos(t);
    BrdfGeometry g{};
    g.h = Vec3{st * std::cos(p), st * std::sin(p), ct};
    const double vh = v.x * g.h.x + v.z * g.h.z;
    g.l = Vec3{2.0 * vh * g.h.x - v.x, 2.0 * vh * g.h.y, 2.0 * vh * g.h.z - v.z};
    if (!(g.l.z > 0.0) || !(vh > 0.0)) return Rgb{0.0, 0.0, 0.0};
    g.v = v;
    g.nl = std::max(g.l.z, kBrdfMinCosine);
    g.nv = std::max(nv, kBrdfMinCosine);
    g.nh = ct;
    g.lh = std::min(vh, 1.0);
    return brdf_at(model, m, g) * (g.l.z * 4.0 * vh * st);
  };

  const double inner_tol = 0.1 * tolerance / (0.5 * kPi);
  // The p integral at polar angle t: [0, pi] below t1, [0, p_e] between t1 and t2.
  auto over_phi = [&](double t) -> Rgb {
    double p_end = kPi;
    if (t > t1) {
      const double a = nv * std::cos(2.0 * t), b = sv * std::sin(2.0 * t);
      if (!(b > 0.0) || a + b <= 0.0) return Rgb{0.0, 0.0, 0.0};
      p_end = std::acos(std::clamp(-a / b, -1.0, 1.0));
    }
    std::vector<double> breaks;
    for (int k = 0; k <= kPhiInitialPanels; ++k) breaks.push_back(p_end * k / kPhiInitialPanels);
    return adaptive([&](double p) { return integrand(t, p); }, breaks, inner_tol);
  };

  // Panel A: t in [0, t1], graded towards 0.
  const double start = kGradingStart * narrowest_lobe(model, m);
  std::vector<double> grading;
  for (double t = start; t < t2; t *= kGradingRatio) grading.push_back(t);
  std::vector<double> breaks_a{0.0};
  for (double t : grading)
    if (t < t1) breaks_a.push_back(t);
  breaks_a.push_back(t1);
  Rgb sum = adaptive(over_phi, breaks_a, 0.5 * tolerance);

  // Panel B: t = t1 + (t2 - t1) (1 - cos(pi x)) / 2, x in [0, 1], dt/dx = (t2 - t1) (pi / 2) sin(pi x).
  if (t2 > t1) {
    const double span = t2 - t1;
    std::vector<double> breaks_b{0.0};
    for (double t : grading)
      if (t > t1) breaks_b.push_back(std::acos(1.0 - 2.0 * (t - t1) / span) / kPi);
    breaks_b.push_back(1.0);
    for (int k = 1; k < kPhiInitialPanels; ++k) breaks_b.push_back(static_cast<double>(k) / kPhiInitialPanels);
    std::sort(breaks_b.begin(), breaks_b.end());
    auto over_x = [&](double x) -> Rgb {
      const double t = t1 + span * 0.5 * (1.0 - std::cos(kPi * x));
      return over_phi(t) * (span * 0.5 * kPi * std::sin(kPi * x));
    };
    sum = sum + adaptive(over_x, breaks_b, 0.5 * tolerance);
  }
  return sum * 2.0;
}

}  // namespace brdfbake::reference
