// BRDF evaluation and tabulation on the reference backend: eval_reference, tabulate_reference and
// tabulate_merl_reference, every value by the scalar double reference
// (host/reference/src/brdf_eval.cpp, brdf_albedo.cpp) on the public Material converted to the
// reference's own parameter type; and the engine's reference kernel (kernel.hpp).
#include <chrono>
#include <cmath>
#include <vector>

#include "brdfbake/brdf.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/reference/brdf.hpp"
#include "families/brdf_eval/kernel.hpp"
#include "families/brdf_eval/model.hpp"
#include "families/brdf_eval/reference_convert.hpp"
#include "io/merl.hpp"

namespace brdfbake {

// ---- Conversions to the reference's types ---------------------------------------------------------

reference::BrdfModel detail::to_reference(BrdfModel model) {
  switch (model) {
    case BrdfModel::Disney:
      return reference::BrdfModel::Disney;
    case BrdfModel::Gltf:
      return reference::BrdfModel::Gltf;
    case BrdfModel::GltfCorrelated:
      return reference::BrdfModel::GltfCorrelated;
    case BrdfModel::Lambert:
      return reference::BrdfModel::Lambert;
    case BrdfModel::Phong:
      return reference::BrdfModel::Phong;
    case BrdfModel::BlinnPhong:
      return reference::BrdfModel::BlinnPhong;
    case BrdfModel::CookTorrance:
      return reference::BrdfModel::CookTorrance;
    case BrdfModel::BlinnPhongFromPbr:
      return reference::BrdfModel::BlinnPhongFromPbr;
  }
  throw Error("unknown BRDF model");
}

reference::MicrofacetDistribution detail::to_reference(MicrofacetDistribution d) {
  return d == MicrofacetDistribution::Beckmann ? reference::MicrofacetDistribution::Beckmann
                                               : reference::MicrofacetDistribution::Ggx;
}

reference::BrdfMaterial detail::to_reference(const Material& m) {
  reference::BrdfMaterial r;
  r.base_color = m.base_color;
  r.metallic = m.metallic;
  r.roughness = m.roughness;
  r.subsurface = m.subsurface;
  r.specular = m.specular;
  r.specular_tint = m.specular_tint;
  r.anisotropic = m.anisotropic;
  r.sheen = m.sheen;
  r.sheen_tint = m.sheen_tint;
  r.clearcoat = m.clearcoat;
  r.clearcoat_gloss = m.clearcoat_gloss;
  r.sheen_color = m.sheen_color;
  r.sheen_roughness = m.sheen_roughness;
  r.clearcoat_roughness = m.clearcoat_roughness;
  r.ior = m.ior;
  r.specular_factor = m.specular_factor;
  r.specular_color_factor = m.specular_color_factor;
  r.diffuse_color = m.diffuse_color;
  r.specular_color = m.specular_color;
  r.shininess = m.shininess;
  r.normalized = m.normalized;
  r.distribution = to_reference(m.distribution);
  return r;
}

namespace {

using math::kPi;
constexpr double kHalfPi = 0.5 * kPi;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

// ---- Evaluation ----------------------------------------------------------------------------------

void eval_reference(BrdfModel model, const Material& material, const double* pairs, size_t count, double* out) {
  validate_material(material, "material");
  const reference::BrdfModel rm = detail::to_reference(model);
  const reference::BrdfMaterial m = detail::to_reference(material);
  for (size_t i = 0; i < count; ++i) {
    const double* d = pairs + 6 * i;
    double wi[3], wo[3];
    if (!detail::unit_direction(d, wi)) throw Error(detail::pair_error(i, "wi"));
    if (!detail::unit_direction(d + 3, wo)) throw Error(detail::pair_error(i, "wo"));
    const Rgb f = reference::brdf(rm, m, {d[0], d[1], d[2]}, {d[3], d[4], d[5]});
    out[3 * i] = f.r;
    out[3 * i + 1] = f.g;
    out[3 * i + 2] = f.b;
  }
}

// ---- Tabulation ----------------------------------------------------------------------------------

MerlTable tabulate_merl_reference(const TabulateSpec& s, TabulateTiming* timing) {
  const auto t0 = Clock::now();
  if (s.layout != TableLayout::Merl) throw Error("tabulate_merl_reference needs the merl layout");
  detail::check_tabulate_spec(s);
  const std::vector<int> res = tabulate_resolution(s);
  const reference::BrdfModel model = detail::to_reference(s.model);
  const reference::BrdfMaterial m = detail::to_reference(s.materials.front().params);
  MerlTable t;
  t.values.resize(3 * kMerlBins);
  detail::parallel_for(static_cast<size_t>(kMerlThetaH * kMerlThetaD), [&](size_t row) {
    const int i = static_cast<int>(row) / kMerlThetaD, j = static_cast<int>(row) % kMerlThetaD;
    for (int k = 0; k < kMerlPhiD; ++k) {
      const io::MerlAngles a = io::merl_bin_centre(i, j, k);
      Vec3 wi{}, wo{};
      io::half_diff_to_directions(a.theta_h, a.theta_d, a.phi_d, wi, wo);
      const size_t b = row * kMerlPhiD + static_cast<size_t>(k);
      Rgb f{kMerlBelowHorizon, kMerlBelowHorizon, kMerlBelowHorizon};
      if (wi.z > 0.0 && wo.z > 0.0) f = reference::brdf(model, m, wi, wo);
      t.values[b] = f.r;
      t.values[kMerlBins + b] = f.g;
      t.values[2 * kMerlBins + b] = f.b;
    }
  });
  detail::tabulate_metadata(t.metadata, s, res, "reference (scalar double)", "fp64", "all");
  detail::merl_metadata(t.metadata);
  if (timing) timing->device_seconds = timing->wall_seconds = seconds_since(t0);
  return t;
}

Table tabulate_reference(const TabulateSpec& s, TabulateTiming* timing) {
  const auto t0 = Clock::now();
  if (s.layout == TableLayout::Merl) throw Error("the merl layout is written by tabulate_merl_reference");
  detail::check_tabulate_spec(s);
  const std::vector<int> res = tabulate_resolution(s);
  Table t = detail::make_tabulate_table(s, res);
  const reference::BrdfModel model = detail::to_reference(s.model);
  std::vector<reference::BrdfMaterial> materials;
  for (const NamedMaterial& nm : s.materials) materials.push_back(detail::to_reference(nm.params));
  auto store = [&](size_t cell, const Rgb& f) {
    t.data[cell * 3] = static_cast<float>(f.r);
    t.data[cell * 3 + 1] = static_cast<float>(f.g);
    t.data[cell * 3 + 2] = static_cast<float>(f.b);
  };
  switch (s.layout) {
    case TableLayout::Albedo: {
      const int n = res[0];
      detail::parallel_for(s.materials.size() * static_cast<size_t>(n), [&](size_t k) {
        const size_t m = k / static_cast<size_t>(n);
        const int i = static_cast<int>(k % static_cast<size_t>(n));
        store(m * static_cast<size_t>(n) + static_cast<size_t>(i),
              reference::directional_albedo(model, materials[m], (i + 0.5) / n * kHalfPi));
      });
      t.set_meta("method", "nested adaptive Gauss-Legendre over the half vector, to 1e-7 (reference)");
      break;
    }
    case TableLayout::Grid: {
      const int ni = res[0], no = res[1], np = res[2];
      const reference::BrdfMaterial& m = materials.front();
      detail::parallel_for(static_cast<size_t>(ni) * static_cast<size_t>(np), [&](size_t row) {
        const int k = static_cast<int>(row) / ni, i = static_cast<int>(row) % ni;
        const double ti = (i + 0.5) / ni * kHalfPi, pd = (k + 0.5) / np * kPi;
        for (int j = 0; j < no; ++j) {
          const double to = (j + 0.5) / no * kHalfPi;
          const Vec3 wi{std::sin(ti), 0.0, std::cos(ti)};
          const Vec3 wo{std::sin(to) * std::cos(pd), std::sin(to) * std::sin(pd), std::cos(to)};
          store(row * static_cast<size_t>(no) + static_cast<size_t>(j), reference::brdf(model, m, wi, wo));
        }
      });
      break;
    }
    case TableLayout::Slice: {
      const int w = res[0], h = res[1];
      const reference::BrdfMaterial& m = materials.front();
      detail::parallel_for(static_cast<size_t>(h), [&](size_t j) {
        for (int i = 0; i < w; ++i) {
          Vec3 wi{}, wo{};
          io::half_diff_to_directions((i + 0.5) / w * kHalfPi, (static_cast<double>(j) + 0.5) / h * kHalfPi,
                                      s.slice_phi_d, wi, wo);
          store(j * static_cast<size_t>(w) + static_cast<size_t>(i), reference::brdf(model, m, wi, wo));
        }
      });
      break;
    }
    case TableLayout::Merl:
      break;
  }
  detail::tabulate_metadata(t.metadata, s, res, "reference (scalar double)", "fp64", "all");
  if (timing) timing->device_seconds = timing->wall_seconds = seconds_since(t0);
  return t;
}

namespace {

class ReferenceEvaluator final : public PairEvaluator {
 public:
  ReferenceEvaluator(BrdfModel model, std::vector<Material> materials)
      : model_(model), materials_(std::move(materials)) {}
  void eval(const double* pairs, std::size_t count, double* out, EvalTiming* timing) override {
    for (std::size_t m = 0; m < materials_.size(); ++m)
      eval_reference(model_, materials_[m], pairs, count, out + 3 * m * count);
    if (timing) *timing = {};
  }

 private:
  BrdfModel model_;
  std::vector<Material> materials_;
};

class ReferenceBrdfEval final : public detail::BrdfEvalKernel {
 public:
  std::unique_ptr<PairEvaluator> evaluator(BrdfModel model, const std::vector<Material>& materials,
                                           const EvalOptions&) override {
    return std::make_unique<ReferenceEvaluator>(model, materials);
  }
  MerlTable tabulate_merl(const TabulateSpec& spec, TabulateTiming* timing) override {
    return tabulate_merl_reference(spec, timing);
  }
  Table tabulate(const TabulateSpec& spec, TabulateTiming* timing) override { return tabulate_reference(spec, timing); }
};

}  // namespace

std::unique_ptr<detail::BrdfEvalKernel> detail::make_reference_brdf_eval() {
  return std::make_unique<ReferenceBrdfEval>();
}

}  // namespace brdfbake
