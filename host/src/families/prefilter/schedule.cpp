// The prefilter family's names (distributions, estimators, schedules) and roughness schedules: the
// roughness of each level and the shader's lod of a roughness, as each engine's convention has it.
#include <algorithm>
#include <cmath>
#include <string>

#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "families/prefilter/model.hpp"

namespace brdfbake {

using detail::enum_from_name;
using detail::enum_name;

EnvDistribution env_distribution_from_name(const std::string& n) {
  return enum_from_name(detail::kEnvDistributionNames, n, "distribution");
}
const char* env_distribution_name(EnvDistribution d) { return enum_name(detail::kEnvDistributionNames, d); }

EnvEstimator env_estimator_from_name(const std::string& n) {
  return enum_from_name(detail::kEnvEstimatorNames, n, "estimator");
}
const char* env_estimator_name(EnvEstimator e) { return enum_name(detail::kEnvEstimatorNames, e); }

RoughnessSchedule roughness_schedule_from_name(const std::string& n) {
  return enum_from_name(detail::kRoughnessScheduleNames, n, "schedule");
}
const char* roughness_schedule_name(RoughnessSchedule s) { return enum_name(detail::kRoughnessScheduleNames, s); }

double schedule_roughness(RoughnessSchedule s, int level, int levels) {
  if (levels <= 1) return 0.0;
  const double t = static_cast<double>(level) / (levels - 1);
  switch (s) {
    case RoughnessSchedule::Linear:
      return t;
    case RoughnessSchedule::Filament:
      return 1.0 - std::sqrt(1.0 - t);
    case RoughnessSchedule::Sqrt:
      return t * t;
    case RoughnessSchedule::Babylon: {
      // Babylon.js HDRFiltering: alphaG = 2^((lod - offset) / scale) / width, 0 at lod 0.
      if (level == 0) return 0.0;
      const double alpha = std::pow(2.0, level / kBabylonLodGenerationScale) / std::ldexp(1.0, levels - 1);
      return std::min(1.0, std::sqrt(alpha));
    }
  }
  return t;
}

double schedule_lod(RoughnessSchedule s, double r, int levels) {
  const double m = levels - 1;
  switch (s) {
    case RoughnessSchedule::Linear:
      return m * r;
    case RoughnessSchedule::Filament:
      return m * r * (2.0 - r);
    case RoughnessSchedule::Sqrt:
      return m * std::sqrt(r);
    case RoughnessSchedule::Babylon: {
      // Babylon.js pbrBlockReflection: getLodFromAlphaG(size, alphaG) * lodGenerationScale, with
      // alphaG = roughness^2 + MINIMUMVARIANCE; textureLod clamps to the chain.
      const double lod =
          kBabylonLodGenerationScale * std::log2(std::ldexp(1.0, levels - 1) * (r * r + kBabylonMinimumVariance));
      return std::clamp(lod, 0.0, m);
    }
  }
  return m * r;
}

std::string schedule_lod_formula(RoughnessSchedule s) {
  switch (s) {
    case RoughnessSchedule::Linear:
      return "lod = (levels - 1) * roughness";
    case RoughnessSchedule::Filament:
      return "lod = (levels - 1) * roughness * (2 - roughness)";
    case RoughnessSchedule::Sqrt:
      return "lod = (levels - 1) * sqrt(roughness)";
    case RoughnessSchedule::Babylon:
      return "lod = clamp(0.8 * log2(size * (roughness^2 + 0.0005)), 0, levels - 1), size = 2^(levels - 1)";
  }
  return "";
}

}  // namespace brdfbake
