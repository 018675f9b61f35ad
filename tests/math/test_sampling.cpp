// Low-discrepancy sequences of the shared maths: the radical inverse's known values and the
// stratification that makes the Hammersley set a (0, m, 2)-net.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "brdfbake/math/sampling.hpp"

namespace brdfbake::math {
namespace {

TEST(Sampling, RadicalInverseKnownValues) {
  // bits mirrored about the binary point: 1 = 0.1b, 2 = 0.01b, 3 = 0.11b, 6 = 110b -> 0.011b
  EXPECT_EQ(radical_inverse_base2(0), 0.0);
  EXPECT_EQ(radical_inverse_base2(1), 0.5);
  EXPECT_EQ(radical_inverse_base2(2), 0.25);
  EXPECT_EQ(radical_inverse_base2(3), 0.75);
  EXPECT_EQ(radical_inverse_base2(6), 0.375);
  EXPECT_EQ(radical_inverse_base2(0x80000000u), 1.0 / 4294967296.0);
  EXPECT_LT(radical_inverse_base2(0xFFFFFFFFu), 1.0);
}

TEST(Sampling, HammersleyPointsAreStratified) {
  // N = 2^m points: every elementary interval [i / 2^a, (i + 1) / 2^a) x [j / 2^b, (j + 1) / 2^b)
  // with a + b = m holds exactly one point.
  const int m = 8, n = 1 << m;
  std::vector<Point2> p;
  for (int k = 0; k < n; ++k) p.push_back(hammersley(static_cast<std::uint32_t>(k), static_cast<std::uint32_t>(n)));
  for (int a = 0; a <= m; ++a) {
    const int cols = 1 << a, rows = 1 << (m - a);
    std::vector<int> count(static_cast<size_t>(n), 0);
    for (const Point2& q : p) {
      const int i = std::min(cols - 1, static_cast<int>(q.u * cols)),
                j = std::min(rows - 1, static_cast<int>(q.v * rows));
      ++count[static_cast<size_t>(j * cols + i)];
    }
    for (int c : count) ASSERT_EQ(c, 1) << "a = " << a;
  }
  EXPECT_EQ(hammersley(3, 8).u, 3.5 / 8.0);
  EXPECT_EQ(hammersley(3, 8).v, 0.75);
}

}  // namespace
}  // namespace brdfbake::math
