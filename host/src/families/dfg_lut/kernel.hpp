// Internal: the DFG tables' kernel, the one calculation of the family that a backend runs. Its
// implementations: opencl.cpp (an OpenCL device) and reference.cpp (the scalar double reference);
// the descriptor (family.cpp) registers both, and bake_lut(Backend&, ...) runs the backend's.
#pragma once

#include <memory>

#include "brdfbake/backend.hpp"
#include "brdfbake/dfg_lut.hpp"

namespace brdfbake::detail {

class DfgLutKernel : public BackendKernel {
 public:
  static constexpr const char* kName = "dfg_lut";
  virtual Table bake(const LutSpec& spec, LutTiming* timing, const Progress& progress) = 0;
};

std::unique_ptr<DfgLutKernel> make_opencl_dfg_lut(Device& device);
std::unique_ptr<DfgLutKernel> make_reference_dfg_lut();

}  // namespace brdfbake::detail
