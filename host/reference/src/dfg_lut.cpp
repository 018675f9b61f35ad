#include "brdfbake/reference/dfg_lut.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <exception>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "brdfbake/math/conventions.hpp"
#include "brdfbake/reference/burley.hpp"
#include "brdfbake/reference/charlie.hpp"
#include "brdfbake/reference/ggx.hpp"
#include "brdfbake/reference/quadrature.hpp"

// Frame: n = +z, v = (sin_v, 0, n.v) with sin_v = sqrt(1 - n.v^2), beta = asin(n.v) the elevation of
// v. Half vectors h = (sin th cos ph, sin th sin ph, cos th); l = 2 (v.h) h - v.
//
// Every specular integral here is over the half vector. With dl = 4 (v.h) dh (the reflection
// Jacobian, Walter et al. 2007) and V = G2 / (4 n.l n.v),
//   integral of D(h) V(l, v) n.l X dl = integral of D(h) g(h) dh,   g = 4 n.l V (v.h) X,
// over the h with n.l > 0 (which implies v.h > 0 since n.h > 0). X is 1, 1 - Fc or Fc.
//
// Where l crosses the horizon. n.l = 2 (v.h) cos th - n.v = A + B cos ph with
//   A = n.v cos 2th,  B = sin_v sin 2th,  A + B = sin(2 (th2 - th)),  A - B = sin(2 (th1 - th)),
//   th1 = beta / 2,  th2 = pi/2 - beta / 2.
// So for th < th1 every ph has n.l > 0, for th1 < th < th2 it holds for ph < ph_e = acos(-A/B), and
// above th2 for none. The integrals below split at th1 and th2 and integrate ph over [0, ph_e]
// (doubling for the mirror half ph < 0). Near th1 and th2 the ph range behaves like sqrt(th - th_i):
// the panels touching them on the cut side get a square-root map.
//
// Near-singularities of the visibility. Every g above is, as a function of x = n.l, analytic on the
// real line near 0 except for a pole or branch point a small distance `pole` below x = 0:
//   GGX: 4 n.l V = 2 x / (x S(n.v) + n.v S(x)), S(c) = sqrt(c^2 + alpha^2 (1 - c^2)): pole at
//        x ~ -n.v alpha / S(n.v) (about -min(n.v, alpha));
//   Neubelt: 4 n.l V = x / (x + n.v - x n.v): pole at x = -n.v / (1 - n.v);
//   Estevez-Kulla: 4 n.l V = 1 / (n.v (1 + Lambda(v) + Lambda(x))), which switches on around
//        Lambda(x) ~ Lambda(v), i.e. x ~ n.v, and has a branch point x^c at x = 0.
// The integrand therefore changes on the scale `pole` next to the horizon curve n.l = 0. Panels
// are refined geometrically towards ph_e (and towards th1, th2 in the outer variable) until they are
// small against that scale; below it the integrand is smooth again, so this costs a few panels per
// decade of n.v instead of a fine grid everywhere.

