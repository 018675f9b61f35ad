// Internal: the Fresnel tables' kernel, the one calculation of the family that a backend runs. Its
// implementations: opencl.cpp (an OpenCL device) and reference.cpp (the scalar double reference);
// the descriptor (family.cpp) registers both, and bake_fresnel(Backend&, ...) runs the backend's.
#pragma once

#include <memory>

#include "brdfbake/backend.hpp"
#include "brdfbake/fresnel.hpp"

namespace brdfbake::detail {

class FresnelKernel : public BackendKernel {
 public:
  static constexpr const char* kName = "fresnel";
  virtual Table bake(const FresnelSpec& spec, FresnelTiming* timing) = 0;
};

std::unique_ptr<FresnelKernel> make_opencl_fresnel(Device& device);
std::unique_ptr<FresnelKernel> make_reference_fresnel();

}  // namespace brdfbake::detail
