// Internal: the steps of render_preview that the writers and tests share.
#pragma once

#include <vector>

#include "brdfbake/plan.hpp"
#include "brdfbake/preview.hpp"
#include "families/preview/model.hpp"

namespace brdfbake::detail::preview {

// What render_preview bakes first when it is given no bake folder: what the target's engine loads,
// as `brdfbake bake --target T` plans it from `env`'s source (the default plan: the standard set for
// metallic-roughness materials), with `o`'s other settings (the defaults unless a test asks for
// smaller chains). With sheened spheres, planned as `bake --scene` plans a scene of one dielectric
// material with KHR_materials_sheen: the standard set, the Charlie chain and the charlie DFG table.
Plan first_bake_plan(const EnvImage& env, EngineTarget target, bool sheen, PlanOptions o = {});

// The environment as the equirect the reference integrates (a cube input resampled to 4S x 2S,
// nearest texel), and its solid-angle-weighted median luminance.
EnvImage reference_equirect(const EnvImage& env);
double median_luminance(const EnvImage& equirect);

// The statistics of one sphere from per-pixel relative errors (rms, 99th percentile, max).
PreviewErrorStats error_stats(std::vector<double> errors);

// The reference's own bound over one sphere (PreviewSphereStats::reference_rms_bound and
// reference_max_bound) from its bound pixels' relative differences |reference - reference at twice
// the refinement| / |the finer one| (RGB norms): kPreviewBoundFactor x their RMS, and x their max,
// each plus kPreviewBoundFloor (brdfbake/preview.hpp says why).
struct ReferenceBound {
  double rms = 0.0, max = 0.0;
};
ReferenceBound reference_bound(const std::vector<double>& differences);

// Per sphere of `layout` (its `pixels`, sphere_pixels(layout)): the error of a split-sum image
// against a reference image of the same layout, as render_preview states it: per pixel
// |s - r| / |r| (Euclidean norms of the linear RGB triples, in double from the float images) and
// the largest difference of the three 8-bit sRGB channels after `exposure` (EV) and the tone map;
// per sphere their error_stats and its pixel count (`pixels`, `linear`, `srgb8`; the reference's
// bound is left at 0). render_preview and the bake sweep (report/bake_sweep.cpp) both use it.
std::vector<PreviewSphereStats> sphere_errors(const Layout& layout, const std::vector<SpherePixel>& pixels,
                                              const PreviewImage& splitsum, const PreviewImage& reference,
                                              double exposure);

// The groups of a result's spheres and their shares (PreviewResult::share_groups): the default
// grid's rows by their material ("gold r0.5" is in "gold"), any other material a group of its own;
// per group the median and the worst sphere's relative RMS of the error and of each share.
std::vector<PreviewShareGroup> share_groups(const PreviewResult& r);

}  // namespace brdfbake::detail::preview
