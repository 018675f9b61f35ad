// Error bounds on inputs whose errors are known, each asserted to its exact value where a term
// decides, so that a changed factor, a dropped term or a floor moved fails (issue 35: with the chain
// bound's safety factor set to 1, the test that compares a bake's bound with the level's error over
// all its texels still passed, the sample's largest difference alone covering that error; a halved
// preview reference bound was caught only by another test's precondition):
// - the prefiltered chain's (host/src/families/prefilter/bound.cpp): max(2 x RMS, the largest
//   difference, 1e-6) per level;
// - the preview reference's per sphere (host/src/families/preview/render.cpp, reference_bound).
// All on the scalar reference: no OpenCL device.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/reference/envmap.hpp"
#include "env/reference_cube.hpp"
#include "families/prefilter/model.hpp"
#include "families/preview/render.hpp"

namespace brdfbake {
namespace {

using detail::ChainBound;
using detail::LevelBound;

// ---- Tolerances, each with its reason ---------------------------------------------------------------

// Sums of a few doubles: EXPECT_DOUBLE_EQ's 4 ulps. A level stored in float32: each channel of (1 + e) x the reference
// rounded once (2^-24 relative), the luminance of three of them, and the reference itself rounded to float in the
// source: a relative difference comes back to e within 2e-7; 1e-6 leaves a margin and still tells 2 e from e (e = 1e-2
// below).
constexpr double kFloatLevel = 1e-6;

// ---- The level's bound from its sample's differences (level_bound) ---------------------------------

TEST(ChainBound, TheSafetyFactorDecidesOnAnEvenSample) {
  // Every texel off by the same amount: RMS = largest = 3e-3, so 2 x RMS decides (a factor of 1
  // would record the largest, 3e-3).
  const LevelBound b = detail::level_bound({3e-3, 3e-3, 3e-3, 3e-3});
  EXPECT_DOUBLE_EQ(b.rms, 3e-3);
  EXPECT_DOUBLE_EQ(b.worst, 3e-3);
  EXPECT_DOUBLE_EQ(b.bound, 6e-3);
  // Two values: RMS sqrt((9 + 16) / 2) 1e-3, 2 x RMS = sqrt(50) 1e-3 = 7.07e-3 above the largest 4e-3.
  const LevelBound c = detail::level_bound({3e-3, 4e-3});
  EXPECT_DOUBLE_EQ(c.rms, std::sqrt(12.5) * 1e-3);
  EXPECT_DOUBLE_EQ(c.bound, std::sqrt(50.0) * 1e-3);
}

TEST(ChainBound, TheLargestDifferenceDecidesWhereOneTexelHoldsTheError) {
  // One texel of nine off by 3e-2 (a sun's edge), the rest exact: RMS 1e-2, 2 x RMS 2e-2, the
  // largest 3e-2 decides (a safety factor above 3 would record more).
  std::vector<double> d(9, 0.0);
  d[4] = 3e-2;
  const LevelBound b = detail::level_bound(d);
  EXPECT_DOUBLE_EQ(b.rms, 1e-2);
  EXPECT_DOUBLE_EQ(b.worst, 3e-2);
  EXPECT_DOUBLE_EQ(b.bound, 3e-2);
  // Where the two terms meet: one texel of four off by 0.5: RMS 0.25, 2 x RMS = the largest = 0.5.
  const LevelBound e = detail::level_bound({0.0, 0.5, 0.0, 0.0});
  EXPECT_DOUBLE_EQ(e.rms, 0.25);
  EXPECT_DOUBLE_EQ(e.bound, 0.5);
}

TEST(ChainBound, TheFloorDecidesForAnExactLevel) {
  // fp32 rounding: no level that is compared records 0, nor less than 1e-6.
  EXPECT_EQ(detail::level_bound({0.0, 0.0, 0.0}).bound, 1e-6);
  EXPECT_EQ(detail::level_bound({1e-8, 2e-7}).bound, 1e-6);
  const LevelBound empty = detail::level_bound({});
  EXPECT_EQ(empty.bound, 1e-6);
  EXPECT_EQ(empty.rms, 0.0);
  // Just above the floor, the factor decides again: 2 x 6e-7.
  EXPECT_DOUBLE_EQ(detail::level_bound({6e-7, 6e-7}).bound, 1.2e-6);
}

// ---- The sample's differences (relative_differences) ------------------------------------------------

TEST(ChainBound, DifferencesAreRelativeToTheReferenceAndToAMillionthOfTheBrightest) {
  // 101 against 100: 1 %; 0.5 against 0.25: 100 %; a black texel (0) read as 1e-5 is measured
  // against 1e-6 of the brightest sample (100): 1e-5 / 1e-4 = 0.1, not infinite.
  const std::vector<double> d = detail::relative_differences({101.0, 0.5, 1e-5}, {100.0, 0.25, 0.0});
  ASSERT_EQ(d.size(), 3u);
  EXPECT_DOUBLE_EQ(d[0], 0.01);
  EXPECT_DOUBLE_EQ(d[1], 1.0);
  EXPECT_DOUBLE_EQ(d[2], 0.1);
  // Below the stored value as above it.
  EXPECT_DOUBLE_EQ(detail::relative_differences({99.0}, {100.0})[0], 0.01);
  // An all-black level read back black: 0, not 0 / 0.
  EXPECT_EQ(detail::relative_differences({0.0, 0.0}, {0.0, 0.0}), (std::vector<double>{0.0, 0.0}));
  EXPECT_THROW(detail::relative_differences({1.0}, {1.0, 2.0}), std::invalid_argument);
}

// ---- The bound a file records (chain_recorded_bound) ------------------------------------------------

TEST(ChainBound, AMaxErrorSearchsMeasurementIsRecordedWhereItIsLarger) {
  ChainBound c;
  c.bound = 2e-3;
  EXPECT_EQ(detail::chain_recorded_bound(c, 0.0, 5e-3), 2e-3) << "without max_error, no search was measured";
  EXPECT_EQ(detail::chain_recorded_bound(c, 1e-2, 5e-3), 5e-3) << "the search's difference decides";
  EXPECT_EQ(detail::chain_recorded_bound(c, 1e-2, 1e-3), 2e-3) << "the comparison decides";
}

// ---- The whole comparison on a chain with planted errors (chain_error_bound) ------------------------

// A chain of face size 8 (levels 8, 4, 2) whose levels 1 and 2 are the double reference's own
// prefiltered levels (what the comparison measures against), stored in float32, then given errors:
// a level's every texel x (1 + e), so every difference is e; or one texel off, the brightest (always
// in the sample).
struct Chain {
  CubeLevels cube;
  std::vector<double> roughness{0.0, 0.5, 1.0};
};

Chain exact_chain() {
  Chain c;
  c.cube.size = 8;
  reference::EnvCube source;
  source.size = 8;
  source.rgb.assign(size_t(6 * 8 * 8 * 3), 0.0);
  for (int f = 0; f < 6; ++f)
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 8; ++i)
        for (int ch = 0; ch < 3; ++ch)  // a smooth sky, a bright texel on +Y, coloured
          source.at(f, i, j, ch) =
              double(float(0.2 + 0.05 * (i + 2 * j) / 8.0 + 0.1 * ch + (f == 2 && i == 3 && j == 4 ? 40.0 : 0.0)));
  c.cube.levels.push_back(detail::to_rgba(source));
  const reference::EnvCube level0 = detail::to_reference_cube(c.cube.levels[0], 8);
  for (int l = 1; l < 3; ++l) {
    const reference::EnvCube want =
        reference::prefilter_cube(level0, reference::EnvLobe::Ggx, c.roughness[size_t(l)], 8 >> l);
    c.cube.levels.push_back(detail::to_rgba(want));
  }
  return c;
}

// The texel of the level with the largest luminance: the one the sample always holds.
float* brightest(CubeLevels& cube, int level) {
  float* best = nullptr;
  double y_best = -1.0;
  const int n = cube.level_size(level);
  for (int f = 0; f < 6; ++f)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        float* t = cube.texel(level, f, i, j);
        const double y = 0.2126 * double(t[0]) + 0.7152 * double(t[1]) + 0.0722 * double(t[2]);
        if (y > y_best) y_best = y, best = t;
      }
  return best;
}

