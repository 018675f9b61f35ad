// The prefiltered environment chain on the device against the brute-force reference
// (host/reference/src/envmap.cpp): white furnace, level 0 = source, a bright texel's lobe, real
// inputs, huge values, odd sizes, schedules and the equirect orientation chart.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/reference/envmap.hpp"
#include "brdfbake/tables.hpp"
#include "families/prefilter/lobes.hpp"
#include "support/device_fixture.hpp"
#include "support/tolerances.hpp"

#ifndef BRDFBAKE_SHARED_DIR
#define BRDFBAKE_SHARED_DIR "../shared"
#endif

namespace brdfbake {
namespace {

namespace fs = std::filesystem;

std::string shared_envmap(const std::string& name) {
  return (fs::path(BRDFBAKE_SHARED_DIR) / "envmaps" / name).string();
}

EnvImage constant_equirect(int width, float r, float g, float b) {
  EnvImage e;
  e.layout = EnvImage::Layout::Equirect;
  e.width = width;
  e.height = width / 2;
  e.source = "constant";
  for (int k = 0; k < e.width * e.height; ++k) e.rgb.insert(e.rgb.end(), {r, g, b});
  return e;
}

CubeLevels constant_cube(int size, float v) {
  CubeLevels c;
  c.size = size;
  c.levels.assign(1, std::vector<float>(24u * size_t(size) * size_t(size), v));
  for (size_t t = 3; t < c.levels[0].size(); t += 4) c.levels[0][t] = 1.0f;
  return c;
}

reference::EnvCube to_reference(const CubeLevels& c) {
  reference::EnvCube e;
  e.size = c.size;
  e.rgb.resize(18u * size_t(c.size) * size_t(c.size));
  for (size_t t = 0; t < e.rgb.size() / 3; ++t)
    for (size_t ch = 0; ch < 3; ++ch) e.rgb[3 * t + ch] = c.levels[0][4 * t + ch];
  return e;
}

struct Errors {
  double rms = 0, max = 0;
};

// Per channel |P - P_ref| / max(P_ref, 1e-3 mean(P_ref)), as bench/prefilter_bench measures.
Errors level_errors(const CubeLevels& got, int level, const reference::EnvCube& want) {
  double mean = 0;
  for (double v : want.rgb) mean += v;
  mean /= double(want.rgb.size());
  Errors e;
  double sum = 0;
  const auto& data = got.levels[size_t(level)];
  for (size_t t = 0; t < want.rgb.size() / 3; ++t)
    for (size_t ch = 0; ch < 3; ++ch) {
      const double w = want.rgb[3 * t + ch];
      const double d = std::fabs(double(data[4 * t + ch]) - w) / std::max(w, 1e-3 * mean);
      sum += d * d;
      e.max = std::max(e.max, d);
    }
  e.rms = std::sqrt(sum / double(want.rgb.size()));
  return e;
}

void expect_all_finite(const CubeLevels& c) {
  for (int l = 0; l < c.level_count(); ++l)
    for (float v : c.levels[size_t(l)]) ASSERT_TRUE(std::isfinite(v)) << "level " << l;
}

class Furnace : public ::testing::TestWithParam<std::tuple<EnvDistribution, EnvEstimator>> {};

// A constant environment gives that constant in every texel of every level.
TEST_P(Furnace, ConstantEverywhere) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  const auto [dist, est] = GetParam();
  PrefilterSpec s;
  s.size = 16;
  s.min_size = 2;
  s.distribution = dist;
  s.estimator = est;
  if (est == EnvEstimator::Sampling) s.samples = 64;
  const float rgb[3] = {2.5f, 0.75f, 1.0f};
  const CubeLevels out = prefilter_environment(*dev, constant_equirect(64, rgb[0], rgb[1], rgb[2]), s);
  ASSERT_EQ(out.level_count(), 4);
  for (int l = 0; l < out.level_count(); ++l)
    for (size_t t = 0; t < out.levels[size_t(l)].size(); t += 4)
      for (size_t ch = 0; ch < 3; ++ch)
        ASSERT_NEAR(out.levels[size_t(l)][t + ch] / rgb[ch], 1.0, test::kEnvFurnace)
            << "level " << l << " texel " << t / 4 << " channel " << ch;
}

INSTANTIATE_TEST_SUITE_P(AllLobes, Furnace,
                         ::testing::Combine(::testing::Values(EnvDistribution::Ggx, EnvDistribution::Charlie),
                                            ::testing::Values(EnvEstimator::Quadrature, EnvEstimator::Sampling)));

// fp64 kernels: the furnace, and the same values as fp32 to fp32's rounding.
// The engine's host-side lobes (host/src/families/prefilter/lobes.cpp: D for the sample tables, the Charlie profile
// for the pyramid's thresholds, W in closed form for the bright texels) against the reference's
// (kernel by its own D, W by adaptive quadrature).
TEST(EnvLobes, EngineMatchesTheReference) {
  for (EnvDistribution d : {EnvDistribution::Ggx, EnvDistribution::Charlie}) {
    const auto lobe = d == EnvDistribution::Ggx ? reference::EnvLobe::Ggx : reference::EnvLobe::Charlie;
    for (double alpha : {1e-3, 0.01, 0.1, 0.3, 1.0 / 3.0, 0.5, 0.8, 0.95, 1.0}) {
      const double w = detail::env_lobe_normalization(d, alpha), want = reference::env_lobe_normalization(lobe, alpha);
      EXPECT_NEAR(w / want, 1.0, test::kAnalytic) << env_distribution_name(d) << " alpha " << alpha;
      for (double c : {-0.5, 0.0, 1e-6, 0.1, 0.5, 0.9, 0.999, 1.0}) {
        const double k = detail::env_lobe_kernel(d, alpha, c), kr = reference::env_lobe_kernel(lobe, alpha, c);
        EXPECT_NEAR(k, kr, test::kRounding * std::max(1.0, std::fabs(kr)))
            << env_distribution_name(d) << " " << alpha << " " << c;
      }
    }
  }
}

TEST(Prefilter, Fp64) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  BRDFBAKE_REQUIRE_FP64(dev);
  const CubeLevels source = environment_to_cube(*dev, builtin_environment("sun", 256), 16);
  for (EnvEstimator est : {EnvEstimator::Quadrature, EnvEstimator::Sampling}) {
    PrefilterSpec s;
    s.size = 16;
    s.min_size = 4;
    s.estimator = est;
    if (est == EnvEstimator::Sampling) s.samples = 256;
    const CubeLevels f32 = prefilter_cube(*dev, source, s);
    s.precision = Precision::Fp64;
    const CubeLevels f64 = prefilter_cube(*dev, source, s);
    EXPECT_EQ(f64.meta("precision"), "fp64");
    for (int l = 1; l < f64.level_count(); ++l)
      for (size_t k = 0; k < f64.levels[size_t(l)].size(); ++k)
        ASSERT_NEAR(double(f64.levels[size_t(l)][k]) / double(f32.levels[size_t(l)][k]), 1.0, test::kEnvFp32VsFp64)
            << env_estimator_name(est) << " level " << l << " value " << k;
  }
  PrefilterSpec s;
  s.size = 8;
  s.min_size = 2;
  s.precision = Precision::Fp64;
  const CubeLevels c = prefilter_environment(*dev, constant_equirect(32, 3.0f, 3.0f, 3.0f), s);
  for (int l = 0; l < c.level_count(); ++l)
    for (size_t k = 0; k < c.levels[size_t(l)].size(); k += 4)
      ASSERT_NEAR(c.levels[size_t(l)][k] / 3.0f, 1.0, test::kEnvFurnace);
}

