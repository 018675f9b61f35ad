// The two backends behind brdfbake::Backend: an OpenCL device and the scalar double reference.
// Each family's entry forwards to the family's device code or to its reference code; nothing else
// in the product chooses between them.
#include "brdfbake/backend.hpp"

#include <cmath>

#include "brdfbake/error.hpp"

namespace brdfbake {

namespace {

class OpenClEvaluator final : public PairEvaluator {
 public:
  OpenClEvaluator(Device& device, BrdfModel model, const std::vector<Material>& materials, const EvalOptions& options)
      : evaluator_(device, model, materials, options) {}
  void eval(const double* pairs, std::size_t count, double* out, EvalTiming* timing) override {
    evaluator_.eval(pairs, count, out, timing);
  }

 private:
  BrdfEvaluator evaluator_;
};

class ReferenceEvaluator final : public PairEvaluator {
 public:
  ReferenceEvaluator(BrdfModel model, std::vector<Material> materials) : model_(model), materials_(std::move(materials)) {}
  void eval(const double* pairs, std::size_t count, double* out, EvalTiming* timing) override {
    for (std::size_t m = 0; m < materials_.size(); ++m) eval_reference(model_, materials_[m], pairs, count, out + 3 * m * count);
    if (timing) *timing = {};
  }

 private:
  BrdfModel model_;
  std::vector<Material> materials_;
};

class OpenClBackend final : public Backend {
 public:
  explicit OpenClBackend(Device device) : device_(std::move(device)) {}
  bool is_reference() const override { return false; }
  std::string name() const override { return device_.info().name; }
  Device* device() override { return &device_; }
  Precision result_precision(Precision requested) const override { return requested; }

  Table lut(const LutSpec& s, LutTiming* t, const Progress& p) override { return bake_lut(device_, s, t, p); }
  Table fresnel(const FresnelSpec& s, FresnelTiming* t) override { return bake_fresnel(device_, s, t); }
  Table thin_film(const ThinFilmSpec& s, ThinFilmTiming* t) override { return bake_thin_film(device_, s, t); }
  CubeLevels prefilter(const EnvImage& env, const PrefilterSpec& s, PrefilterTiming* t, const EnvProgress& p) override {
    return prefilter_environment(device_, env, s, t, p);
  }
  IrradianceResult irradiance(const EnvImage& env, const IrradianceSpec& s, const EnvProgress& p) override {
    return compute_irradiance(device_, env, s, p);
  }
  std::unique_ptr<PairEvaluator> evaluator(BrdfModel model, const std::vector<Material>& materials,
                                           const EvalOptions& options) override {
    return std::make_unique<OpenClEvaluator>(device_, model, materials, options);
  }
  MerlTable tabulate_merl(const TabulateSpec& s, TabulateTiming* t) override { return brdfbake::tabulate_merl(device_, s, t); }
  Table tabulate(const TabulateSpec& s, TabulateTiming* t) override { return brdfbake::tabulate(device_, s, t); }

 private:
  Device device_;
};

class ReferenceBackend final : public Backend {
 public:
  bool is_reference() const override { return true; }
  std::string name() const override { return "reference"; }
  Device* device() override { return nullptr; }
  Precision result_precision(Precision) const override { return Precision::Fp64; }

  Table lut(const LutSpec& s, LutTiming* t, const Progress& p) override { return bake_lut_reference(s, t, p); }
  Table fresnel(const FresnelSpec& s, FresnelTiming* t) override { return bake_fresnel_reference(s, t); }
  Table thin_film(const ThinFilmSpec& s, ThinFilmTiming* t) override { return bake_thin_film_reference(s, t); }
  CubeLevels prefilter(const EnvImage&, const PrefilterSpec&, PrefilterTiming*, const EnvProgress&) override {
    throw Error("the reference backend does not prefilter yet; choose an OpenCL device");
  }
  IrradianceResult irradiance(const EnvImage&, const IrradianceSpec&, const EnvProgress&) override {
    throw Error("the reference backend does not compute irradiance yet; choose an OpenCL device");
  }
  std::unique_ptr<PairEvaluator> evaluator(BrdfModel model, const std::vector<Material>& materials,
                                           const EvalOptions&) override {
    return std::make_unique<ReferenceEvaluator>(model, materials);
  }
  MerlTable tabulate_merl(const TabulateSpec& s, TabulateTiming* t) override { return tabulate_merl_reference(s, t); }
  Table tabulate(const TabulateSpec& s, TabulateTiming* t) override { return tabulate_reference(s, t); }
};

}  // namespace

std::shared_ptr<Backend> Backend::open(const std::string& selector) {
  if (selector == "reference") return std::make_shared<ReferenceBackend>();
  return std::make_shared<OpenClBackend>(Device::open(selector));
}

std::shared_ptr<Backend> Backend::open(const Device& device) { return std::make_shared<OpenClBackend>(device); }

}  // namespace brdfbake
