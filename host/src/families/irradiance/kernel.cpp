// Diffuse irradiance on any backend: the public entry runs the backend's implementation of the
// family's kernel (kernel.hpp).
#include "families/irradiance/kernel.hpp"

#include "families/kernels.hpp"

namespace brdfbake {

IrradianceResult compute_irradiance(Backend& backend, const EnvImage& env, const IrradianceSpec& spec,
                                    const EnvProgress& progress) {
  return detail::run_kernel<detail::IrradianceKernel>(
      backend, [&](detail::IrradianceKernel& k) { return k.bake(env, spec, progress); });
}

}  // namespace brdfbake