TEST(Prefilter, LevelZeroIsTheSource) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  const EnvImage env = builtin_environment("studio", 256);
  PrefilterSpec s;
  s.size = 32;
  s.min_size = 8;
  const CubeLevels source = environment_to_cube(*dev, env, 32);
  const CubeLevels out = prefilter_environment(*dev, env, s);
  ASSERT_EQ(out.levels[0].size(), source.levels[0].size());
  for (size_t k = 0; k < source.levels[0].size(); ++k) ASSERT_EQ(out.levels[0][k], source.levels[0][k]) << k;
  EXPECT_EQ(out.meta("roughness_per_level"), "0,0.5,1");
}

// Every level against the brute-force reference filtering the same source cube.
void expect_reference_agreement(Device& dev, const EnvImage& env, EnvDistribution dist, EnvEstimator est, int samples,
                                double rms_bound, double max_bound) {
  PrefilterSpec s;
  s.size = 32;
  s.min_size = 4;
  s.distribution = dist;
  s.estimator = est;
  s.samples = samples;
  const CubeLevels source = environment_to_cube(dev, env, s.size);
  const CubeLevels out = prefilter_cube(dev, source, s);
  expect_all_finite(out);
  const reference::EnvCube src = to_reference(source);
  const auto lobe = dist == EnvDistribution::Ggx ? reference::EnvLobe::Ggx : reference::EnvLobe::Charlie;
  for (int l = 1; l < out.level_count(); ++l) {
    const double r = schedule_roughness(s.schedule, l, out.level_count());
    const reference::EnvCube want = reference::prefilter_cube(src, lobe, r, out.level_size(l));
    const Errors e = level_errors(out, l, want);
    EXPECT_LE(e.rms, rms_bound) << env.source << " " << env_distribution_name(dist) << " level " << l;
    EXPECT_LE(e.max, max_bound) << env.source << " " << env_distribution_name(dist) << " level " << l;
  }
}

