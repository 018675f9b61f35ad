// Internal: the steps of render_preview that the writers and tests share.
#pragma once

#include <vector>

#include "brdfbake/plan.hpp"
#include "brdfbake/preview.hpp"
#include "families/preview/model.hpp"
#include "families/preview/splitsum.hpp"

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
// The shares per sphere of `res` (PreviewSphereStats::engine_share, bake_share: |ideal - reference|
// and |split-sum - ideal| over |reference|, per pixel, from res.splitsum, res.ideal, res.reference)
// into res.stats (filled by sphere_errors first) and res.share_groups.
void add_shares(const Layout& layout, const std::vector<SpherePixel>& pixels, PreviewResult& res);
// The split-sum render of `split`'s files into `out` as render_preview draws it (the background and
// every sphere pixel of `layout`), for the spheres of `res` (its spec's background).
void render_split_sum(const Layout& layout, const std::vector<SpherePixel>& pixels, const SplitSum& split,
                      const Vec3& v, const PreviewResult& res, PreviewImage& out);

// The sharp-reflection probe (docs/REPORT.md, "Sharp reflections"): the bake's share where a sphere of
// the default grid's 20 pixels cannot show it. Each sphere of roughness below kProbeMaxRoughness is
// drawn again at a radius of 2 x the files' level-0 face size in pixels, so that one texel of level
// 0 spans at least 2 pixels at the sphere's centre (the reflection turns twice as fast as the normal,
// and a texel at a face's centre spans 2 / size radians); kProbeSamples of its pixels, drawn with a
// fixed low-discrepancy sequence, are shaded from the files and from their ideal bake, and the
// sphere's probe error is the RMS over them of min(|files - ideal| / |ideal|, kProbeMaxPixelError)
// (the linear RGB norms, as the shares). Point samples: the RMS over the drawn pixels estimates the RMS over all the
// sphere's pixels (to about 1 / sqrt(2 kProbeSamples) of itself). Per sphere of `layout`; -1 where not probed. A
// pixel's error counts up to kProbeMaxPixelError (as large as the pixel itself): a sun blurred into the sky beside it
// is ~100x off there, and a handful of such pixels would decide the RMS alone (and its estimate from the drawn pixels:
// 30 % off on venice's sun at 16384 draws of 51,000 pixels).
inline constexpr double kProbeMaxPixelError = 1.0;
inline constexpr double kProbeMaxRoughness = 0.1;
inline constexpr int kProbeSamples = 16384;
std::vector<double> sharp_probe(const Layout& layout, const SplitSum& files, const SplitSum& ideal,
                                int samples = kProbeSamples);

}  // namespace brdfbake::detail::preview
