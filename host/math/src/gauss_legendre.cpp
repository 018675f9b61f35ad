#include "brdfbake/math/gauss_legendre.hpp"

#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

#include "brdfbake/math/conventions.hpp"

namespace brdfbake::math {
namespace {

// Newton's iteration on P_n stops when the step is below this: the node is then exact to rounding
// (Newton converges quadratically, so the step after a 1e-15 step is far below double precision).
constexpr double kNewtonStep = 1e-15;
constexpr int kNewtonMaxIterations = 100;

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
// w_k = 2 / ((1 - x_k^2) P_n'(x_k)^2) (Abramowitz & Stegun 25.4.29).
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
  if (order < 1 || order > kMaxGaussLegendreOrder) {
    throw std::invalid_argument("gauss_legendre: order " + std::to_string(order) + " outside [1, " +
                                std::to_string(kMaxGaussLegendreOrder) + "]");
  }
  static std::mutex mutex;
  static std::map<int, std::unique_ptr<GaussLegendreRule>> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  auto& slot = cache[order];
  if (!slot) slot = compute_rule(order);
  return *slot;
}

}  // namespace brdfbake::math