TEST(Prefilter, AgreesWithTheReferenceOnBuiltins) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  for (const char* name : {"studio", "sun"})
    for (EnvDistribution d : {EnvDistribution::Ggx, EnvDistribution::Charlie})
      expect_reference_agreement(*dev, builtin_environment(name, 256), d, EnvEstimator::Quadrature, 0,
                                 test::kEnvPrefilterRms, test::kEnvPrefilterMax);
}

TEST(Prefilter, AgreesWithTheReferenceOnARealMap) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  const std::string file = shared_envmap("derived/venice_sunset_256x128_derived.hdr");
  if (!fs::exists(file)) GTEST_SKIP() << "no shared envmaps at " << BRDFBAKE_SHARED_DIR << " (" << file << ")";
  const EnvImage env = load_environment(file);
  for (EnvDistribution d : {EnvDistribution::Ggx, EnvDistribution::Charlie})
    expect_reference_agreement(*dev, env, d, EnvEstimator::Quadrature, 0, test::kEnvPrefilterRms,
                               test::kEnvPrefilterMax);
  // the sampling estimator converges to the same values at a high sample count
  expect_reference_agreement(*dev, env, EnvDistribution::Ggx, EnvEstimator::Sampling, 4096, test::kEnvSamplingRms,
                             test::kEnvSamplingMax);
}

// The default filters blocks of 8 x 8 texels with one walk of the pyramid refined for all of them
// (levels 16^2 and 8^2 here), the former path walks it per texel (4^2 always does): both meet the
// reference's bounds, and the blocks, whose partitions are each texel's own or finer, are no less
// accurate than the per-texel walk (to a tenth of its error plus fp32 rounding).
TEST(Prefilter, BlocksAreAtLeastAsAccurateAsThePerTexelWalk) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  for (const char* name : {"studio", "sun"})
    for (EnvDistribution d : {EnvDistribution::Ggx, EnvDistribution::Charlie}) {
      const EnvImage env = builtin_environment(name, 256);
      PrefilterSpec s;
      s.size = 32;
      s.min_size = 4;
      s.distribution = d;
      const CubeLevels source = environment_to_cube(*dev, env, s.size);
      const CubeLevels blocks = prefilter_cube(*dev, source, s);
      s.strips = false;
      const CubeLevels per_texel = prefilter_cube(*dev, source, s);
      const reference::EnvCube src = to_reference(source);
      const auto lobe = d == EnvDistribution::Ggx ? reference::EnvLobe::Ggx : reference::EnvLobe::Charlie;
      for (int l = 1; l < blocks.level_count(); ++l) {
        const double r = schedule_roughness(s.schedule, l, blocks.level_count());
        const reference::EnvCube want = reference::prefilter_cube(src, lobe, r, blocks.level_size(l));
        const Errors eb = level_errors(blocks, l, want), ep = level_errors(per_texel, l, want);
        const std::string where = std::string(name) + " " + env_distribution_name(d) + " level " + std::to_string(l);
        EXPECT_LE(eb.rms, test::kEnvPrefilterRms) << where;
        EXPECT_LE(ep.rms, test::kEnvPrefilterRms) << where;
        EXPECT_LE(eb.rms, 1.1 * ep.rms + test::kEnvFp32VsFp64) << where;
        if (l == blocks.level_count() - 1) {  // 4^2: no block fits, the same walk
          for (size_t k = 0; k < blocks.levels[size_t(l)].size(); ++k)
            ASSERT_EQ(blocks.levels[size_t(l)][k], per_texel.levels[size_t(l)][k]) << where;
        }
      }
    }
}

