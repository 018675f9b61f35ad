// Internal: the thin-film table's kernel, the one calculation of the family that a backend runs. Its
// implementations: opencl.cpp (an OpenCL device) and reference.cpp (the scalar double reference);
// the descriptor (family.cpp) registers both, and bake_thin_film(Backend&, ...) runs the backend's.
#pragma once

#include <memory>

#include "brdfbake/backend.hpp"
#include "brdfbake/thin_film.hpp"

namespace brdfbake::detail {

class ThinFilmKernel : public BackendKernel {
 public:
  static constexpr const char* kName = "thin_film";
  virtual Table bake(const ThinFilmSpec& spec, ThinFilmTiming* timing) = 0;
};

std::unique_ptr<ThinFilmKernel> make_opencl_thin_film(Device& device);
std::unique_ptr<ThinFilmKernel> make_reference_thin_film();

}  // namespace brdfbake::detail
