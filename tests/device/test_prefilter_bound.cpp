// The chain's error bound with its reference summed on the device (families/prefilter/bound_device.cpp,
// kernels/prefilter_bound.cl) against the scalar double reference it stands for
// (host/reference/src/prefilter.cpp, prefilter_directions): the values at sample directions, and the
// bound a chain records, whichever computes them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "brdfbake/backend.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/reference/envmap.hpp"
#include "env/reference_cube.hpp"
#include "families/prefilter/bound_kernel.hpp"
#include "families/prefilter/model.hpp"
#include "support/device_fixture.hpp"

namespace brdfbake {
namespace {

// The device's sums against the reference's: the same terms (the solid angles to the bit, from the
// same corner table, or the device's own atan2 along a row where the table is not given), each
// direction, solid angle and lobe value within a few roundings of the reference's (a reciprocal for a
// division, (1 + c) / 2 for the square of sqrt((1 + c) / 2), contracted multiply-adds; Charlie's
// exp and log within OpenCL's 3 ulps, times its exponent 1 / (2 alpha) <= 8 here), bilinear weights
// within a rounding of the position (x ~ size, so 1e-16 x 64 of a texel), added in another order
// (rows of at most 256 sub-cells, then the rows: ~1e5 positive terms, each sum's relative error
// below 1e5 x 1.1e-16 = 1e-11 in the worst case). The largest term of a sum here, a sun's texel
// against a sky of ~1e-3 of it, amplifies a weight's rounding at most 1e3-fold: 1e-12. Measured on
// PoCL: 2.2e-14 at most (GGX and Charlie); 1e-10 leaves a margin of ~5000 and is 4 orders below
// the smallest bound a chain records (kChainBoundFloor, 1e-6).
constexpr double kDeviceReference = 1e-10;

// A source cube of face `size` from a builtin environment with a sun, converted on the device.
CubeLevels sun_cube(Device& dev, int size) { return environment_to_cube(dev, builtin_environment("sun", 256), size); }

// Sample directions: every texel centre of a 4 x 4 level (96: two launches of 64 at most), and
// points near the faces' edges and corners (the bilinear's neighbouring faces).
std::vector<Vec3> sample_directions() {
  std::vector<Vec3> dirs;
  for (int f = 0; f < 6; ++f)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) dirs.push_back(math::cube_texel_direction(f, 4, i, j));
  for (const Vec3& p :
       {Vec3{1.0, 0.999, 0.3}, Vec3{-1.0, 0.998, -0.999}, Vec3{0.2, -1.0, 0.9999}, Vec3{1.0, 1.0, 1.0}}) {
    const double n = std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
    dirs.push_back({p.x / n, p.y / n, p.z / n});
  }
  return dirs;
}

TEST(PrefilterBound, DeviceReferenceEqualsTheDoubleReference) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  BRDFBAKE_REQUIRE_FP64(dev);
  // 16^2: 4 sub-cells a texel side (no corner table: the kernel's atan2); 64^2: one (the table)
  for (int size : {16, 64}) {
    const CubeLevels cube = sun_cube(*dev, size);
    const reference::EnvCube source = detail::to_reference_cube(cube.levels[0], size);
    for (EnvDistribution dist : {EnvDistribution::Ggx, EnvDistribution::Charlie}) {
      const reference::EnvLobe lobe =
          dist == EnvDistribution::Ggx ? reference::EnvLobe::Ggx : reference::EnvLobe::Charlie;
      std::vector<detail::BoundLevelSample> samples;
      for (double r : {0.25, 0.5, 1.0}) {
        detail::BoundLevelSample s;
        s.level = int(samples.size()) + 1;
        s.roughness = r;
        s.subdivision = reference::env_default_subdivision(lobe, r * r, size);
        s.directions = sample_directions();
        samples.push_back(s);
      }
      const std::vector<std::vector<double>> got = detail::device_bound_reference(*dev, cube, dist, samples);
      ASSERT_EQ(got.size(), samples.size());
      double worst = 0.0;
      for (size_t s = 0; s < samples.size(); ++s) {
        SCOPED_TRACE("size " + std::to_string(size) + " " + env_distribution_name(dist) + " roughness " +
                     std::to_string(samples[s].roughness) + " q " + std::to_string(samples[s].subdivision));
        const std::vector<double> want = reference::prefilter_directions(source, lobe, samples[s].roughness,
                                                                         samples[s].directions, samples[s].subdivision);
        ASSERT_EQ(got[s].size(), want.size());
        for (size_t k = 0; k < want.size(); ++k) {
          ASSERT_GT(want[k], 0.0);
          const double d = std::fabs(got[s][k] - want[k]) / want[k];
          worst = std::max(worst, d);
          EXPECT_LE(d, kDeviceReference) << "direction " << k / 3 << " channel " << k % 3 << ": " << got[s][k]
                                         << " against " << want[k];
        }
      }
      std::printf("size %d %s: largest relative difference from the reference %.3g\n", size,
                  env_distribution_name(dist), worst);
    }
  }
}

// The bound a chain records is the same whether its reference was summed on the device or on the
// host: the same sample (the same texels), reference values within kDeviceReference relative, so
// each texel's difference d = |Y - Y_ref| / Y_ref moves by at most (1 + d) kDeviceReference, and a
// level's bound (2 x their RMS, or the largest) by at most twice that. On a sun and a studio, GGX and Charlie, levels
// whose sub-cells take the corner table and levels whose do not.
TEST(PrefilterBound, TheDeviceMeasuresTheHostsBound) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  BRDFBAKE_REQUIRE_FP64(dev);
  const std::shared_ptr<Backend> backend = Backend::open(*dev);
  for (const char* env_name : {"sun", "studio"})
    for (EnvDistribution dist : {EnvDistribution::Ggx, EnvDistribution::Charlie}) {
      SCOPED_TRACE(std::string(env_name) + " " + env_distribution_name(dist));
      PrefilterSpec spec;
      spec.size = 32;
      spec.min_size = 2;
      spec.distribution = dist;
      const CubeLevels cube = prefilter_environment(*dev, builtin_environment(env_name, 128), spec);
      std::vector<double> roughness;
      for (int l = 0; l < cube.level_count(); ++l)
        roughness.push_back(schedule_roughness(spec.schedule, l, cube.level_count()));
      const detail::ChainBound host = detail::chain_error_bound(cube, dist, roughness);
      const detail::ChainBound device = detail::chain_error_bound(*backend, cube, dist, roughness);
      EXPECT_FALSE(host.on_device);
      EXPECT_TRUE(device.on_device) << "an fp64 device sums the reference itself";
      ASSERT_EQ(device.per_level.size(), host.per_level.size());
      EXPECT_EQ(device.samples, host.samples) << "the same sample";
      for (size_t l = 0; l < host.per_level.size(); ++l) {
        const double moves = 2.0 * (1.0 + host.per_level[l]) * kDeviceReference;
        EXPECT_NEAR(device.per_level[l], host.per_level[l], moves) << "level " << l;
        EXPECT_NEAR(device.max_difference[l], host.max_difference[l], moves) << "level " << l;
      }
      EXPECT_NEAR(device.bound, host.bound, 2.0 * (1.0 + host.bound) * kDeviceReference);
    }
}

}  // namespace
}  // namespace brdfbake
