// Internal: the prefiltered chain's kernel, the one calculation of the family that a backend runs.
// Its implementations: opencl.cpp (an OpenCL device) and reference.cpp (the scalar double
// reference); the descriptor (family.cpp) registers both, and prefilter_environment(Backend&, ...)
// runs the backend's.
#pragma once

#include <functional>
#include <memory>

#include "brdfbake/backend.hpp"
#include "brdfbake/environment.hpp"

namespace brdfbake::detail {

class PrefilterKernel : public BackendKernel {
 public:
  static constexpr const char* kName = "prefilter";
  // source_done: as prefilter_environment's (the reference never calls it).
  virtual CubeLevels bake(const EnvImage& env, const PrefilterSpec& spec, PrefilterTiming* timing,
                          const EnvProgress& progress, const std::function<void()>& source_done) = 0;
};

std::unique_ptr<PrefilterKernel> make_opencl_prefilter(Device& device);
std::unique_ptr<PrefilterKernel> make_reference_prefilter();

}  // namespace brdfbake::detail
