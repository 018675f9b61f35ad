// The Fresnel tables on any backend: the public entry runs the backend's implementation of the
// family's kernel (kernel.hpp).
#include "families/fresnel/kernel.hpp"

#include "families/kernels.hpp"

namespace brdfbake {

Table bake_fresnel(Backend& backend, const FresnelSpec& spec, FresnelTiming* timing) {
  return detail::run_kernel<detail::FresnelKernel>(backend,
                                                   [&](detail::FresnelKernel& k) { return k.bake(spec, timing); });
}

}  // namespace brdfbake
