// Internal: the thin-film family's model (model.cpp), what its descriptor and its two kernels
// (opencl.cpp, reference.cpp) share.
#pragma once

#include "brdfbake/math/types.hpp"
#include "brdfbake/table.hpp"
#include "brdfbake/thin_film.hpp"

namespace brdfbake::detail {

// The film as both evaluate it: indices and the base's F0 seen from air (a dielectric base_ior n
// becomes ((n - 1) / (n + 1))^2).
struct ThinFilmParams {
  double outside_ior = 1.0;
  double film_ior = 1.3;
  Rgb base_f0{0.04, 0.04, 0.04};
};
ThinFilmParams thin_film_params(const ThinFilmSpec& spec);
// The table of a resolved spec: axes and metadata, data zero.
Table make_thin_film_table(const ThinFilmSpec& spec);

}  // namespace brdfbake::detail