// A single bright texel spreads into the lobe the reference predicts, whether it is summed
// exactly (environment sampling) or left in the pyramid.
TEST(Prefilter, BrightTexelSpreadsIntoTheLobe) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  CubeLevels source = constant_cube(16, 0.0f);
  float* t = source.texel(0, 4, 6, 9);
  t[0] = t[1] = t[2] = 1e4f;
  EXPECT_EQ(find_bright_texels(source, 16).size(), 1u);
  const reference::EnvCube src = to_reference(source);
  for (int bright : {-1, 0})
    for (EnvEstimator est : {EnvEstimator::Quadrature, EnvEstimator::Sampling}) {
      // sampling without environment sampling is the firefly case that environment sampling
      // exists for (bench/prefilter_bench measures it)
      if (est == EnvEstimator::Sampling && bright == 0) continue;
      PrefilterSpec s;
      s.size = 16;
      s.min_size = 4;
      s.bright_texels = bright;
      s.estimator = est;
      if (est == EnvEstimator::Sampling) s.samples = 4096;
      const CubeLevels out = prefilter_cube(*dev, source, s);
      for (int l = 1; l < out.level_count(); ++l) {
        const reference::EnvCube want = reference::prefilter_cube(
            src, reference::EnvLobe::Ggx, schedule_roughness(s.schedule, l, out.level_count()), out.level_size(l));
        // where the lobe holds the texel's light (above 5% of the brightest value: nearer the
        // horizon, the pyramid's box texel and the reference's bilinear tent differ at first order
        // on a source this coarse)
        double peak = 0, worst = 0;
        for (double v : want.rgb) peak = std::max(peak, v);
        for (size_t k = 0; k < want.rgb.size() / 3; ++k) {
          const double w = want.rgb[3 * k];
          if (w < 5e-2 * peak) continue;
          worst = std::max(worst, std::fabs(double(out.levels[size_t(l)][4 * k]) - w) / w);
        }
        EXPECT_LE(worst, test::kEnvPrefilterMax)
            << "level " << l << " bright " << bright << " " << env_estimator_name(est);
      }
    }
}

TEST(Prefilter, HugeValuesStayFinite) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  CubeLevels source = constant_cube(8, 1e6f);
  float* t = source.texel(0, 2, 3, 3);
  t[0] = t[1] = t[2] = 3e7f;
  for (EnvDistribution d : {EnvDistribution::Ggx, EnvDistribution::Charlie}) {
    PrefilterSpec s;
    s.size = 8;
    s.min_size = 1;
    s.distribution = d;
    const CubeLevels out = prefilter_cube(*dev, source, s);
    expect_all_finite(out);
    for (int l = 1; l < out.level_count(); ++l)
      for (size_t k = 0; k < out.levels[size_t(l)].size(); k += 4) ASSERT_GE(out.levels[size_t(l)][k], 0.9e6f);
  }
}

TEST(Prefilter, OddAndTinySizes) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  const EnvImage env = constant_equirect(32, 1.0f, 2.0f, 3.0f);
  struct Case {
    int size, min_size, levels;
  };
  for (const Case c : {Case{1, 1, 1}, Case{2, 1, 2}, Case{24, 6, 3}, Case{48, 16, 2}, Case{5, 1, 3}}) {
    PrefilterSpec s;
    s.size = c.size;
    s.min_size = c.min_size;
    const CubeLevels out = prefilter_environment(*dev, env, s);
    ASSERT_EQ(out.level_count(), c.levels) << c.size;
    for (int l = 0; l < out.level_count(); ++l) {
      ASSERT_EQ(out.levels[size_t(l)].size(), 24u * size_t(out.level_size(l)) * size_t(out.level_size(l)));
      for (size_t k = 0; k < out.levels[size_t(l)].size(); k += 4)
        ASSERT_NEAR(out.levels[size_t(l)][k + 1], 2.0f, 2.0 * test::kEnvFurnace) << c.size << " level " << l;
    }
  }
  PrefilterSpec bad;
  bad.size = 0;
  EXPECT_THROW(resolve_prefilter_spec(bad), Error);
  bad.size = 16;
  bad.min_size = 32;
  EXPECT_THROW(resolve_prefilter_spec(bad), Error);
}

