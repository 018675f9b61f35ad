// Internal: the prefilter family's engine, what its files share. The chain (chain.cpp) turns a
// source cube into the prefiltered levels: the bright texels leave the source (env/bright_texels.cpp,
// bright.cpp), the rest is read through the quadrature's pyramid (pyramid.cpp) or the sampling
// estimator's lobe samples (samples.cpp) and padded mip chain (env/device.cpp), each level launched
// by launch.hpp's kernels and recorded by metadata.cpp; its error bound is measured by bound.cpp.
// The roughness schedules and names are schedule.cpp's, the spec's limits spec.cpp's.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/math/types.hpp"
#include "enum_names.hpp"
#include "runtime/program.hpp"

namespace brdfbake::detail {

// BRDFBAKE_STRIP_ROWS (kernels/prefilter.cl): the strips kernel's blocks of 8 x 8 texels.
inline constexpr int kStripRows = 4;
// max_error with the sampling estimator: the sample counts a level's search starts at and stops at.
inline constexpr int kPrefilterSearchStart = 32;
inline constexpr int kPrefilterSearchMax = 8192;

// ---- Names (schedule.cpp's *_from_name and *_name read these; the schema offers them) ----------

inline constexpr EnumName<EnvDistribution> kEnvDistributionNames[] = {{EnvDistribution::Ggx, "ggx"},
                                                                      {EnvDistribution::Charlie, "charlie"}};
inline constexpr EnumName<RoughnessSchedule> kRoughnessScheduleNames[] = {{RoughnessSchedule::Linear, "linear"},
                                                                          {RoughnessSchedule::Filament, "filament"},
                                                                          {RoughnessSchedule::Sqrt, "sqrt"},
                                                                          {RoughnessSchedule::Babylon, "babylon"}};
inline constexpr EnumName<EnvEstimator> kEnvEstimatorNames[] = {{EnvEstimator::Quadrature, "quadrature"},
                                                                {EnvEstimator::Sampling, "sampling"}};

// ---- The chain (chain.cpp) and its record (metadata.cpp) ----------------------------------------

// The filter's program (kernels/prefilter.cl) for a spec's lobe and precision.
cl::Program filter_program(Device::Impl& dev, const PrefilterSpec& spec);
// The chain from a source cube it owns (level 0 moves into the output: no copy).
CubeLevels prefilter_chain(Device& device, CubeLevels source, const PrefilterSpec& spec, PrefilterTiming* timing,
                           const EnvProgress& progress);
// The same with level l filtered at roughness[l] (one a level of the spec's chain; level 0 is the
// source whatever roughness[0] says) instead of the spec's schedule: the preview's ideal bake
// (families/preview/ideal.cpp) filters each level of a target's chain on its own, at a face size of
// its choosing, at the roughness the target's schedule gives that level.
CubeLevels prefilter_chain_at(Device& device, CubeLevels source, const PrefilterSpec& spec,
                              const std::vector<double>& roughness, PrefilterTiming* timing = nullptr);

// What a chain measured and chose per level, for its metadata and timing.
struct ChainRecord {
  std::vector<double> roughness;                       // of each level
  std::vector<double> seconds;                         // device seconds of each level
  std::vector<double> refinement;                      // quadrature: the refinement kept
  std::vector<int> samples;                            // sampling: the samples kept
  std::vector<double> measured;                        // max_error: the last difference of each level's search
  size_t bright = 0;                                   // bright texels summed exactly
  std::vector<std::pair<std::string, double>> stages;  // wall seconds of each step
};

// The metadata of a prefiltered chain common to every estimator: conventions, what a level holds,
// sizes, the roughness schedule and the roughness of each level (roughness.size() levels).
void prefilter_metadata(CubeLevels& out, const PrefilterSpec& spec, const std::vector<double>& roughness);
// The metadata of the chain's estimator and, with max_error, its measured error; throws Error when
// a level did not reach max_error (no file may claim a bound it does not meet).
void chain_metadata(CubeLevels& out, const PrefilterSpec& spec, const ChainRecord& record);

// ---- The sampling estimator (samples.cpp) ---------------------------------------------------------

// The lobe samples of one level in the frame (t, b, R), as the arrays x, y, z, weight, lod_k
// (kernels/prefilter.cl); *kept: the samples above the horizon before padding.
std::vector<double> lobe_samples(EnvDistribution dist, double alpha, int n, int source_size, bool fis, double lod_bias,
                                 int* kept);
// The sampling estimator's default lobe samples per texel.
int default_prefilter_samples(int level, int levels);

// ---- Bright texels in the filter (bright.cpp) -----------------------------------------------------

// Sub-cells per texel side of the bright texels' footprints: the lobe's part alone (away from a
// texel's horizon), and the full subdivision (near it) for `bright` texels.
int bright_lobe_subdivision(EnvDistribution dist, double alpha, int source_size);
int bright_subdivision(EnvDistribution dist, double alpha, int source_size, size_t bright);
// Whether one point a bright texel resolves the lobe.
bool bright_single_point(EnvDistribution dist, double alpha, int source_size);
// Groups of `per` points (one bright texel's, with SoA stride `stride`) merged into one each.
std::vector<double> merge_bright_points(const std::vector<double>& pts, size_t stride, size_t per, size_t texels);

// ---- The quadrature's pyramid (pyramid.cpp; kernels/common/env_sampling.clh) ----------------------

struct Pyramid {
  std::vector<float> data;   // every level's ten arrays (gx gy gz mx my mz omega r g b)
  std::vector<cl_int> info;  // offset (floats) and face size per level
  std::vector<int> sizes;
  int levels = 0;
};
// The pyramid of an RGBA cube of face s0 from level `base` of the full pyramid up; texels marked in
// `skip` (the bright ones) add their solid angle but no radiance.
Pyramid build_pyramid(const std::vector<float>& rgba, int s0, int base, const std::vector<uint8_t>& skip);
// The refinement thresholds of one output level: cos_core per pyramid level and band (lo, hi) pairs.
void pyramid_thresholds(const Pyramid& p, EnvDistribution dist, double alpha, const PrefilterSpec& s, double refinement,
                        std::vector<double>& cos_core, std::vector<double>& band);
// The finest level of the full pyramid that the quadrature visits for any of the lobes `alphas`.
int pyramid_base_level(int s0, EnvDistribution dist, const std::vector<double>& alphas, const PrefilterSpec& s);

// ---- The error bound every chain records (bound.cpp) ----------------------------------------------

// Reference terms (source sub-cells x directions) the comparison may spend over a chain (a quarter
// of a second on two quiet cores; a 1024^2 source's 3 texels a level take more), the sample texels
// a level (the brightest's 3 x 3 neighbourhood from kChainBoundNeighbourhood on), the factor on
// the sample's RMS and the floor (fp32 rounding) of every level's bound.
inline constexpr double kChainBoundWork = 2.5e7;
inline constexpr int kChainBoundMinSamples = 3;
inline constexpr int kChainBoundMaxSamples = 64;
inline constexpr int kChainBoundNeighbourhood = 16;
inline constexpr double kChainBoundSafety = 2.0;
inline constexpr double kChainBoundFloor = 1e-6;
// A texel darker than this fraction of the level's brightest sample is compared relative to that
// fraction of the brightest: a black texel's absolute difference is not divided by 0.
inline constexpr double kChainBoundDarkFraction = 1e-6;

inline constexpr const char* kChainBoundDefinition =
    "bound on the RMS relative luminance distance of a level's stored values from the converged ones (the double "
    "reference: the lobe's integral over the bilinear interpolation of level 0): the larger of 2 x the RMS and "
    "the largest of |Y - Y_ref| / Y_ref over a deterministic sample of its texels (bound_samples_per_level: the "
    "brightest texel, its 3 x 3 "
    "neighbourhood where 16 or more are compared, R2 points over the faces), at least 1e-6 (fp32 rounding)";

struct ChainBound {
  std::vector<double> per_level;       // the bound of each level (level 0: the floor)
  std::vector<double> max_difference;  // the largest relative difference on the sample
  std::vector<int> samples;            // texels compared per level
  double bound = 0.0;                  // the largest of per_level
  double seconds = 0.0;                // wall seconds of the comparison
  bool on_device = false;              // the reference's values from an fp64 device (bound_device.cpp)
  double device_seconds = 0.0;         // its kernels' device time
};
// One level's sample: d_k = |y_stored[k] - y_ref[k]| / max(y_ref[k], kChainBoundDarkFraction max y_ref),
// the relative luminance differences of its texels (throws std::invalid_argument on sizes that differ).
std::vector<double> relative_differences(const std::vector<double>& y_stored, const std::vector<double>& y_ref);
// One level's bound from its sample's differences: max(kChainBoundSafety x RMS, the largest, kChainBoundFloor).
struct LevelBound {
  double bound = 0.0;  // what the level records
  double rms = 0.0;    // RMS of the differences (0 for an empty sample)
  double worst = 0.0;  // the largest difference
};
LevelBound level_bound(const std::vector<double>& differences);
// The bound a chain's file records: the chain's (the largest level's), or with max_error > 0 the
// search's last measured difference where that is larger (family.cpp says so in the definition).
double chain_recorded_bound(const ChainBound& chain, double max_error, double measured_error);
// One level's sample for the reference: the directions of its sample texels, the level's roughness
// and the sub-cells per source texel side the reference sums (env_default_subdivision).
struct BoundLevelSample {
  int level = 0;
  double roughness = 0.0;
  int subdivision = 1;
  std::vector<Vec3> directions;
};
// The double reference's prefiltered radiance of level 0 of `cube` at every sample's directions
// (reference::prefilter_directions' definition: 3 doubles a direction, one vector a sample).
using BoundReference = std::function<std::vector<std::vector<double>>(
    const CubeLevels& cube, EnvDistribution distribution, const std::vector<BoundLevelSample>& samples)>;
// The scalar reference itself, on the host's cores (level 0 copied into double).
std::vector<std::vector<double>> host_bound_reference(const CubeLevels& cube, EnvDistribution distribution,
                                                      const std::vector<BoundLevelSample>& samples);
// Every level of `cube` (level 0 its source) compared with the double reference on a sample of its
// texels (bound.cpp says how); roughness: of each level. `reference` computes the reference's
// values (empty: host_bound_reference; an fp64 device: bound_device.cpp's, the same definition).
ChainBound chain_error_bound(const CubeLevels& cube, EnvDistribution distribution, const std::vector<double>& roughness,
                             const BoundReference& reference = {});

// ---- The reference (reference.cpp) -----------------------------------------------------------------

// The reference's prefiltered radiance (RGB per direction) of a source cube (level 0 of `source`,
// RGBA) at unit directions, one lobe of `roughness`: for measurements at probe directions
// (brdfbake report).
std::vector<double> prefilter_reference_directions(const CubeLevels& source, EnvDistribution distribution,
                                                   double roughness, const std::vector<Vec3>& directions);

}  // namespace brdfbake::detail
