// The thin-film table on any backend: the public entry runs the backend's implementation of the
// family's kernel (kernel.hpp).
#include "families/thin_film/kernel.hpp"

#include "families/kernels.hpp"

namespace brdfbake {

Table bake_thin_film(Backend& backend, const ThinFilmSpec& spec, ThinFilmTiming* timing) {
  return detail::run_kernel<detail::ThinFilmKernel>(backend,
                                                    [&](detail::ThinFilmKernel& k) { return k.bake(spec, timing); });
}

}  // namespace brdfbake