TEST(Prefilter, SchedulesAndTheirInverse) {
  for (RoughnessSchedule s : {RoughnessSchedule::Linear, RoughnessSchedule::Filament, RoughnessSchedule::Sqrt})
    for (int levels : {2, 5, 9})
      for (int l = 0; l < levels; ++l) {
        const double r = schedule_roughness(s, l, levels);
        EXPECT_GE(r, 0.0);
        EXPECT_LE(r, 1.0);
        EXPECT_NEAR(schedule_lod(s, r, levels), l, test::kRoundingFewOps) << roughness_schedule_name(s);
      }
  EXPECT_DOUBLE_EQ(schedule_roughness(RoughnessSchedule::Linear, 1, 5), 0.25);
  EXPECT_DOUBLE_EQ(schedule_roughness(RoughnessSchedule::Filament, 1, 5), 1.0 - std::sqrt(0.75));
  EXPECT_DOUBLE_EQ(schedule_roughness(RoughnessSchedule::Sqrt, 1, 5), 0.0625);
}

// The numbers of a comma-separated metadata list ("0,4,3", "0, 128, 512").
std::vector<double> meta_numbers(const std::string& text) {
  std::vector<double> out;
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, ',');) out.push_back(std::stod(item));
  return out;
}

// The RMS relative luminance difference of two levels: --max-error's measure (prefilter.cpp).
double rms_luminance_difference(const std::vector<float>& a, const std::vector<float>& b) {
  auto lum = [](const float* t) { return 0.2126 * double(t[0]) + 0.7152 * double(t[1]) + 0.0722 * double(t[2]); };
  double sum = 0.0;
  size_t n = 0;
  for (size_t t = 0; t + 3 < a.size() && t + 3 < b.size(); t += 4, ++n) {
    const double d = std::fabs(lum(&a[t]) - lum(&b[t])) / std::max(std::fabs(lum(&b[t])), 1e-30);
    sum += d * d;
  }
  return std::sqrt(sum / double(std::max<size_t>(n, 1)));
}

// --max-error chooses each level's refinement (quadrature) or sample count (sampling) from its own
// measurement: the recorded choices are steps of the search, the recorded measurements are those of
// the kept results and within the target, and a target just below the worst level's measurement
// moves that level alone to a finer step, leaving every other level's choice and texels as they
// were. Sizes where the choices differ between levels: quadrature on 64^2 .. 8^2 (the refinement
// matters on level 1 only; below it, every texel is refined at the first step), sampling on
// 16^2 .. 4^2.
TEST(Prefilter, MaxErrorChoosesPerLevel) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  const std::vector<double> steps = {3.0, 4.0, 6.0, 8.0, 12.0, 16.0};  // after the first, 2
  for (EnvEstimator estimator : {EnvEstimator::Quadrature, EnvEstimator::Sampling}) {
    const bool quadrature = estimator == EnvEstimator::Quadrature;
    SCOPED_TRACE(env_estimator_name(estimator));
    PrefilterSpec s;
    s.size = quadrature ? 64 : 16;
    s.min_size = quadrature ? 8 : 4;
    s.estimator = estimator;
    s.max_error = quadrature ? 0.002 : 0.02;
    const size_t levels = quadrature ? 4 : 3;
    const CubeLevels source = environment_to_cube(*dev, builtin_environment("studio", 256), s.size);
    const char* choice_key = quadrature ? "refinement_per_level" : "samples_per_level";
    PrefilterTiming timing;
    const CubeLevels a = prefilter_cube(*dev, source, s, &timing);
    const std::vector<double> choice = meta_numbers(a.meta(choice_key));
    const std::vector<double>& measured = timing.measured_error_per_level;
    ASSERT_EQ(choice.size(), levels);
    ASSERT_EQ(measured.size(), levels);
    EXPECT_EQ(choice[0], 0.0) << "level 0 is the source";
    EXPECT_EQ(measured[0], 0.0);
    for (size_t l = 1; l < levels; ++l) {
      if (quadrature) {
        EXPECT_NE(std::find(steps.begin(), steps.end(), choice[l]), steps.end()) << "level " << l << ": " << choice[l];
      } else {  // 4 n, n = 32, 64, ... (the 4n result of the pair (n, 4n) is kept)
        const double n = choice[l] / 4.0;
        EXPECT_TRUE(n >= 32 && n <= 2048 && std::exp2(std::round(std::log2(n))) == n)
            << "level " << l << ": " << choice[l];
      }
      EXPECT_GE(measured[l], 0.0) << "level " << l;
      EXPECT_LE(measured[l], s.max_error) << "level " << l;
    }
    // the file records what was measured
    std::string text = "source";  // level 0: nothing refined
    for (size_t l = 1; l < levels; ++l) {
      char v[32];
      std::snprintf(v, sizeof v, "%.3g", measured[l]);
      text += "," + std::string(v);
    }
    EXPECT_EQ(a.meta("refinement_difference_per_level"), text);
    const size_t worst = size_t(std::max_element(measured.begin(), measured.end()) - measured.begin());
    EXPECT_EQ(timing.measured_error, measured[worst]);
    ASSERT_GT(measured[worst], 0.0) << "no level was measured: the search compared nothing";

    // A target just below the worst level's measurement: that level goes on to a finer step; the
    // others meet it where they stopped, with the same measurement and the same texels.
    PrefilterSpec tighter = s;
    tighter.max_error = measured[worst] * 0.99;
    PrefilterTiming t2;
    if (choice[worst] == (quadrature ? steps.back() : 8192.0)) {  // the last step: nothing finer to go to
      EXPECT_THROW(prefilter_cube(*dev, source, tighter, &t2), Error);
      continue;
    }
    const CubeLevels b = prefilter_cube(*dev, source, tighter, &t2);
    const std::vector<double> choice2 = meta_numbers(b.meta(choice_key));
    ASSERT_EQ(choice2.size(), levels);
    ASSERT_EQ(t2.measured_error_per_level.size(), levels);
    EXPECT_GT(choice2[worst], choice[worst]) << "level " << worst << " kept its choice above the target";
    EXPECT_LE(t2.measured_error_per_level[worst], tighter.max_error);
    EXPECT_EQ(b.levels[0], a.levels[0]);
    int kept = 0;
    for (size_t l = 1; l < levels; ++l) {
      if (l == worst || measured[l] > tighter.max_error) continue;
      ++kept;
      EXPECT_EQ(choice2[l], choice[l]) << "level " << l;
      EXPECT_EQ(t2.measured_error_per_level[l], measured[l]) << "level " << l;
      EXPECT_EQ(b.levels[l], a.levels[l]) << "level " << l;
    }
    EXPECT_GT(kept, 0) << "no other level to hold still";
    // Quadrature, one step further: the search compared the two kept results, so its measurement
    // is their difference, recomputed here from the texels.
    const auto at = std::find(steps.begin(), steps.end(), choice[worst]);
    if (quadrature && at != steps.end() && at + 1 != steps.end() && *(at + 1) == choice2[worst])
      EXPECT_DOUBLE_EQ(rms_luminance_difference(a.levels[worst], b.levels[worst]), t2.measured_error_per_level[worst]);
    else if (quadrature)
      std::printf("level %zu went from refinement %g to %g: the measurement is not recomputed\n", worst, choice[worst],
                  choice2[worst]);
  }
}

