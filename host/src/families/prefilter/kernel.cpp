// The prefiltered chain on any backend: the public entry runs the backend's implementation of the
// family's kernel (kernel.hpp).
#include "families/prefilter/kernel.hpp"

#include "families/kernels.hpp"

namespace brdfbake {

CubeLevels prefilter_environment(Backend& backend, const EnvImage& env, const PrefilterSpec& spec,
                                 PrefilterTiming* timing, const EnvProgress& progress,
                                 const std::function<void()>& source_done) {
  return detail::run_kernel<detail::PrefilterKernel>(
      backend, [&](detail::PrefilterKernel& k) { return k.bake(env, spec, timing, progress, source_done); });
}

}  // namespace brdfbake