namespace brdfbake::reference {
namespace {

using brdfbake::math::kPi;
constexpr double kHalfPi = 0.5 * kPi;

// ---- Resolution at refinement 1 (refinement f divides widths by f, refinement depths by f^2). ----

// Widest panel in ph: the integrand is smooth, even and 2pi-periodic in ph away from the horizon.
constexpr double kMaxPhiPanel = kPi / 3.0;
// Widest panel in y = ln tan th (GGX): the GGX weight and sin th, cos th are analytic in a strip of
// half-width pi/2 about the real y axis, so a unit panel converges like 6^(-2n) at n nodes.
constexpr double kMaxGgxPanel = 1.0;
// Widest panel in the Charlie elevation e = pi/2 - th, for the variation of the inner integral.
constexpr double kMaxCharliePanel = 0.4;
// Charlie's D = (...) cos(e)^(1/alpha) may drop by at most exp(kMaxLogDrop) across a panel: a
// steeper exponential would need more than the panel's nodes.
constexpr double kMaxLogDrop = 4.0;
// Geometric refinement towards a near-singularity stops when the innermost panel spans, in n.l,
// 1/kPoleResolution of the distance to it: the singularity is then far outside the panel.
constexpr double kPoleResolution = 16.0;
// A region whose whole contribution is bounded by this need not be resolved further (refinement
// stops, tails are dropped). Hundreds of such regions stay far below the 1e-6 contract.
constexpr double kNegligible = 1e-13;
// Estevez-Kulla's Lambda has a (1 - n.l)^c cusp at l = n, i.e. at h = (th_v / 2, ph = 0): there
// Lambda = exp(2 L(1/2) - L(1 - n.l)) < 1e-6 for 1 - n.l < 1e-8, i.e. within ~1e-4 of th_v / 2, so
// refinement in th towards th_v / 2 stops at that distance.
constexpr double kCuspAngle = 1e-4;
// Charlie's weight ~ th^(1/alpha + 1) at th = 0 is not analytic for non-integer 1/alpha; panels are
// refined towards th = 0 down to this (its mass below is < 1e-12 for alpha <= 1).
constexpr double kPoleOfHemisphere = 1e-4;
// Below this elevation from th = 0 the Charlie tail truncation is pointless: integrate to th = 0.
constexpr double kTruncationMargin = 0.05;
// n.v = 0 has no frame of its own here (th1 = 0, y1 = -inf), so the integrals take n.v >= 1e-16.
// GGX and Neubelt approach their n.v -> 0 limits linearly, with slopes up to ~3e7 at the alpha floor
// (the lobe's grazing scale is n.v ~ alpha): 1e-16 is within 3e-9 of the limit for every alpha.
constexpr double kMinViewCosine = 1e-16;
// Estevez-Kulla's albedo has no finite n.v -> 0 limit: its fitted Lambda saturates at exp(a + e),
// so V ~ 1/n.v and the albedo grows like ~1e-8 / n.v. It is evaluated at the kernels' floor instead
// (docs/CONVENTIONS.md: "the kernels keep 1e-7").
constexpr double kMinViewCosineSheenFit = 1e-7;

struct Settings {
  const GaussLegendreRule* rule;
  double max_phi;       // widest ph panel
  double max_ggx;       // widest y panel
  double max_charlie;   // widest e panel
  double max_log_drop;  // steepest Charlie panel
  double pole_div;      // kPoleResolution, refined
  double negligible;    // kNegligible, refined
  double cusp_angle;    // kCuspAngle, refined
  double hemisphere_pole;
};

Settings make_settings(const Quadrature& q) {
  if (q.order < 1 || q.order > 512) {
    throw std::invalid_argument("Quadrature::order " + std::to_string(q.order) + " outside [1, 512]");
  }
  if (q.refinement < 1 || q.refinement > 64) {
    throw std::invalid_argument("Quadrature::refinement " + std::to_string(q.refinement) + " outside [1, 64]");
  }
  const double f = q.refinement;
  Settings s{};
  s.rule = &gauss_legendre(q.order);
  s.max_phi = kMaxPhiPanel / f;
  s.max_ggx = kMaxGgxPanel / f;
  s.max_charlie = kMaxCharliePanel / f;
  s.max_log_drop = kMaxLogDrop / f;
  s.pole_div = kPoleResolution * f * f;
  s.negligible = kNegligible / (f * f * f * f);
  s.cusp_angle = kCuspAngle / (f * f);
  s.hemisphere_pole = kPoleOfHemisphere / (f * f);
  return s;
}

double pow5(double x) {
  const double x2 = x * x;
  return x2 * x2 * x;
}

// Inputs: NaN is an error; anything else is clamped to [0, 1] (docs/CONVENTIONS.md).
double unit_input(const char* function, const char* name, double value) {
  if (std::isnan(value)) {
    throw std::invalid_argument(std::string(function) + ": " + name + " is NaN");
  }
  return std::clamp(value, 0.0, 1.0);
}

// What the ph panels must resolve in x = n.l (see the top of this file).
struct NdotLFeatures {
  double pole;           // the visibility's near-singularity lies at about x = -pole
  bool sheen_fit;        // Estevez-Kulla Lambda: C1 seam at x = 1/2 (split there) ...
  double horizon_power;  // ... and analytic in x^c, not x, at x = 0: power 1/c at the horizon
};

// Visits (cos ph, weight) for the ph quadrature of one th: ph over [0, ph_e] where
// n.l = A + B cos ph > 0. `mass` bounds the contribution per unit ph (outer weight times the
// integrand's bound); it lets the refinement stop where a panel cannot matter.
// Lobe integrand evaluations made by this thread (bench/lut_accuracy's equal-samples comparison).
thread_local uint64_t t_lobe_evaluations = 0;
uint64_t panel_nodes(const GaussLegendreRule& rule) { return rule.nodes.size(); }

template <class Visit>
void for_each_phi_node(double A, double B, const NdotLFeatures& feat, double mass, const Settings& s,
                       std::vector<Panel>& panels, Visit&& visit) {
  double phi_end = kPi;
  double x_end = 0.0;  // n.l at ph_e
  bool full = true;
  if (!(B > 0.0)) {
    if (!(A > 0.0)) return;
    x_end = A;
  } else if (A - B >= 0.0) {
    x_end = A - B;
  } else if (A + B <= 0.0) {
    return;
  } else {
    full = false;
    phi_end = std::acos(std::clamp(-A / B, -1.0, 1.0));
  }
  const double d_mass = mass > 0.0 ? s.negligible / mass : phi_end;

  // Towards ph_e: innermost panel spanning (x_end + pole) / pole_div in n.l.
  EndRefinement at_end;
  if (B > 0.0) {
    const double dx = (x_end + feat.pole) / s.pole_div;
    double d = phi_end;
    if (full) {
      // n.l(pi - d) - n.l(pi) = 2 B sin^2(d/2)
      const double q = dx / (2.0 * B);
      if (q < 1.0) d = 2.0 * std::asin(std::sqrt(q));
    } else {
      // n.l(ph_e - d) = B (cos(ph_e - d) - cos ph_e)
      const double c = (dx - A) / B;
      if (c < 1.0) d = phi_end - std::acos(c);
    }
    d = std::max(d, d_mass);
    at_end = EndRefinement{d < phi_end, d, full ? 1.0 : feat.horizon_power};
  }

  // Estevez-Kulla: split at the seam n.l = 1/2. (Its cusp at n.l = 1 is a point, l = n, resolved
  // by refining th towards th_v / 2 in integrate_charlie; refining ph as well gained nothing.)
  double phi_half = -1.0;
  if (feat.sheen_fit && B > 0.0 && x_end < 0.5 && A + B > 0.5) {
    phi_half = std::acos(std::clamp((0.5 - A) / B, -1.0, 1.0));
  }

  panels.clear();
  if (phi_half > 0.0 && phi_half < phi_end) {
    append_panels(0.0, phi_half, EndRefinement{}, EndRefinement{}, s.max_phi, panels);
    append_panels(phi_half, phi_end, EndRefinement{}, at_end, s.max_phi, panels);
  } else {
    append_panels(0.0, phi_end, EndRefinement{}, at_end, s.max_phi, panels);
  }
  for (const Panel& panel : panels) {
    t_lobe_evaluations += panel_nodes(*s.rule);
    for_each_node(panel, *s.rule, [&](const PanelNode& node) { visit(std::cos(node.t), node.weight); });
  }
}

// ---------------------------------------------------------------------------------------------
// GGX specular: scale and bias.
//
// The outer variable follows GGX's own CDF. The measure D(h) cos th dh has CDF in th
//   xi(th) = tan^2 th / (alpha^2 + tan^2 th)         (tan^2 th = alpha^2 xi / (1 - xi)),
// so D(h) dh = dxi dph / (2 pi cos th) and, doubling for ph < 0,
//   integral of D g dh = integral over xi of 1/(2 pi cos th) * 2 integral_0^ph_e g dph  dxi.
// In xi the weight is flat, but the geometry (th1, th2, the horizon features) crowds into
// 1 - xi ~ alpha^2 for small alpha. So xi is used only near th = 0, up to y_start; beyond it the
// variable is y = ln tan th, with dxi/dy = 2 xi (1 - xi): panels of unit width in y resolve every
// scale of th from alpha to the horizon alike, and th1 (y1 = ln tan(beta/2)), th2 (y2 = -y1) are
// panel ends. The integrand g = 4 n.l V (v.h) (1 - Fc or Fc) is bounded by 2 / S(n.v).
DfgGgx integrate_ggx(double n_dot_v, double alpha_in, const Settings& s) {
  const double nv = std::max(n_dot_v, kMinViewCosine);
  const double alpha = std::max(alpha_in, kMinAlpha);
  const double sin_v = std::sqrt((1.0 - nv) * (1.0 + nv));
  const double beta = std::asin(nv);
  const double s_v = std::sqrt(nv * nv + alpha * alpha * sin_v * sin_v);
  const double g_max = 2.0 / s_v;
  const NdotLFeatures feat{nv * alpha / s_v, false, 1.0};
  const double log_alpha = std::log(alpha);

  const double y1 = std::log(std::tan(0.5 * beta));
  const double y2 = -y1;
  // Tail above y_top: with 1 - xi <= alpha^2 e^(-2y) and 1/cos th <= sqrt(2) + e^y, the dropped
  // part is at most g_max (sqrt(2) e^(-2K) + 2 alpha e^(-K)) for y_top = ln alpha + K.
  const double k_tail =
      std::max(0.5 * std::log(3.0 * g_max / s.negligible), std::log(4.0 * alpha * g_max / s.negligible));
  const double y_top = std::min(y2, log_alpha + std::max(k_tail, 2.0));
  const double y_start = std::min(log_alpha, y1) - 2.0;

  // Contribution per unit y near y, bounded: (dxi/dy) / (2 pi cos th) * 2 pi * g_max.
  auto density = [&](double y) {
    const double q2 = std::exp(2.0 * (log_alpha - y));  // alpha^2 / tan^2 th = (1 - xi) / xi
    const double xi_1mxi = q2 / ((1.0 + q2) * (1.0 + q2));
    return 2.0 * xi_1mxi * std::sqrt(1.0 + std::exp(2.0 * y)) * g_max;
  };
  // Innermost panel at th1 or th2: the horizon feature spans n.l ~ pole, i.e. th ~ pole / 2, and
  // dy/dth = 2 / sin 2th = 2 / n.v there.
  auto horizon_size = [&](double y) {
    const double by_pole = feat.pole / (s.pole_div * nv);
    return std::max(by_pole, s.negligible / density(y));
  };

  std::vector<Panel> outer;
  if (y1 < y_top) {
    const double m1 = horizon_size(y1);
    append_panels(y_start, y1, EndRefinement{}, EndRefinement{true, m1, 1.0}, s.max_ggx, outer);
    const EndRefinement top = y_top >= y2 ? EndRefinement{true, horizon_size(y2), 2.0} : EndRefinement{};
    append_panels(y1, y_top, EndRefinement{true, m1, 2.0}, top, s.max_ggx, outer);
  } else {
    const EndRefinement top = y_top >= y1 ? EndRefinement{true, horizon_size(y1), 1.0} : EndRefinement{};
    append_panels(y_start, y_top, EndRefinement{}, top, s.max_ggx, outer);
  }

  double scale = 0.0;
  double bias = 0.0;
  std::vector<Panel> phi_panels;
  auto at_theta = [&](double cos_t, double sin_t, double w_outer) {
    const double A = nv * (cos_t - sin_t) * (cos_t + sin_t);
    const double B = sin_v * 2.0 * sin_t * cos_t;
    for_each_phi_node(A, B, feat, 2.0 * w_outer * g_max, s, phi_panels, [&](double cos_p, double w_phi) {
      const double v_dot_h = sin_v * sin_t * cos_p + nv * cos_t;
      const double n_dot_l = 2.0 * v_dot_h * cos_t - nv;
      if (!(n_dot_l > 0.0)) return;
      const double g = 4.0 * n_dot_l * V_SmithGGXCorrelated(nv, n_dot_l, alpha) * v_dot_h;
      const double fc = pow5(1.0 - v_dot_h);
      const double w = 2.0 * w_outer * w_phi;
      scale += w * (1.0 - fc) * g;
      bias += w * fc * g;
    });
  };

  // xi in [0, xi_start]: tan^2 th = alpha^2 xi / (1 - xi), weight dxi / (2 pi cos th).
  const double xi_start = 1.0 / (1.0 + std::exp(2.0 * (log_alpha - y_start)));
  for_each_node(Panel{0.0, xi_start}, *s.rule, [&](const PanelNode& node) {
    const double tan2 = alpha * alpha * node.t / (1.0 - node.t);
    const double cos_t = 1.0 / std::sqrt(1.0 + tan2);
    at_theta(cos_t, std::sqrt(tan2) * cos_t, node.weight / (2.0 * kPi * cos_t));
  });
  // y = ln tan th: weight (dxi/dy) / (2 pi cos th) = xi (1 - xi) / (pi cos th).
  for (const Panel& panel : outer) {
    for_each_node(panel, *s.rule, [&](const PanelNode& node) {
      const double tan_t = std::exp(node.t);
      const double cos_t = 1.0 / std::sqrt(1.0 + tan_t * tan_t);
      const double q2 = std::exp(2.0 * (log_alpha - node.t));
      const double xi_1mxi = q2 / ((1.0 + q2) * (1.0 + q2));
      at_theta(cos_t, tan_t * cos_t, node.weight * xi_1mxi / (kPi * cos_t));
    });
  }
  return DfgGgx{scale, bias};
}

// ---------------------------------------------------------------------------------------------
// Burley diffuse albedo.
//
// integral of f_d n.l dl = integral_0^1 dmu integral_0^2pi dph f_d(mu, ph) mu, mu = n.l, where
// l.v = sin_v sqrt(1 - mu^2) cos ph + n.v mu and (l.h)^2 = (1 + l.v) / 2. f_d is a polynomial of
// degree 2 in (l.h)^2 (through F_D90) times powers of mu, so f_d mu is a polynomial of degree <= 2
// in cos ph and, once the odd powers of cos ph have integrated to zero, of degree <= 8 in mu. The
// midpoint rule in ph on [0, pi] (Gauss-Chebyshev in cos ph) with N >= 2 nodes and Gauss-Legendre
// in mu with n >= 5 nodes are then exact: the result is exact to rounding.
template <class Fd>
double integrate_burley(double n_dot_v, const Settings& s, Fd&& fd) {
  const double nv = n_dot_v;
  const double sin_v = std::sqrt((1.0 - nv) * (1.0 + nv));
  const int n_phi = static_cast<int>(s.rule->nodes.size());
  const double w_phi = kPi / n_phi;
  double sum = 0.0;
  for_each_node(Panel{0.0, 1.0}, *s.rule, [&](const PanelNode& node) {
    const double mu = node.t;
    const double sin_l = std::sqrt((1.0 - mu) * (1.0 + mu));
    for (int k = 0; k < n_phi; ++k) {
      const double cos_p = std::cos((k + 0.5) * w_phi);
      const double l_dot_v = sin_v * sin_l * cos_p + nv * mu;
      sum += 2.0 * node.weight * w_phi * fd(mu, l_dot_v) * mu;
    }
  });
  return sum;
}

// ---------------------------------------------------------------------------------------------
// Charlie sheen albedo.
//
// The outer variable is the elevation of h, e = pi/2 - th (n.h = sin e), with
// D(h) dh = D sin th dth dph = D(sin e) cos e de dph. Charlie's D ~ cos(e)^(1/alpha) is a band of
// width ~sqrt(alpha) along the horizon (e = 0) for small alpha and a power law th^(1/alpha) at
// th = 0. Valid h have e > e2 = beta / 2 (th < th2); e1 = pi/2 - beta/2 is th1. Panels:
//   - ends at e2 and e1, refined towards both (horizon features, see the top of the file), with
//     square-root maps on the cut side;
//   - Estevez-Kulla only: ends where the C1 seam n.l = 1/2 meets ph = 0 or pi
//     (A + B = 1/2: e = e2 + pi/12, e2 + 5pi/12; A - B = 1/2: e = e1 + pi/12) with square-root maps
//     (the inner integral behaves like |e - e_s|^(5/2) there), and refinement towards
//     e_v = pi/4 + beta/2 (th = th_v / 2, where l = n and the fitted Lambda has its cusp);
//   - no wider than kMaxCharliePanel, and split where log D drops by more than kMaxLogDrop;
//   - truncated where the rest of D's mass cannot matter, else refined towards th = 0.
// The integrand g = 4 n.l V (v.h) is bounded by 1 (Neubelt) or 1 / (n.v (1 + Lambda(v))) (E-K).
struct Break {
  double at;
  EndRefinement below;
  EndRefinement above;
};

double log_cos(double e) {
  const double s = std::sin(e);
  return 0.5 * std::log1p(-s * s);
}

double integrate_charlie(double n_dot_v, double alpha_in, SheenVisibility visibility, const Settings& s) {
  const bool ek = visibility == SheenVisibility::EstevezKulla;
  const double nv = std::max(n_dot_v, ek ? kMinViewCosineSheenFit : kMinViewCosine);
  const double alpha = std::clamp(alpha_in, kMinAlpha, 1.0);
  const double sin_v = std::sqrt((1.0 - nv) * (1.0 + nv));
  const double beta = std::asin(nv);
  const double lambda_v = ek ? Lambda_CharlieEstevezKulla(nv, alpha) : 0.0;
  const double g_max = ek ? 1.0 / (nv * (1.0 + lambda_v)) : 1.0;
  // Estevez-Kulla's x^c at the horizon: the ph panel ending on it takes the power 1/c. (The inner
  // integral then inherits a weak (e - e_i)^c term at e2 and e1; powers 1/c or 2/c there instead of
  // the square root were tried and gained nothing over the geometric refinement.)
  const NdotLFeatures feat{nv, ek, ek ? 1.0 / SheenFitExponent(alpha) : 1.0};
  const double inv_a = 1.0 / alpha;

  // Truncation: the mass beyond e is at most (pi/2) (2 + 1/alpha)/(2 pi) cos(e)^(1/alpha), times
  // 2 pi g_max for the inner integral.
  const double tail_scale = kHalfPi * (2.0 + inv_a) * g_max;
  const double cos_top = std::exp(-alpha * std::log(std::max(tail_scale / s.negligible, 1.0)));
  double e_top = std::acos(cos_top);
  const bool to_pole = e_top > kHalfPi - kTruncationMargin;
  if (to_pole) e_top = kHalfPi;
  const double e2 = 0.5 * beta;
  const double e1 = kHalfPi - 0.5 * beta;
  if (!(e_top > e2)) return 0.0;

  auto density = [&](double e) {  // contribution per unit e, bounded
    return D_Charlie(std::sin(e), alpha) * std::cos(e) * 2.0 * kPi * g_max;
  };
  auto horizon_size = [&](double e) { return std::max(0.5 * feat.pole / s.pole_div, s.negligible / density(e)); };

  std::vector<Break> breaks;
  const double m2 = horizon_size(e2);
  breaks.push_back(Break{e2, EndRefinement{}, EndRefinement{true, m2, 2.0}});
  const double m1 = horizon_size(e1);
  breaks.push_back(Break{e1, EndRefinement{true, m1, 2.0}, EndRefinement{true, m1, 1.0}});
  if (ek) {
    const double e_v = 0.25 * kPi + 0.5 * beta;
    const double m_v = std::max(s.cusp_angle, s.negligible / density(e_v));
    breaks.push_back(Break{e_v, EndRefinement{true, m_v, 1.0}, EndRefinement{true, m_v, 1.0}});
    const EndRefinement seam{false, 0.0, 2.0};
    for (double e_s : {e2 + kPi / 12.0, e2 + 5.0 * kPi / 12.0, e1 + kPi / 12.0}) {
      breaks.push_back(Break{e_s, seam, seam});
    }
  }
  {
    EndRefinement below;
    if (to_pole) below = EndRefinement{true, s.hemisphere_pole, 1.0};
    breaks.push_back(Break{e_top, below, EndRefinement{}});
  }
  // Keep the breaks in [e2, e_top], sorted; merge coincident ones.
  std::vector<Break> inside;
  for (const Break& b : breaks) {
    if (b.at >= e2 && b.at <= e_top) inside.push_back(b);
  }
  std::sort(inside.begin(), inside.end(), [](const Break& l, const Break& r) { return l.at < r.at; });
  auto merge = [](EndRefinement& into, const EndRefinement& from) {
    if (from.refine) {
      into.min_size = into.refine ? std::min(into.min_size, from.min_size) : from.min_size;
      into.refine = true;
    }
    into.map_power = std::max(into.map_power, from.map_power);
  };
  std::vector<Break> merged;
  for (const Break& b : inside) {
    if (!merged.empty() && b.at - merged.back().at < 1e-12) {
      merge(merged.back().below, b.below);
      merge(merged.back().above, b.above);
    } else {
      merged.push_back(b);
    }
  }

  std::vector<Panel> raw;
  for (std::size_t k = 0; k + 1 < merged.size(); ++k) {
    append_panels(merged[k].at, merged[k + 1].at, merged[k].above, merged[k + 1].below, s.max_charlie, raw);
  }
  // Split panels across which D drops by more than max_log_drop, at equal steps of log D.
  std::vector<Panel> outer;
  for (const Panel& p : raw) {
    const double la = log_cos(p.a);
    const double lb = log_cos(p.b);
    const double drop = (la - lb) * inv_a;
    if (!std::isfinite(drop) || drop <= s.max_log_drop) {
      outer.push_back(p);
      continue;
    }
    const double pieces = std::min(std::ceil(drop / s.max_log_drop), 4096.0);
    const int n = static_cast<int>(pieces);
    double a = p.a;
    for (int k = 1; k <= n; ++k) {
      const double b = k == n ? p.b : std::acos(std::exp(la - (la - lb) * k / n));
      if (b > a) outer.push_back(Panel{a, b, k == 1 ? p.power_a : 1.0, k == n ? p.power_b : 1.0});
      a = std::max(a, b);
    }
  }

  double sum = 0.0;
  std::vector<Panel> phi_panels;
  for (const Panel& panel : outer) {
    for_each_node(panel, *s.rule, [&](const PanelNode& node) {
      const double sin_e = std::sin(node.t);  // n.h = cos th
      const double cos_e = std::cos(node.t);  // sin th
      const double w_outer = D_Charlie(sin_e, alpha) * cos_e * node.weight;
      if (!(w_outer > 0.0)) return;
      const double A = nv * (sin_e - cos_e) * (sin_e + cos_e);
      const double B = sin_v * 2.0 * sin_e * cos_e;
      for_each_phi_node(A, B, feat, 2.0 * w_outer * g_max, s, phi_panels, [&](double cos_p, double w_phi) {
        const double v_dot_h = sin_v * cos_e * cos_p + nv * sin_e;
        const double n_dot_l = 2.0 * v_dot_h * sin_e - nv;
        if (!(n_dot_l > 0.0)) return;
        // 4 n.l V: Estevez-Kulla's as 1 / (n.v (1 + Lambda(v) + Lambda(l))), Lambda(v) hoisted.
        const double four_nl_v = ek ? 1.0 / (nv * (1.0 + lambda_v + Lambda_CharlieEstevezKulla(n_dot_l, alpha)))
                                    : 4.0 * n_dot_l * V_Neubelt(nv, n_dot_l);
        sum += 2.0 * w_outer * w_phi * four_nl_v * v_dot_h;
      });
    });
  }
  return sum;
}

}  // namespace

DfgGgx dfg_ggx(double n_dot_v, double roughness) { return dfg_ggx(n_dot_v, roughness, Quadrature{}); }

DfgGgx dfg_ggx(double n_dot_v, double roughness, const Quadrature& quadrature) {
  const double nv = unit_input("dfg_ggx", "n_dot_v", n_dot_v);
  const double r = unit_input("dfg_ggx", "roughness", roughness);
  return integrate_ggx(nv, r * r, make_settings(quadrature));
}

double burley_albedo(double n_dot_v, double roughness) { return burley_albedo(n_dot_v, roughness, Quadrature{}); }

double burley_albedo(double n_dot_v, double roughness, const Quadrature& quadrature) {
  const double nv = unit_input("burley_albedo", "n_dot_v", n_dot_v);
  const double r = unit_input("burley_albedo", "roughness", roughness);
  return integrate_burley(nv, make_settings(quadrature), [&](double n_dot_l, double l_dot_v) {
    return Fd_Burley(nv, n_dot_l, std::sqrt(std::max(0.0, 0.5 * (1.0 + l_dot_v))), r);
  });
}

double burley_albedo_fixed_f90(double n_dot_v, double f_d90, const Quadrature& quadrature) {
  const double nv = unit_input("burley_albedo_fixed_f90", "n_dot_v", n_dot_v);
  if (!std::isfinite(f_d90)) throw std::invalid_argument("burley_albedo_fixed_f90: f_d90 is not finite");
  return integrate_burley(nv, make_settings(quadrature),
                          [&](double n_dot_l, double) { return Fd_BurleyF90(nv, n_dot_l, f_d90); });
}

double charlie_albedo(double n_dot_v, double sheen_roughness, SheenVisibility visibility) {
  return charlie_albedo(n_dot_v, sheen_roughness, visibility, Quadrature{});
}

double charlie_albedo(double n_dot_v, double sheen_roughness, SheenVisibility visibility,
                      const Quadrature& quadrature) {
  const double nv = unit_input("charlie_albedo", "n_dot_v", n_dot_v);
  const double r = unit_input("charlie_albedo", "sheen_roughness", sheen_roughness);
  return integrate_charlie(nv, r * r, visibility, make_settings(quadrature));
}

uint64_t lobe_evaluations_this_thread() { return t_lobe_evaluations; }

int lut_channels(LutKind kind) {
  switch (kind) {
    case LutKind::Ggx:
    case LutKind::GgxMultiscatter:
      return 3;
    case LutKind::Charlie:
      return 1;
  }
  throw std::invalid_argument("lut_channels: unknown LutKind");
}

std::vector<double> lut_table(LutKind kind, int width, int height, SheenVisibility visibility, unsigned threads) {
  if (width < 1 || height < 1) {
    throw std::invalid_argument("lut_table: size " + std::to_string(width) + "x" + std::to_string(height) +
                                " must be at least 1x1");
  }
  const auto channels = static_cast<std::size_t>(lut_channels(kind));
  const auto w = static_cast<std::size_t>(width);
  std::vector<double> table(w * static_cast<std::size_t>(height) * channels);

  auto fill_row = [&](int j) {
    const double roughness = (j + 0.5) / height;
    double* row = table.data() + static_cast<std::size_t>(j) * w * channels;
    for (int i = 0; i < width; ++i) {
      const double n_dot_v = (i + 0.5) / width;
      double* texel = row + static_cast<std::size_t>(i) * channels;
      switch (kind) {
        case LutKind::Ggx: {
          const DfgGgx d = dfg_ggx(n_dot_v, roughness);
          texel[0] = d.scale;
          texel[1] = d.bias;
          texel[2] = burley_albedo(n_dot_v, roughness);
          break;
        }
        case LutKind::GgxMultiscatter: {
          const DfgGgx d = dfg_ggx(n_dot_v, roughness);
          texel[0] = d.bias;
          texel[1] = d.scale + d.bias;
          texel[2] = burley_albedo(n_dot_v, roughness);
          break;
        }
        case LutKind::Charlie:
          texel[0] = charlie_albedo(n_dot_v, roughness, visibility);
          break;
      }
    }
  };

  unsigned n_threads = threads != 0 ? threads : std::max(1u, std::thread::hardware_concurrency());
  n_threads = std::min(n_threads, static_cast<unsigned>(height));
  std::atomic<int> next_row{0};
  std::vector<std::exception_ptr> errors(n_threads);
  auto worker = [&](unsigned t) {
    try {
      for (int j = next_row++; j < height; j = next_row++) fill_row(j);
    } catch (...) {
      errors[t] = std::current_exception();
      next_row = height;  // stop the others early
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < n_threads; ++t) pool.emplace_back(worker, t);
  worker(0);
  for (std::thread& th : pool) th.join();
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
  return table;
}

}  // namespace brdfbake::reference
