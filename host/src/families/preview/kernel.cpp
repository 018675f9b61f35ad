// The preview family's kernel on any backend (kernel.hpp).
#include "families/preview/kernel.hpp"

#include "families/kernels.hpp"

namespace brdfbake::detail {

ReferenceSums run_preview_reference(Backend& backend, const ReferenceTask& task,
                                    const std::function<void(double)>& progress) {
  return run_kernel<PreviewKernel>(backend, [&](PreviewKernel& k) { return k.reference(task, progress); });
}

PreviewRulesValues preview_rules(double refinement, double radiance_scale) {
  // At refinement 4: straddling cells down to 0.1 rad (the prefilter's horizon_texel), a bright cell
  // until its luminance x rho is below 2.5e-4 of a typical irradiance, and no cell above 0.125 rad
  // (the moment rule's curvature error on the broad lobes of rough metals: 0.3% RMS against the brute
  // force with 0.2 rad cells, 0.13% with 0.125; tests/device/test_preview.cpp).
  const double r = refinement;
  return {0.4 / r, 0.016 * radiance_scale / (r * r * r), 0.5 / r};
}

}  // namespace brdfbake::detail