TEST(ChainBound, AChainWithPlantedErrorsRecordsTwiceAnEvenErrorAndTheLargestOfOne) {
  Chain c = exact_chain();
  // Level 1: every texel 1 % high, so 2 x RMS decides: 2 %. Level 2: only its brightest texel 5 %
  // high; the level (2 x 2 faces, 24 texels) is compared whole, so its RMS is 5 % / sqrt(24) and 2 x
  // RMS = 2.04 %: the largest decides, 5 %.
  for (float& v : c.cube.levels[1]) v = float(double(v) * 1.01);
  float* b = brightest(c.cube, 2);
  for (int ch = 0; ch < 3; ++ch) b[ch] = float(double(b[ch]) * 1.05);
  const ChainBound exact = detail::chain_error_bound(exact_chain().cube, EnvDistribution::Ggx, c.roughness);
  const ChainBound planted = detail::chain_error_bound(c.cube, EnvDistribution::Ggx, c.roughness);
  ASSERT_EQ(planted.per_level.size(), 3u);
  EXPECT_EQ(planted.samples[2], 24) << "a level of 24 texels is compared whole";

  // The exact chain: every level at the floor (its levels are the reference rounded to float).
  for (size_t l = 0; l < 3; ++l) EXPECT_EQ(exact.per_level[l], 1e-6) << "level " << l;
  EXPECT_EQ(planted.per_level[0], 1e-6) << "level 0 is the source: the floor";
  EXPECT_NEAR(planted.max_difference[1], 0.01, kFloatLevel);
  EXPECT_NEAR(planted.per_level[1], 0.02, kFloatLevel) << "2 x the RMS of an even 1 %";
  EXPECT_NEAR(planted.max_difference[2], 0.05, kFloatLevel);
  EXPECT_NEAR(planted.per_level[2], 0.05, kFloatLevel) << "the largest: 5 % on one texel of 24";
  EXPECT_EQ(planted.bound, *std::max_element(planted.per_level.begin(), planted.per_level.end()));
}

