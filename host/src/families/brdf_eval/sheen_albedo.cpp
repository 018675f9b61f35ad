// KHR_materials_sheen's albedo E(mu) for the kernels (sheen_albedo.hpp).
#include "families/brdf_eval/sheen_albedo.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <map>
#include <mutex>
#include <vector>

#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/gauss_legendre.hpp"
#include "families/brdf_eval/model.hpp"

// The layout of the kernels' table.
#include "../../../../kernels/common/brdf_params.clh"

namespace brdfbake::detail {

EstevezKullaFit estevez_kulla_fit(double alpha) {
  const double t = (1.0 - alpha) * (1.0 - alpha);
  const auto mix = [t](double at_r1, double at_r0) { return at_r1 + (at_r0 - at_r1) * t; };
  return {mix(21.5473, 25.3245), mix(3.82987, 3.32435), mix(0.19823, 0.16801), mix(-1.97760, -1.27393),
          mix(-4.32054, -4.85967)};
}

namespace {

using math::kPi;

// ---------------------------------------------------------------------------------------------
// The integral, over the light direction l (not over the half vector, as the reference integrates).
//
// With x = n.l, phi the azimuth of l about n relative to v, and V (n.l) = 1 / (4 mu (1 + Lambda(mu)
// + Lambda(x))) (Estevez & Kulla's visibility with their fitted Lambda):
//   E(mu) = 1 / (4 mu) int_0^1 g(x) I(x) dx,  g = 1 / (1 + Lambda(mu) + Lambda(x)),
//   I(x) = int_0^2pi D(h) dphi = 4 int_0^(pi/2) D(h(psi)) dpsi,  psi = phi / 2.
// The visibility depends on x only, so its features are lines in x: Lambda is analytic in x^c (not x)
// at x -> 0 and in (1 - x)^c at x -> 1, with a C1 seam at 1/2. Hence the outer variable is t = ln x
// on (0, 1/2] and u = ln(1 - x) on [1/2, 1): Lambda is smooth in both (x^c = e^(c t)).
// D depends on both. With the polar angles tl of l and tv of v, P = sin tl sin tv,
// S = cos^2((tl + tv) / 2) and d = sin((tl - tv) / 2):
//   |l + v|^2 = 2 (1 + l.v) = 4 (S + P cos^2 psi),  (n.l + n.v)^2 = 4 S (1 - d^2),
//   cos^2(theta_h) = S (1 - d^2) / (S + P cos^2 psi),  sin^2(theta_h) = (S d^2 + P cos^2 psi) / (S + P cos^2 psi),
// so ln sin^2(theta_h) is formed without cancellation on both sides of 1/2 (log1p(-cos^2) where
// theta_h is large, where Charlie's lobe lives; the log of the ratio near the normal, where the mirror
// direction tl = tv, psi = pi/2 gives n.h = 1), and
//   D = (2 + 1/alpha) / (2 pi) exp(ln(sin^2 theta_h) / (2 alpha)).
// Both integrals are adaptive: a panel's 10-point Gauss-Legendre sum is accepted when it agrees with
// the sum over its two halves to the panel's share of the tolerance (1e-10 of the whole) or to 1e-12
// of itself (above the integrand's own rounding: the exponent 1 / (2 alpha), up to 5e6, turns a
// relative error of 1e-16 in sin^2 into up to ~1e-13 of D where D is representable), else both
// halves are refined. The outer panels break at the features: ln mu (where g switches on and the
// mirror direction passes), ln sqrt(alpha) (the width of the lobe's band in x), and every 8 units of
// t or u from 8 below ln mu (resp. 8 below 0); the lower tail below x = 1e-14 mu is dropped (the
// integrand is bounded there: less than 1e-14 of the whole).
// Against the reference's charlie_albedo at order 12 and refinement 2: 2e-12 relative above 1 at the
// series' nodes (measured at sheen roughness 0, 0.3, 1); 0.4 s per sheen roughness on one core.
// ---------------------------------------------------------------------------------------------
constexpr int kGaussOrder = 10;
constexpr int kMaxDepth = 20;
constexpr double kRelativeTolerance = 1e-10;
constexpr double kRoundingFloor = 1e-12;
constexpr double kOuterPanel = 8.0;
constexpr double kLowerTail = 1e-14;
// D below exp(-745) underflows: a direction where even the largest D is below it contributes nothing.
constexpr double kUnderflow = -745.0;

template <class F>
double gauss(const F& f, double a, double b) {
  const math::GaussLegendreRule& rule = math::gauss_legendre(kGaussOrder);
  const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
  double sum = 0.0;
  for (size_t k = 0; k < rule.nodes.size(); ++k) sum += rule.weights[k] * f(mid + half * rule.nodes[k]);
  return sum * half;
}

template <class F>
double refine(const F& f, double a, double b, double whole, double tol, int depth) {
  const double m = 0.5 * (a + b);
  const double left = gauss(f, a, m), right = gauss(f, m, b);
  const double error = std::fabs(left + right - whole);
  if (depth == 0 || error <= std::max(tol, kRoundingFloor * (std::fabs(left) + std::fabs(right)))) return left + right;
  const double sub = tol / std::sqrt(2.0);
  return refine(f, a, m, left, sub, depth - 1) + refine(f, m, b, right, sub, depth - 1);
}

// The integral of f over the panels between consecutive breaks, to `relative` of its magnitude
// (estimated by a first pass over the panels).
template <class F>
double adaptive(const F& f, const std::vector<double>& breaks, double relative) {
  std::vector<double> first(breaks.size() - 1);
  double magnitude = 0.0;
  for (size_t k = 0; k + 1 < breaks.size(); ++k) {
    first[k] = gauss(f, breaks[k], breaks[k + 1]);
    magnitude += std::fabs(first[k]);
  }
  const double tol = relative * magnitude / std::sqrt(static_cast<double>(first.size()));
  double sum = 0.0;
  for (size_t k = 0; k + 1 < breaks.size(); ++k) sum += refine(f, breaks[k], breaks[k + 1], first[k], tol, kMaxDepth);
  return sum;
}

double lambda(const EstevezKullaFit& f, double x, double one_minus_x) {
  const auto L = [&f](double y) { return f.a / (1.0 + f.b * std::pow(y, f.c)) + f.d * y + f.e; };
  return x < 0.5 ? std::exp(L(x)) : std::exp(2.0 * L(0.5) - L(one_minus_x));
}

// The polar angle of a direction with cosine x, 1 - x given (accurate on both sides).
double polar_angle(double x, double one_minus_x) {
  return x < 0.5 ? std::acos(x) : 2.0 * std::asin(std::sqrt(0.5 * one_minus_x));
}

// Breaks: the ends, the features inside, and every kOuterPanel from `from` up.
std::vector<double> outer_breaks(double bottom, double top, double from, std::initializer_list<double> features) {
  std::vector<double> br = {bottom, top};
  for (double t = from; t < top; t += kOuterPanel)
    if (t > bottom) br.push_back(t);
  for (double e : features)
    if (e > bottom && e < top) br.push_back(e);
  std::sort(br.begin(), br.end());
  br.erase(std::unique(br.begin(), br.end()), br.end());
  return br;
}

// E at n.v = mu, with 1 - mu given separately (the upper panels' nodes sit within 1e-16 of 1).
double albedo(double mu, double one_minus_mu, double sheen_roughness) {
  const double alpha = std::max(sheen_roughness * sheen_roughness, math::kMinAlpha);
  const double q = 0.5 / alpha;
  const EstevezKullaFit fit = estevez_kulla_fit(alpha);
  const double tv = polar_angle(mu, one_minus_mu), sin_v = std::sqrt(one_minus_mu * (1.0 + mu));
  const double lambda_v = lambda(fit, mu, one_minus_mu);

  // I(x) / (4 (2 + 1/alpha) / (2 pi)) for l at polar angle tl.
  auto inner = [&](double tl) {
    const double cp = std::cos(0.5 * (tl + tv)), d = std::sin(0.5 * (tl - tv));
    const double S = cp * cp, C = 1.0 - d * d, P = std::sin(tl) * sin_v;
    auto log_sin2 = [&](double cos2_psi) {
      const double den = S + P * cos2_psi;
      const double cos2_h = S * C / den;
      return cos2_h < 0.5 ? std::log1p(-cos2_h) : std::log((S * d * d + P * cos2_psi) / den);
    };
    if (q * log_sin2(1.0) < kUnderflow) return 0.0;  // the largest D, at psi = 0
    auto dist = [&](double psi) {
      const double c = std::cos(psi);
      return std::exp(q * log_sin2(c * c));
    };
    return adaptive(dist, {0.0, 0.25 * kPi, 0.5 * kPi}, 0.1 * kRelativeTolerance);
  };
  auto lower = [&](double t) {  // x = e^t in (0, 1/2]
    const double x = std::exp(t);
    return inner(polar_angle(x, 1.0 - x)) * x / (1.0 + lambda_v + lambda(fit, x, 1.0 - x));
  };
  auto upper = [&](double u) {  // 1 - x = e^u in (0, 1/2]
    const double omx = std::exp(u), x = 1.0 - omx;
    return inner(polar_angle(x, omx)) * omx / (1.0 + lambda_v + lambda(fit, x, omx));
  };
  const double top = std::log(0.5), log_mu = std::log(mu);
  const double below = adaptive(
      lower, outer_breaks(log_mu + std::log(kLowerTail), top, log_mu - kOuterPanel, {log_mu, 0.5 * std::log(alpha)}),
      kRelativeTolerance);
  const double above =
      adaptive(upper, outer_breaks(std::log(1e-16), top, -kOuterPanel, {std::log(one_minus_mu)}), kRelativeTolerance);
  // D's normalisation (2 + 1/alpha) / (2 pi) times the 4 of I(x), over 4 mu
  return (2.0 + 1.0 / alpha) / (2.0 * kPi) * (below + above) / mu;
}

// Clenshaw's recurrence for sum_k c_k T_k(x), c_0 already halved.
double chebyshev_sum(const double* c, int n, double x) {
  double b1 = 0.0, b2 = 0.0;
  for (int k = n - 1; k >= 1; --k) {
    const double b0 = c[k] + 2.0 * x * b1 - b2;
    b2 = b1;
    b1 = b0;
  }
  return c[0] + x * b1 - b2;
}

// The Chebyshev series of E on the kernels' panels, kSeriesOrder coefficients each, from E at the
// Chebyshev points of the first kind (c_k = (2/N) sum_j f_j cos(k (2j + 1) pi / 2N), Trefethen,
// "Approximation Theory and Approximation Practice", ch. 3):
//   panels 0 .. BRDF_SHEEN_LOWER - 1: uniform in w = ln mu over [BRDF_SHEEN_W_LOW, BRDF_SHEEN_W_SEAM],
//     where E grows like 1/mu (analytic in w) and Lambda's x^c is e^(c w);
//   the next BRDF_SHEEN_UPPER: uniform in s = (1 - mu)^c over [0, (1/2)^c], where Lambda's mirrored
//     fit is smooth (1 - mu = s^(1/c)).
// 16 coefficients resolve E to ~1e-10 on these panels (tests/device/test_brdf_eval.cpp measures it).
constexpr int kSeriesOrder = 16;

std::vector<double> series(double sheen_roughness) {
  // the upper panels' exponent as the kernels map mu to s (BRDF_GLTF_SHEEN_FIT + 2, alpha unfloored)
  const double c = estevez_kulla_fit(sheen_roughness * sheen_roughness).c;
  const double s_seam = std::pow(0.5, c);
  const int panels = BRDF_SHEEN_LOWER + BRDF_SHEEN_UPPER, n = kSeriesOrder;
  // E at every node of every panel, on every core
  std::vector<double> values(static_cast<size_t>(panels * n));
  parallel_for(values.size(), [&](size_t k) {
    const int p = static_cast<int>(k) / n, j = static_cast<int>(k) % n;
    const double node = std::cos((2.0 * j + 1.0) * kPi / (2.0 * n));
    if (p < BRDF_SHEEN_LOWER) {
      const double w0 = BRDF_SHEEN_W_LOW + (BRDF_SHEEN_W_SEAM - BRDF_SHEEN_W_LOW) * p / BRDF_SHEEN_LOWER;
      const double w1 = BRDF_SHEEN_W_LOW + (BRDF_SHEEN_W_SEAM - BRDF_SHEEN_W_LOW) * (p + 1) / BRDF_SHEEN_LOWER;
      const double mu = std::exp(0.5 * (w0 + w1) + 0.5 * (w1 - w0) * node);
      values[k] = albedo(mu, 1.0 - mu, sheen_roughness);
    } else {
      const int pu = p - BRDF_SHEEN_LOWER;
      const double s0 = s_seam * pu / BRDF_SHEEN_UPPER, s1 = s_seam * (pu + 1) / BRDF_SHEEN_UPPER;
      const double omu = std::pow(0.5 * (s0 + s1) + 0.5 * (s1 - s0) * node, 1.0 / c);
      values[k] = albedo(1.0 - omu, omu, sheen_roughness);
    }
  });
  std::vector<double> coefficients;
  for (int p = 0; p < panels; ++p)
    for (int k = 0; k < n; ++k) {
      double sum = 0.0;
      for (int j = 0; j < n; ++j)
        sum += values[static_cast<size_t>(p * n + j)] * std::cos(k * (2.0 * j + 1.0) * kPi / (2.0 * n));
      sum *= 2.0 / n;
      coefficients.push_back(k == 0 ? 0.5 * sum : sum);
    }
  return coefficients;
}

}  // namespace

double sheen_albedo_quadrature(double mu, double sheen_roughness) {
  const double m = std::clamp(mu, math::kBrdfMinCosine, 1.0);
  return albedo(m, 1.0 - m, sheen_roughness);
}

// The series cut into the kernels' cubic pieces (common/brdf_params.clh): on each piece, the cubic in
// u in [0, 1] through the series at the piece's four Chebyshev points, converted to monomial
// coefficients.
const std::vector<double>& sheen_albedo_pieces(double sheen_roughness) {
  if (!(sheen_roughness >= 0.0 && sheen_roughness <= 1.0))
    throw Error("sheen roughness must be in [0, 1] for the sheen albedo table");
  static std::mutex mutex;
  static std::map<double, std::vector<double>> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  std::vector<double>& t = cache[sheen_roughness];
  if (!t.empty()) return t;
  const std::vector<double> coefficients = series(sheen_roughness);
  const int panels = BRDF_SHEEN_LOWER + BRDF_SHEEN_UPPER;
  for (int p = 0; p < panels; ++p) {
    const double* c = coefficients.data() + static_cast<size_t>(p) * static_cast<size_t>(kSeriesOrder);
    for (int k = 0; k < BRDF_SHEEN_PIECES; ++k) {
      // values at the Chebyshev points u_i of the piece, then Newton's divided differences and the
      // expansion of the Newton form into monomials
      double u[4], y[4];
      for (int i = 0; i < 4; ++i) {
        u[i] = 0.5 * (1.0 - std::cos((2.0 * i + 1.0) * kPi / 8.0));
        const double local = (k + u[i]) / BRDF_SHEEN_PIECES;  // in [0, 1] across the panel
        y[i] = chebyshev_sum(c, kSeriesOrder, 2.0 * local - 1.0);
      }
      double d[4] = {y[0], y[1], y[2], y[3]};
      for (int j = 1; j < 4; ++j)
        for (int i = 3; i >= j; --i) d[i] = (d[i] - d[i - 1]) / (u[i] - u[i - j]);
      // p(u) = d0 + d1 (u - u0) + d2 (u - u0)(u - u1) + d3 (u - u0)(u - u1)(u - u2)
      double a[4] = {d[3], 0.0, 0.0, 0.0};  // Horner on the Newton form, in monomials
      for (int i = 2; i >= 0; --i) {
        // a(u) <- a(u) (u - u_i) + d_i
        double next[4] = {0.0, 0.0, 0.0, 0.0};
        for (int m = 0; m < 3; ++m) {
          next[m + 1] += a[m];
          next[m] -= a[m] * u[i];
        }
        next[0] += d[i];
        for (int m = 0; m < 4; ++m) a[m] = next[m];
      }
      t.insert(t.end(), a, a + 4);
    }
  }
  return t;
}

}  // namespace brdfbake::detail
