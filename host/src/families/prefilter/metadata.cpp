// What a prefiltered chain records: its conventions, schedule and levels (prefilter_metadata), and
// how its estimator made them, with the measured error of a max_error search (chain_metadata).
#include <cstdio>
#include <string>
#include <vector>

#include "brdfbake/error.hpp"
#include "env/cube.hpp"
#include "families/prefilter/model.hpp"

namespace brdfbake {

namespace {

using detail::comma_join;
using detail::kPrefilterSearchMax;

std::string fmt(double v, const char* f = "%.6g") {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

// A max_error search's record: what was measured per level. A level that reached the largest
// refinement (or sample count) without meeting the target makes the chain fail: no file may claim a
// bound it does not meet.
void max_error_metadata(CubeLevels& out, const PrefilterSpec& s, const detail::ChainRecord& r) {
  const int levels = static_cast<int>(r.roughness.size());
  const bool quadrature = s.estimator == EnvEstimator::Quadrature;
  // A level that reached the largest refinement (or sample count) without meeting the target makes
  // the chain fail: no file may claim a bound it does not meet.
  double worst = 0.0;
  int worst_level = 0;
  std::vector<std::string> m_text;
  for (int l = 0; l < levels; ++l) {
    // level 0 is the source itself: nothing was refined, nothing measured
    m_text.push_back(l == 0 ? std::string("source") : fmt(r.measured[size_t(l)], "%.3g"));
    if (r.measured[size_t(l)] > worst) {
      worst = r.measured[size_t(l)];
      worst_level = l;
    }
  }
  if (worst > s.max_error)
    throw Error("chain-max-error " + fmt(s.max_error) + " is not reached: level " + std::to_string(worst_level) +
                " still differs by " + fmt(worst, "%.3g") + " (RMS) between its two finest " +
                (quadrature ? "refinements (the largest is 16)"
                            : "sample counts (the largest is " + std::to_string(kPrefilterSearchMax) + ")") +
                "; ask for chain-max-error " + fmt(worst * 1.5, "%.2g") + " or more");
  out.set_meta("max_error", "measured per level: RMS relative luminance difference between successive " +
                                std::string(quadrature ? "refinements" : "sample counts (N, 4N)") +
                                " <= " + fmt(s.max_error) + " (the finer result is kept)");
  // The difference between the two finest refinements (what max_error stops on), not the error
  // against the converged chain: integration_error_bound_per_level is that (issue 35).
  out.set_meta("refinement_difference_per_level", comma_join(m_text));
  out.set_meta("refinement_difference", fmt(worst, "%.3g"));
}

}  // namespace

void detail::prefilter_metadata(CubeLevels& out, const PrefilterSpec& s, const std::vector<double>& roughness) {
  const int levels = static_cast<int>(roughness.size());
  cube_conventions_metadata(out);
  out.set_meta("kind", "prefiltered radiance");
  out.set_meta("distribution", env_distribution_name(s.distribution));
  out.set_meta("definition",
               "level l holds P(R) = int L(l) D(h) (n.l)+ dl / int D(h) (n.l)+ dl with n = v = R (Karis 2013), "
               "D = " +
                   std::string(s.distribution == EnvDistribution::Ggx ? "GGX (Walter et al. 2007)"
                                                                      : "Charlie (Estevez & Kulla 2017)") +
                   ", alpha = roughness^2, L the seamless bilinear interpolation of level 0; level 0 is "
                   "the source itself (roughness 0)");
  out.set_meta("levels", std::to_string(levels));
  out.set_meta("size", std::to_string(s.size));
  out.set_meta("min_size", std::to_string(out.level_size(levels - 1)));
  out.set_meta("roughness_schedule", roughness_schedule_name(s.schedule));
  out.set_meta("roughness_of_level",
               s.schedule == RoughnessSchedule::Linear     ? "roughness = l / (levels - 1)"
               : s.schedule == RoughnessSchedule::Filament ? "roughness = 1 - sqrt(1 - l / (levels - 1))"
               : s.schedule == RoughnessSchedule::Sqrt
                   ? "roughness = (l / (levels - 1))^2"
                   : "roughness = min(1, sqrt(2^(l / 0.8) / size)), 0 at level 0 (Babylon.js HDRFiltering)");
  out.set_meta("lod_from_roughness", schedule_lod_formula(s.schedule) + " (levels = " + std::to_string(levels) + ")");
  std::vector<std::string> r_text;
  for (double r : roughness) r_text.push_back(fmt(r, "%.9g"));
  out.set_meta("roughness_per_level", comma_join(r_text));
}

void detail::chain_metadata(CubeLevels& out, const PrefilterSpec& s, const ChainRecord& r) {
  const int levels = static_cast<int>(r.roughness.size());
  const bool quadrature = s.estimator == EnvEstimator::Quadrature;
  prefilter_metadata(out, s, r.roughness);
  std::vector<std::string> n_text;
  for (int l = 0; l < levels; ++l) {
    n_text.push_back(quadrature ? (l == 0 ? std::string("0") : fmt(r.refinement[size_t(l)], "%g"))
                                : std::to_string(r.samples[size_t(l)]));
  }
  out.set_meta("estimator", env_estimator_name(s.estimator));
  if (quadrature) {
    out.set_meta("refinement_per_level", comma_join(n_text));
    out.set_meta("estimator_description",
                 "deterministic hierarchical quadrature: a solid-angle pyramid of level 0 (per texel: solid angle, "
                 "L Omega, centroid and radiance centroid directions), texels refined within refinement x texel "
                 "size of R (core to texel size <= 2 alpha / " +
                     fmt(s.core_refinement) + ") and across the horizon (to " + fmt(s.horizon_texel) +
                     " rad); K at the radiance centroid, normalised by the sum of K Omega; plus " +
                     std::to_string(r.bright) + " bright texels summed exactly (environment sampling)");
  } else {
    out.set_meta("samples_per_level", comma_join(n_text));
    out.set_meta("estimator_description",
                 std::string("lobe importance sampling, N = V = R, Hammersley points, ") +
                     (s.filtered_importance_sampling
                          ? "filtered importance sampling (Krivanek & Colbert 2008; lod = 0.5 log2(4 / (N D) / texel "
                            "solid angle) + " +
                                fmt(s.lod_bias) + ") "
                          : "no filtered importance sampling ") +
                     "from a solid-angle-weighted mip chain, self-normalised weights (n.l)+; plus " +
                     std::to_string(r.bright) + " bright texels summed exactly (environment sampling)");
  }
  if (s.max_error > 0.0) max_error_metadata(out, s, r);
  if (s.clamp_luminance > 0.0)
    out.set_meta("clamp", "BIASED: source luminance above " + fmt(s.clamp_luminance) +
                              " compressed to limit (1 + log(lum / limit))");
}

}  // namespace brdfbake
