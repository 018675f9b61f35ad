// The BRDF evaluation engine's OpenCL kernel (kernel.hpp): evaluators over BrdfEvaluator
// (evaluator.cpp) and the tabulations of tabulate.cpp on the backend's device.
#include <memory>
#include <vector>

#include "families/brdf_eval/kernel.hpp"

namespace brdfbake {

namespace {

class OpenClEvaluator final : public PairEvaluator {
 public:
  OpenClEvaluator(Device& device, BrdfModel model, const std::vector<Material>& materials, const EvalOptions& options)
      : evaluator_(device, model, materials, options) {}
  void eval(const double* pairs, std::size_t count, double* out, EvalTiming* timing) override {
    evaluator_.eval(pairs, count, out, timing);
  }
  std::size_t chunk_pairs() const override { return evaluator_.chunk_pairs(); }

 private:
  BrdfEvaluator evaluator_;
};

class OpenClBrdfEval final : public detail::BrdfEvalKernel {
 public:
  explicit OpenClBrdfEval(Device& device) : device_(device) {}
  std::unique_ptr<PairEvaluator> evaluator(BrdfModel model, const std::vector<Material>& materials,
                                           const EvalOptions& options) override {
    return std::make_unique<OpenClEvaluator>(device_, model, materials, options);
  }
  MerlTable tabulate_merl(const TabulateSpec& spec, TabulateTiming* timing) override {
    return brdfbake::tabulate_merl(device_, spec, timing);
  }
  Table tabulate(const TabulateSpec& spec, TabulateTiming* timing) override {
    return brdfbake::tabulate(device_, spec, timing);
  }

 private:
  Device& device_;
};

}  // namespace

std::unique_ptr<detail::BrdfEvalKernel> detail::make_opencl_brdf_eval(Device& device) {
  return std::make_unique<OpenClBrdfEval>(device);
}

}  // namespace brdfbake
