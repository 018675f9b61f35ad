// Internal: the BRDF evaluation engine's kernel, what the eval and tabulate families run on a
// backend: an evaluator of direction pairs, and the MERL and table layouts. Its implementations:
// opencl.cpp (an OpenCL device) and reference.cpp (the scalar double reference); the eval
// descriptor (eval_family.cpp) registers both, and make_evaluator, tabulate_merl and tabulate
// (Backend&, ...) run the backend's.
#pragma once

#include <memory>
#include <vector>

#include "brdfbake/backend.hpp"
#include "brdfbake/brdf.hpp"

namespace brdfbake::detail {

class BrdfEvalKernel : public BackendKernel {
 public:
  static constexpr const char* kName = "brdf_eval";
  virtual std::unique_ptr<PairEvaluator> evaluator(BrdfModel model, const std::vector<Material>& materials,
                                                   const EvalOptions& options) = 0;
  virtual MerlTable tabulate_merl(const TabulateSpec& spec, TabulateTiming* timing) = 0;
  virtual Table tabulate(const TabulateSpec& spec, TabulateTiming* timing) = 0;
};

std::unique_ptr<BrdfEvalKernel> make_opencl_brdf_eval(Device& device);
std::unique_ptr<BrdfEvalKernel> make_reference_brdf_eval();

}  // namespace brdfbake::detail
