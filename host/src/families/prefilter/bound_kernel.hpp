// Internal: the chain's error bound as a backend kernel (bound.cpp says what it measures). Its
// implementations: bound_device.cpp (the reference's values summed on an OpenCL device in fp64,
// kernels/prefilter_bound.cl; the host's scalar reference where the device has no fp64 or cannot
// allocate level 0 in one buffer) and the
// reference backend's (the scalar reference); the descriptor (family.cpp) registers both.
#pragma once

#include <memory>
#include <vector>

#include "brdfbake/backend.hpp"
#include "brdfbake/environment.hpp"
#include "families/prefilter/model.hpp"

namespace brdfbake::detail {

class ChainBoundKernel : public BackendKernel {
 public:
  static constexpr const char* kName = "prefilter_bound";
  // chain_error_bound of `cube` with this backend's reference values.
  virtual ChainBound measure(const CubeLevels& cube, EnvDistribution distribution,
                             const std::vector<double>& roughness) = 0;
};

std::unique_ptr<ChainBoundKernel> make_opencl_chain_bound(Device& device);
std::unique_ptr<ChainBoundKernel> make_reference_chain_bound();

// The reference's values of `samples` summed on `device` in fp64 (kernels/prefilter_bound.cl): the
// levels that share a subdivision in one launch, level 0 read in place as float. Samples at
// roughness 0 (the mirror), and subdivisions whose table of solid-angle corners would outgrow a
// float level 0 (a small source's fine sub-cells), are left to host_bound_reference. Throws Error
// on a device without fp64. device_seconds: the kernels' device time, added.
std::vector<std::vector<double>> device_bound_reference(Device& device, const CubeLevels& cube,
                                                        EnvDistribution distribution,
                                                        const std::vector<BoundLevelSample>& samples,
                                                        double* device_seconds = nullptr);

// The chain's bound on `backend` (run_kernel of ChainBoundKernel).
ChainBound chain_error_bound(Backend& backend, const CubeLevels& cube, EnvDistribution distribution,
                             const std::vector<double>& roughness);

}  // namespace brdfbake::detail