// Every chain records its error bound (families/prefilter/bound.cpp), with or without max_error:
// every level's is above 0 (a max_error search's difference of successive refinements is 0 on
// every Charlie level and on a GGX chain's last), and it holds: at least the RMS relative luminance
// distance of the stored level from the double reference over all its texels (the sample the bake
// compared was a few dozen of them), on a sun (a bright spot: the hardest case) and a studio.
TEST(Prefilter, RecordsABoundThatHoldsOnEveryLevel) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  const std::shared_ptr<Backend> backend = Backend::open(*dev);
  for (const char* env_name : {"sun", "studio"})
    for (const char* dist : {"ggx", "charlie"})
      for (double max_error : {0.0, 0.02}) {
        if (std::string(env_name) == "studio" && max_error > 0) continue;  // the sun's cases are the hard ones
        SCOPED_TRACE(std::string(env_name) + " " + dist + " max_error " + std::to_string(max_error));
        const EnvImage env = builtin_environment(env_name, 128);
        TableRequest q;
        q.kind = TableKind::Prefilter;
        q.environment = std::string("builtin:") + env_name;
        q.params = {{"distribution", std::string(dist)}, {"size", 32.0}, {"min_size", 2.0}};
        if (max_error > 0) q.params.push_back({"max_error", max_error});
        validate_table(q);
        BakeInputs in;
        in.environment = &env;
        const BakeResult r = bake_table(q, *backend, in);
        ASSERT_TRUE(r.error_bound.has_value()) << "recorded without max_error too";
        const CubeLevels& c = *r.cube();
        const std::vector<double> bound = meta_numbers(c.meta("integration_error_bound_per_level"));
        const std::vector<double> roughness = meta_numbers(c.meta("roughness_per_level"));
        ASSERT_EQ(bound.size(), size_t(c.level_count()));
        const reference::EnvCube source = to_reference(c);
        const reference::EnvLobe lobe =
            std::string(dist) == "ggx" ? reference::EnvLobe::Ggx : reference::EnvLobe::Charlie;
        for (int l = 0; l < c.level_count(); ++l) {
          EXPECT_GT(bound[size_t(l)], 0.0) << "level " << l;
          // the per-level text is rounded up to 3 significant digits
          EXPECT_LE(bound[size_t(l)], *r.error_bound * 1.01) << "level " << l << ": the file's bound is the largest";
          if (l == 0) continue;
          const int n = c.level_size(l);
          const reference::EnvCube want = reference::prefilter_cube(source, lobe, roughness[size_t(l)], n, 0);
          double y_max = 0.0;
          std::vector<double> y_ref(want.rgb.size() / 3);
          for (size_t t = 0; t < y_ref.size(); ++t) {
            y_ref[t] = 0.2126 * want.rgb[3 * t] + 0.7152 * want.rgb[3 * t + 1] + 0.0722 * want.rgb[3 * t + 2];
            y_max = std::max(y_max, y_ref[t]);
          }
          double sum = 0.0;
          for (size_t t = 0; t < y_ref.size(); ++t) {
            const float* p = &c.levels[size_t(l)][4 * t];
            const double y = 0.2126 * double(p[0]) + 0.7152 * double(p[1]) + 0.0722 * double(p[2]);
            const double d = std::fabs(y - y_ref[t]) / std::max(y_ref[t], 1e-6 * y_max);
            sum += d * d;
          }
          const double rms = std::sqrt(sum / double(y_ref.size()));
          EXPECT_GE(bound[size_t(l)], rms) << "level " << l << " (" << n << "^2)";
        }
      }
}

