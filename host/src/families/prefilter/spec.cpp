// The prefilter family's specs: the limits of a spec and the levels a chain has.
#include <algorithm>
#include <cmath>
#include <string>

#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"

namespace brdfbake {

PrefilterSpec resolve_prefilter_spec(const PrefilterSpec& in) {
  PrefilterSpec s = in;
  if (s.size < 1 || s.size > kPrefilterMaxSize)
    throw Error("size must be in 1.." + std::to_string(kPrefilterMaxSize) + " (got " + std::to_string(s.size) + ")");
  if (s.min_size < 1 || s.min_size > s.size)
    throw Error("min-size must be in 1..size (got " + std::to_string(s.min_size) + " for size " +
                std::to_string(s.size) + ")");
  if (s.samples < 0 || s.samples > kPrefilterMaxSamples)
    throw Error("samples must be in 1.." + std::to_string(kPrefilterMaxSamples) + " (got " + std::to_string(s.samples) +
                ")");
  if (!std::isfinite(s.max_error) || s.max_error < 0.0) throw Error("chain-max-error must be a positive number");
  if (s.max_error > 0.0 && s.samples > 0) throw Error("give either samples or chain-max-error, not both");
  if (!std::isfinite(s.lod_bias)) throw Error("lod bias must be finite");
  if (!std::isfinite(s.clamp_luminance) || s.clamp_luminance < 0.0) throw Error("clamp must be a positive number");
  if (s.bright_texels < -1) throw Error("bright texel count must be >= 0 (or -1: automatic)");
  if (!(s.refinement >= 1.5 && s.refinement <= 64.0)) throw Error("refinement must be in 1.5..64");
  if (!(s.core_refinement >= 1.0 && s.core_refinement <= 256.0)) throw Error("core refinement must be in 1..256");
  if (!(s.horizon_texel > 0.0)) throw Error("horizon texel size must be positive");
  if (s.estimator == EnvEstimator::Quadrature && s.samples > 0)
    throw Error("samples apply to the sampling estimator; the quadrature takes a refinement (or chain-max-error)");
  return s;
}

int prefilter_level_count(const PrefilterSpec& spec) {
  int levels = 0;
  for (int l = 0;; ++l) {
    const int s = std::max(1, spec.size >> l);
    if (s < spec.min_size || (l > 0 && (spec.size >> l) == 0)) break;
    ++levels;
    if (s == 1) break;
  }
  return std::max(levels, 1);
}

}  // namespace brdfbake
