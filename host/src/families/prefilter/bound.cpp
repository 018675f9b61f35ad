// The error bound every prefiltered chain records (docs/CONVENTIONS.md, "Error bounds"): each
// stored level compared with the double reference (host/reference/src/prefilter.cpp, the definition
// itself: the lobe's integral over the bilinear interpolation of level 0) on a deterministic sample
// of its texels. The reference's values are summed by host_bound_reference (the scalar reference
// itself) or, on an OpenCL device with fp64, by bound_device.cpp (kernels/prefilter_bound.cl: the
// same terms, held to the scalar reference by tests/device/test_prefilter_bound.cpp); this file
// chooses the sample and turns the values into the bound.
//
// Per level l >= 1, with Y the luminance of a texel:
//   d_k   = |Y_stored(k) - Y_ref(k)| / max(Y_ref(k), 1e-6 max_k Y_ref(k))   on the sample texels k
//           (relative_differences),
//   bound = max(kChainBoundSafety * RMS_k d_k, max_k d_k, kChainBoundFloor)   (level_bound).
// Both are pure functions of the sample's luminances, tested on inputs with known differences where
// each term decides (tests/host/test_error_bounds.cpp).
// The safety factor and the sample's largest difference stand for what a sample of the level does
// not see (the RMS over a few dozen texels against the RMS over all of them: a sun's neighbourhood
// holds most of a level's error, and the sample holds the brightest texel's); the floor is the fp32
// rounding of a stored value, the preview reference's floor: no level that is not exact records 0.
// Level 0 is the source itself (exact up to its fp32 storage): the floor.
//
// The sample: as many texels as kChainBoundWork reference terms allow (kChainBoundMinSamples to
// kChainBoundMaxSamples a level): the level's brightest texel with its 3 x 3 neighbourhood (a sun's
// edge is where a quadrature errs most; the neighbourhood from kChainBoundNeighbourhood texels on),
// the rest spread over the six faces by the R2 sequence (Roberts 2018, "The Unreasonable
// Effectiveness of Quasirandom Sequences": u_k = frac(0.5 + k / g), v_k = frac(0.5 + k / g^2), g
// the plastic number); a level with no more texels than that is compared whole.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/reference/envmap.hpp"
#include "env/cube.hpp"
#include "env/reference_cube.hpp"
#include "families/prefilter/model.hpp"

namespace brdfbake::detail {

namespace {

struct Texel {
  int face, i, j;
  bool operator==(const Texel& o) const { return face == o.face && i == o.i && j == o.j; }
};

// The `count` sample texels of a level of face size n: the brightest texel with (from
// kChainBoundNeighbourhood texels on) its 3 x 3 neighbourhood within its face, the rest R2 points
// over the faces; the whole level when it has no more texels.
std::vector<Texel> sample_texels(const CubeLevels& cube, int level, int count) {
  const int n = cube.level_size(level);
  std::vector<Texel> out;
  if (6 * n * n <= count) {
    for (int f = 0; f < 6; ++f)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) out.push_back({f, i, j});
    return out;
  }
  auto add = [&](Texel t) {
    if (std::find(out.begin(), out.end(), t) == out.end()) out.push_back(t);
  };
  Texel bright{0, 0, 0};
  double best = -1.0;
  for (int f = 0; f < 6; ++f)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double y = luminance(cube.texel(level, f, i, j));
        if (y > best) {
          best = y;
          bright = {f, i, j};
        }
      }
  const int reach = count >= kChainBoundNeighbourhood ? 1 : 0;
  for (int dj = -reach; dj <= reach; ++dj)
    for (int di = -reach; di <= reach; ++di) {
      const int i = bright.i + di, j = bright.j + dj;
      if (i >= 0 && j >= 0 && i < n && j < n) add({bright.face, i, j});
    }
  constexpr double kG = 1.32471795724474602596;  // the plastic number
  for (int k = 0; static_cast<int>(out.size()) < count && k < 4 * count; ++k) {
    const double u = std::fmod(0.5 + k / kG, 1.0), v = std::fmod(0.5 + k / (kG * kG), 1.0);
    add({k % 6, std::min(int(u * n), n - 1), std::min(int(v * n), n - 1)});
  }
  return out;
}

}  // namespace

std::vector<double> relative_differences(const std::vector<double>& y_stored, const std::vector<double>& y_ref) {
  if (y_stored.size() != y_ref.size())
    throw std::invalid_argument("relative_differences: " + std::to_string(y_stored.size()) + " stored values against " +
                                std::to_string(y_ref.size()) + " reference values");
  double y_max = 0.0;
  for (double y : y_ref) y_max = std::max(y_max, y);
  std::vector<double> d(y_ref.size());
  for (size_t k = 0; k < y_ref.size(); ++k)
    d[k] = std::fabs(y_stored[k] - y_ref[k]) / std::max({y_ref[k], kChainBoundDarkFraction * y_max, 1e-300});
  return d;
}