// Progress follows the rows of each level (the first levels hold most of the work: a progress line
// that moved only between levels sat at 0% through most of a bake), goes only forward, and names
// the refinement a --max-error search is at.
TEST(Prefilter, ProgressMovesWithinEveryLevel) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  const CubeLevels source = environment_to_cube(*dev, builtin_environment("studio", 256), 64);
  for (double max_error : {0.0, 0.01}) {
    PrefilterSpec s;
    s.size = 64;
    s.min_size = 16;  // levels 64, 32, 16: level 1 holds 4/5 of the filtered texels
    s.max_error = max_error;
    std::vector<double> f;
    std::vector<std::string> labels;
    prefilter_cube(*dev, source, s, nullptr, [&](double x, const std::string& label) {
      f.push_back(x);
      labels.push_back(label);
    });
    ASSERT_FALSE(f.empty());
    for (size_t k = 1; k < f.size(); ++k) EXPECT_GE(f[k], f[k - 1]) << labels[k];
    EXPECT_EQ(f.back(), 1.0);
    int inside_level_one = 0;
    for (size_t k = 0; k < f.size(); ++k)
      inside_level_one += f[k] > 0.0 && f[k] < 0.8 && labels[k].rfind("level 1/2", 0) == 0;
    // a level runs as at least 4 launches when progress is followed (more where it is slow: each
    // launch takes ~50 ms at most), so level 1 reports at least 3 times before it ends
    EXPECT_GE(inside_level_one, 3) << "max_error " << max_error;
    bool refinement = false;
    for (const auto& l : labels) refinement |= l.find("refinement") != std::string::npos;
    EXPECT_EQ(refinement, max_error > 0.0);
  }
}