// ---- The preview reference's bound per sphere (reference_bound) ------------------------------------

TEST(PreviewReferenceBound, TwiceTheRmsAndTheMaxOfTheFinerDifferencesAndTheFloor) {
  // four bound pixels, differences 1e-3, 1e-3, 1e-3 and 3e-3 from the render at twice the refinement:
  // RMS sqrt(12 / 4) 1e-3, max 3e-3; each x 2, plus 0.05 % (what the independent check resolved
  // beyond the refinement's difference: brdfbake/preview.hpp, kPreviewBoundFloor)
  const detail::preview::ReferenceBound b = detail::preview::reference_bound({1e-3, 1e-3, 1e-3, 3e-3});
  EXPECT_DOUBLE_EQ(b.rms, 2.0 * std::sqrt(3.0) * 1e-3 + 5e-4);
  EXPECT_DOUBLE_EQ(b.max, 6e-3 + 5e-4);
  // a sphere the refinement does not move (the mirror: its differences the float sums' 1e-6): the
  // floor decides, as for the roughness-0.05 metals that stated 0.004 % before it
  const detail::preview::ReferenceBound m = detail::preview::reference_bound({1e-6, 1e-6, 1e-6});
  EXPECT_DOUBLE_EQ(m.rms, 2e-6 + 5e-4);
  EXPECT_DOUBLE_EQ(m.max, 2e-6 + 5e-4);
}

}  // namespace
}  // namespace brdfbake
