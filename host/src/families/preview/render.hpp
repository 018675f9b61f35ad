// Internal: the steps of render_preview that the writers and tests share.
#pragma once

#include <vector>

#include "brdfbake/preview.hpp"

namespace brdfbake::detail::preview {

// The environment as the equirect the reference integrates (a cube input resampled to 4S x 2S,
// nearest texel), and its solid-angle-weighted median luminance.
EnvImage reference_equirect(const EnvImage& env);
double median_luminance(const EnvImage& equirect);

// The statistics of one sphere from per-pixel relative errors (rms, 99th percentile, max).
PreviewErrorStats error_stats(std::vector<double> errors);

}  // namespace brdfbake::detail::preview
