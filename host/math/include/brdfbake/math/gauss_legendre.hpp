// Gauss-Legendre rules: the n-point rule on [-1, 1], exact for polynomials of degree <= 2n - 1,
// computed once per order (Newton's iteration on the Legendre recurrence, in double) and cached.
#pragma once

#include <vector>

namespace brdfbake::math {

struct GaussLegendreRule {
  std::vector<double> nodes;    // ascending, exactly symmetric about 0
  std::vector<double> weights;  // positive, summing to 2
};

// The largest order handed out.
inline constexpr int kMaxGaussLegendreOrder = 512;

// The n-point rule, 1 <= n <= kMaxGaussLegendreOrder; thread-safe. Throws std::invalid_argument
// outside that range.
const GaussLegendreRule& gauss_legendre(int order);

}  // namespace brdfbake::math
