// Internal: the irradiance family's kernel, the one calculation of the family that a backend runs.
// Its implementations: opencl.cpp (the SH on the host and the cube on an OpenCL device) and
// reference.cpp (the scalar double reference); the descriptor (family.cpp) registers both, and
// compute_irradiance(Backend&, ...) runs the backend's.
#pragma once

#include <memory>

#include "brdfbake/backend.hpp"
#include "brdfbake/environment.hpp"

namespace brdfbake::detail {

class IrradianceKernel : public BackendKernel {
 public:
  static constexpr const char* kName = "irradiance";
  virtual IrradianceResult bake(const EnvImage& env, const IrradianceSpec& spec, const EnvProgress& progress) = 0;
};

// The OpenCL kernel takes the backend, whose device it opens only for a cube.
std::unique_ptr<IrradianceKernel> make_opencl_irradiance(Backend& backend);
std::unique_ptr<IrradianceKernel> make_reference_irradiance();

}  // namespace brdfbake::detail
