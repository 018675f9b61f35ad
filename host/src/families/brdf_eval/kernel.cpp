// BRDF evaluation and tabulation on any backend: the public entries run the backend's
// implementation of the engine's kernel (kernel.hpp). An evaluator keeps to the backend's call lock
// for each batch and for its release (Backend::lock_calls), as every kernel call does.
#include "families/brdf_eval/kernel.hpp"

#include "families/kernels.hpp"

namespace brdfbake {

namespace {

class GuardedEvaluator final : public PairEvaluator {
 public:
  GuardedEvaluator(Backend& backend, std::unique_ptr<PairEvaluator> inner)
      : backend_(backend), inner_(std::move(inner)) {}
  ~GuardedEvaluator() override {
    const std::unique_lock<std::mutex> lock = backend_.lock_calls();  // its device buffers too
    inner_.reset();
  }
  GuardedEvaluator(const GuardedEvaluator&) = delete;
  GuardedEvaluator& operator=(const GuardedEvaluator&) = delete;
  void eval(const double* pairs, std::size_t count, double* out, EvalTiming* timing) override {
    const std::unique_lock<std::mutex> lock = backend_.lock_calls();
    inner_->eval(pairs, count, out, timing);
  }
  std::size_t chunk_pairs() const override { return inner_->chunk_pairs(); }

 private:
  Backend& backend_;
  std::unique_ptr<PairEvaluator> inner_;
};

}  // namespace

std::unique_ptr<PairEvaluator> make_evaluator(Backend& backend, BrdfModel model, const std::vector<Material>& materials,
                                              const EvalOptions& options) {
  std::unique_ptr<PairEvaluator> inner = detail::run_kernel<detail::BrdfEvalKernel>(
      backend, [&](detail::BrdfEvalKernel& k) { return k.evaluator(model, materials, options); });
  return std::make_unique<GuardedEvaluator>(backend, std::move(inner));
}

MerlTable tabulate_merl(Backend& backend, const TabulateSpec& spec, TabulateTiming* timing) {
  return detail::run_kernel<detail::BrdfEvalKernel>(
      backend, [&](detail::BrdfEvalKernel& k) { return k.tabulate_merl(spec, timing); });
}

Table tabulate(Backend& backend, const TabulateSpec& spec, TabulateTiming* timing) {
  return detail::run_kernel<detail::BrdfEvalKernel>(
      backend, [&](detail::BrdfEvalKernel& k) { return k.tabulate(spec, timing); });
}

}  // namespace brdfbake
