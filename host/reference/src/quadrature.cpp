#include "brdfbake/reference/quadrature.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

namespace brdfbake::reference {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Newton's iteration on P_n stops when the step is below this: the node is then exact to rounding
// (Newton converges quadratically, so the step after a 1e-15 step is far below double precision).
constexpr double kNewtonStep = 1e-15;
constexpr int kNewtonMaxIterations = 100;

// The largest order we hand out: the recurrence and the initial guesses are accurate well beyond it,
// and no integral of the reference needs more than a few dozen nodes per panel.
constexpr int kMaxOrder = 512;

// Geometric refinement: a panel [d, 3d] from the end, i.e. twice as long as its distance to it.
constexpr double kGradingRatio = 3.0;

// Legendre P_n(x) and P_n'(x) by the three-term recurrence (k+1) P_{k+1} = (2k+1) x P_k - k P_{k-1}.
void legendre(int n, double x, double& p, double& dp) {
  double p_prev = 1.0;  // P_0
  double p_cur = x;     // P_1
  for (int k = 1; k < n; ++k) {
    const double p_next = ((2.0 * k + 1.0) * x * p_cur - k * p_prev) / (k + 1.0);
    p_prev = p_cur;
    p_cur = p_next;
  }
  p = n == 0 ? 1.0 : p_cur;
  // P_n'(x) = n (x P_n - P_{n-1}) / (x^2 - 1); the nodes are interior, so x^2 < 1.
  dp = n * (x * p_cur - p_prev) / ((x - 1.0) * (x + 1.0));
}

// Nodes: Newton on P_n from the asymptotic guess x_k ~ cos(pi (k - 1/4) / (n + 1/2)), which lies
// close enough to the k-th root (counted from +1) for Newton to converge to it. Weights:
// w_k = 2 / ((1 - x_k^2) P_n'(x_k)^2).
std::unique_ptr<GaussLegendreRule> compute_rule(int n) {
  auto rule = std::make_unique<GaussLegendreRule>();
  const auto size = static_cast<std::size_t>(n);
  rule->nodes.assign(size, 0.0);
  rule->weights.assign(size, 0.0);
  const int half = (n + 1) / 2;
  for (int k = 1; k <= half; ++k) {
    double x = std::cos(kPi * (k - 0.25) / (n + 0.5));
    double p = 0.0;
    double dp = 0.0;
    for (int it = 0; it < kNewtonMaxIterations; ++it) {
      legendre(n, x, p, dp);
      const double step = p / dp;
      x -= step;
      if (std::fabs(step) < kNewtonStep) break;
    }
    legendre(n, x, p, dp);
    const double w = 2.0 / ((1.0 - x) * (1.0 + x) * dp * dp);
    // Root k counted from +1 downwards; store ascending and mirror, so the rule is exactly symmetric.
    const auto hi = static_cast<std::size_t>(n - k);
    const auto lo = static_cast<std::size_t>(k - 1);
    rule->nodes[hi] = x;
    rule->nodes[lo] = -x;
    rule->weights[hi] = w;
    rule->weights[lo] = w;
  }
  if (n % 2 == 1) rule->nodes[static_cast<std::size_t>(n / 2)] = 0.0;
  return rule;
}

}  // namespace

const GaussLegendreRule& gauss_legendre(int order) {
  if (order < 1 || order > kMaxOrder) {
    throw std::invalid_argument("gauss_legendre: order " + std::to_string(order) + " outside [1, " +
                                std::to_string(kMaxOrder) + "]");
  }
  static std::mutex mutex;
  static std::map<int, std::unique_ptr<GaussLegendreRule>> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  auto& slot = cache[order];
  if (!slot) slot = compute_rule(order);
  return *slot;
}

void append_panels(double a, double b, const EndRefinement& at_a, const EndRefinement& at_b, double max_width,
                   std::vector<Panel>& out) {
  const double length = b - a;
  if (!(length > 0.0)) return;
  if (!(max_width > 0.0)) throw std::invalid_argument("append_panels: max_width must be positive");

  // Offsets of the graded break points from each end, innermost first.
  const bool both = at_a.refine && at_b.refine;
  const double budget = both ? 0.5 * length : length;
  auto graded_offsets = [&](const EndRefinement& r, double offsets[], int& count) {
    count = 0;
    // The innermost panel obeys max_width like every other.
    const double innermost = std::min(r.min_size, max_width);
    if (!r.refine || !(innermost > 0.0) || innermost >= budget) return;
    double o = innermost;
    offsets[count++] = o;
    while (count < 64) {
      const double next = kGradingRatio * o;
      if (next > budget || next - o > max_width) break;
      o = next;
      offsets[count++] = o;
    }
  };
  double offsets_a[64];
  double offsets_b[64];
  int count_a = 0;
  int count_b = 0;
  graded_offsets(at_a, offsets_a, count_a);
  graded_offsets(at_b, offsets_b, count_b);

  // Break points, ascending.
  double points[64 + 64 + 4096 + 2];
  int n_points = 0;
  points[n_points++] = a;
  for (int k = 0; k < count_a; ++k) points[n_points++] = a + offsets_a[k];
  const double mid_a = count_a > 0 ? a + offsets_a[count_a - 1] : a;
  const double mid_b = count_b > 0 ? b - offsets_b[count_b - 1] : b;
  const double mid_length = mid_b - mid_a;
  if (mid_length > 0.0) {
    const double pieces = std::ceil(mid_length / max_width);
    const int n_mid = pieces > 4096.0 ? 4096 : static_cast<int>(pieces);
    for (int k = 1; k < n_mid; ++k) points[n_points++] = mid_a + mid_length * k / n_mid;
  }
  if (count_b > 0 && mid_length > 0.0) points[n_points++] = mid_b;
  for (int k = count_b - 2; k >= 0; --k) points[n_points++] = b - offsets_b[k];
  points[n_points++] = b;

  const bool map_a = at_a.map_power != 1.0;
  const bool map_b = at_b.map_power != 1.0;
  if (n_points == 2 && map_a && map_b) {
    // One panel cannot carry both maps: halve it.
    const double mid = 0.5 * (a + b);
    out.push_back(Panel{a, mid, at_a.map_power, 1.0});
    out.push_back(Panel{mid, b, 1.0, at_b.map_power});
    return;
  }
  for (int k = 0; k + 1 < n_points; ++k) {
    if (!(points[k + 1] > points[k])) continue;
    Panel panel{points[k], points[k + 1]};
    if (k == 0 && map_a) panel.power_a = at_a.map_power;
    if (k + 2 == n_points && map_b) panel.power_b = at_b.map_power;
    out.push_back(panel);
  }
}

}  // namespace brdfbake::reference
