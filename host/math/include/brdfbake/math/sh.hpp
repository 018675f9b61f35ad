// Real spherical harmonics without the Condon-Shortley phase (Ramamoorthi & Hanrahan 2001's
// convention; the table is in docs/CONVENTIONS.md): index k = l (l + 1) + m, bands l < order
// (order 3: 9 functions, order 5: 25), Y_00 = 1 / (2 sqrt(pi)), Y_1-1 = sqrt(3 / 4pi) y,
// Y_10 = sqrt(3 / 4pi) z, Y_11 = sqrt(3 / 4pi) x, ...
#pragma once

#include <vector>

#include "brdfbake/math/types.hpp"

namespace brdfbake::math {

inline constexpr int kMaxShOrder = 5;

// The index of Y_lm in a coefficient list.
constexpr int sh_index(int l, int m) { return l * (l + 1) + m; }

// Y_k(d) for k < order^2, d a unit vector. Throws std::invalid_argument for an order outside
// 1..kMaxShOrder.
std::vector<double> sh_basis(int order, const Vec3& d);

// Ramamoorthi & Hanrahan 2001, eq. 8-9: the SH coefficients A_l of the clamped cosine lobe, so that
// the irradiance is E(n) = sum A_l L_lm Y_lm(n): A_0 = pi, A_1 = 2 pi / 3, A_2 = pi / 4, A_3 = 0,
// A_4 = -pi / 24. Throws std::invalid_argument for l outside 0..4.
double sh_cosine_lobe(int l);

}  // namespace brdfbake::math