// Progress moves with the work: each level's share of the line (from its first report to the next
// level's) is its share of the device time within a factor of 4 where that is 10 % or more (the
// estimate of a quadrature walk counts the texels it refines; a small level's device time varies
// by 2x between runs on a loaded machine), for a Charlie
// chain (whose rough levels cost many times more a texel than its sharp ones: weighted by texel
// count, the line sat near its end through most of the bake) and a GGX one; it only goes forward,
// and no step jumps by half the line.
TEST(Prefilter, ProgressMovesWithTheWork) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  const CubeLevels source = environment_to_cube(*dev, builtin_environment("studio", 256), 64);
  for (EnvDistribution d : {EnvDistribution::Charlie, EnvDistribution::Ggx}) {
    SCOPED_TRACE(env_distribution_name(d));
    PrefilterSpec s;
    s.size = 64;
    s.min_size = 4;
    s.distribution = d;
    // Up to 3 runs: the device time of a small level doubles now and then on a loaded machine; a
    // line weighted by texels alone fails every run (a Charlie level with 20-40 % of the time
    // held 4.7 % of the line).
    std::string misfit;
    for (int attempt = 0; attempt < 3; ++attempt) {
      std::vector<double> f;
      std::vector<std::string> labels;
      PrefilterTiming timing;
      prefilter_cube(*dev, source, s, &timing, [&](double x, const std::string& label) {
        f.push_back(x);
        labels.push_back(label);
      });
      ASSERT_GE(f.size(), 2u);
      for (size_t k = 1; k < f.size(); ++k) {
        EXPECT_GE(f[k], f[k - 1]) << labels[k];
        EXPECT_LE(f[k] - f[k - 1], 0.5) << labels[k - 1] << " -> " << labels[k];
      }
      const size_t levels = timing.level_device_seconds.size();
      ASSERT_EQ(levels, 5u);
      double total = 0.0;
      for (size_t l = 1; l < levels; ++l) total += timing.level_device_seconds[l];
      misfit.clear();
      for (size_t l = 1; l < levels; ++l) {
        const std::string name = "level " + std::to_string(l) + "/", next = "level " + std::to_string(l + 1) + "/";
        double begin = -1.0, end = 1.0;
        for (size_t k = 0; k < f.size(); ++k) {
          if (begin < 0 && labels[k].rfind(name, 0) == 0) begin = f[k];
          if (labels[k].rfind(next, 0) == 0) {
            end = f[k];
            break;
          }
        }
        ASSERT_GE(begin, 0.0) << name;
        const double share = end - begin, time_share = timing.level_device_seconds[l] / total;
        if (time_share < 0.1) continue;  // a level of a few ms: its time varies most with the load
        if (share < time_share / 4.0 || share > time_share * 4.0)
          misfit += name + " has " + std::to_string(share) + " of the line, " + std::to_string(time_share) +
                    " of the device time; ";
      }
      if (misfit.empty()) break;
    }
    EXPECT_EQ(misfit, "");
  }
}

// OrientationLatLong.exr (OpenEXR's chart) draws, at the four horizon views, short black lines
// towards the positive axes: from +X towards +Z, from +Z towards +X, from -X towards +Z, from -Z
// towards +X, and from each view up towards +Y. The cube converted on the device must be black
// 5 degrees along each line, and not black (white, or the chart's light blue text) 5 degrees the
// other way along the horizon.
TEST(Prefilter, EquirectOrientationChart) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  const std::string file = shared_envmap("OrientationLatLong.exr");
  if (!fs::exists(file)) GTEST_SKIP() << "no shared envmaps at " << BRDFBAKE_SHARED_DIR << " (" << file << ")";
  const CubeLevels cube = environment_to_cube(*dev, load_environment(file), 256);
  const int n = cube.size;
  // the darkest luminance within one texel of the direction
  auto darkest = [&](double x, double y, double z) {
    int face = 0;
    double a = 0, b = 0;
    math::cube_face_coords({x, y, z}, face, a, b);
    const int ci = std::clamp(int(std::floor(0.5 * (a + 1) * n)), 0, n - 1);
    const int cj = std::clamp(int(std::floor(0.5 * (b + 1) * n)), 0, n - 1);
    double lum = 1e9;
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di) {
        const float* t = cube.texel(0, face, std::clamp(ci + di, 0, n - 1), std::clamp(cj + dj, 0, n - 1));
        lum = std::min(lum, (double(t[0]) + double(t[1]) + double(t[2])) / 3.0);
      }
    return lum;
  };
  const double c = std::cos(5.0 * M_PI / 180.0), s = std::sin(5.0 * M_PI / 180.0);
  struct Probe {
    const char* what;
    double x, y, z;
    bool dark;
  };
  const Probe probes[] = {
      {"+X towards +Z", c, 0, s, true},   {"+X towards -Z", c, 0, -s, false},  {"+Z towards +X", s, 0, c, true},
      {"+Z towards -X", -s, 0, c, false}, {"-X towards +Z", -c, 0, s, true},   {"-X towards -Z", -c, 0, -s, false},
      {"-Z towards +X", s, 0, -c, true},  {"-Z towards -X", -s, 0, -c, false}, {"+X up", c, s, 0, true},
      {"+Z up", 0, s, c, true},           {"-X up", -c, s, 0, true},           {"-Z up", 0, s, -c, true},
  };
  for (const Probe& p : probes) {
    const double lum = darkest(p.x, p.y, p.z);
    if (p.dark)
      EXPECT_LT(lum, 0.3) << p.what;
    else
      EXPECT_GT(lum, 0.5) << p.what;
  }
}

}  // namespace
}  // namespace brdfbake
