// The DFG tables on any backend: the public entry runs the backend's implementation of the family's
// kernel (kernel.hpp).
#include "families/dfg_lut/kernel.hpp"

#include "families/kernels.hpp"

namespace brdfbake {

Table bake_lut(Backend& backend, const LutSpec& spec, LutTiming* timing, const Progress& progress) {
  return detail::run_kernel<detail::DfgLutKernel>(
      backend, [&](detail::DfgLutKernel& k) { return k.bake(spec, timing, progress); });
}

}  // namespace brdfbake