LevelBound level_bound(const std::vector<double>& differences) {
  LevelBound b;
  double sum = 0.0;
  for (double d : differences) {
    sum += d * d;
    b.worst = std::max(b.worst, d);
  }
  b.rms = std::sqrt(sum / double(std::max<size_t>(differences.size(), 1)));
  b.bound = std::max({kChainBoundSafety * b.rms, b.worst, kChainBoundFloor});
  return b;
}

double chain_recorded_bound(const ChainBound& chain, double max_error, double measured_error) {
  return max_error > 0 && measured_error > chain.bound ? measured_error : chain.bound;
}

std::vector<std::vector<double>> host_bound_reference(const CubeLevels& cube, EnvDistribution distribution,
                                                      const std::vector<BoundLevelSample>& samples) {
  std::vector<std::vector<double>> out;
  if (samples.empty()) return out;
  const reference::EnvCube source = to_reference_cube(cube.levels[0], cube.size);
  const reference::EnvLobe lobe =
      distribution == EnvDistribution::Charlie ? reference::EnvLobe::Charlie : reference::EnvLobe::Ggx;
  for (const BoundLevelSample& s : samples)
    out.push_back(reference::prefilter_directions(source, lobe, s.roughness, s.directions, s.subdivision));
  return out;
}

ChainBound chain_error_bound(const CubeLevels& cube, EnvDistribution distribution, const std::vector<double>& roughness,
                             const BoundReference& reference_values) {
  const auto t0 = std::chrono::steady_clock::now();
  const int levels = cube.level_count();
  ChainBound b;
  b.per_level.assign(size_t(levels), kChainBoundFloor);
  b.max_difference.assign(size_t(levels), 0.0);
  b.samples.assign(size_t(levels), 0);
  if (levels > 1) {
    const reference::EnvLobe lobe =
        distribution == EnvDistribution::Charlie ? reference::EnvLobe::Charlie : reference::EnvLobe::Ggx;
    const double cells = 6.0 * double(cube.size) * double(cube.size);
    std::vector<BoundLevelSample> samples;
    std::vector<std::vector<Texel>> texels;
    for (int l = 1; l < levels; ++l) {
      const double r = roughness.at(size_t(l));
      const int q = reference::env_default_subdivision(lobe, r * r, cube.size);
      const double per_direction = cells * q * q;
      const int count = static_cast<int>(std::clamp(kChainBoundWork / (levels - 1) / per_direction,
                                                    double(kChainBoundMinSamples), double(kChainBoundMaxSamples)));
      texels.push_back(sample_texels(cube, l, count));
      BoundLevelSample s;
      s.level = l;
      s.roughness = r;
      s.subdivision = q;
      for (const Texel& t : texels.back())
        s.directions.push_back(math::cube_texel_direction(t.face, cube.level_size(l), t.i, t.j));
      samples.push_back(std::move(s));
    }
    // every level's reference values at once: a device sums the levels that share a subdivision
    // in one pass over level 0
    const std::vector<std::vector<double>> ref = reference_values ? reference_values(cube, distribution, samples)
                                                                  : host_bound_reference(cube, distribution, samples);
    if (ref.size() != samples.size())
      throw std::logic_error("chain_error_bound: the reference answered " + std::to_string(ref.size()) + " levels of " +
                             std::to_string(samples.size()));
    for (size_t s = 0; s < samples.size(); ++s) {
      const int l = samples[s].level;
      const std::vector<Texel>& ts = texels[s];
      std::vector<double> y_ref(ts.size());
      for (size_t k = 0; k < ts.size(); ++k)  // in double, with luminance()'s weights (Rec. 709)
        y_ref[k] = 0.2126 * ref[s][3 * k] + 0.7152 * ref[s][3 * k + 1] + 0.0722 * ref[s][3 * k + 2];
      std::vector<double> y_stored(ts.size());
      for (size_t k = 0; k < ts.size(); ++k) y_stored[k] = luminance(cube.texel(l, ts[k].face, ts[k].i, ts[k].j));
      const LevelBound lb = level_bound(relative_differences(y_stored, y_ref));
      b.per_level[size_t(l)] = lb.bound;
      b.max_difference[size_t(l)] = lb.worst;
      b.samples[size_t(l)] = static_cast<int>(ts.size());
    }
  }
  b.bound = *std::max_element(b.per_level.begin(), b.per_level.end());
  b.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return b;
}

}  // namespace brdfbake::detail
