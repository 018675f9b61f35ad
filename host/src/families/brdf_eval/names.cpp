// The BRDF models' and layouts' names (with each model's kernel switch), and the lobes a set of
// materials uses under a model (the kernel is compiled with those alone).
#include <algorithm>
#include <string>
#include <vector>

#include "brdfbake/brdf.hpp"
#include "brdfbake/error.hpp"
#include "families/brdf_eval/model.hpp"

namespace brdfbake {

using detail::max3;

namespace {

struct ModelName {
  BrdfModel model;
  const char* name;
  const char* define;
};
const ModelName kModels[] = {
    {BrdfModel::Disney, "disney", "BRDFBAKE_MODEL_DISNEY"},
    {BrdfModel::Gltf, "gltf", "BRDFBAKE_MODEL_GLTF"},
    {BrdfModel::GltfCorrelated, "gltf-correlated", "BRDFBAKE_MODEL_GLTF_CORRELATED"},
    {BrdfModel::Lambert, "lambert", "BRDFBAKE_MODEL_LAMBERT"},
    {BrdfModel::Phong, "phong", "BRDFBAKE_MODEL_PHONG"},
    {BrdfModel::BlinnPhong, "blinn-phong", "BRDFBAKE_MODEL_BLINN_PHONG"},
    {BrdfModel::CookTorrance, "cook-torrance", "BRDFBAKE_MODEL_COOK_TORRANCE"},
    {BrdfModel::BlinnPhongFromPbr, "blinn-phong-from-pbr", "BRDFBAKE_MODEL_BLINN_PHONG_FROM_PBR"},
};

const ModelName& model_entry(BrdfModel model) {
  for (const ModelName& m : kModels)
    if (m.model == model) return m;
  throw Error("unknown BRDF model");
}

}  // namespace

const char* detail::brdf_model_define(BrdfModel model) { return model_entry(model).define; }

BrdfModel brdf_model_from_name(const std::string& name) {
  std::string expected;
  for (const ModelName& m : kModels) {
    if (name == m.name) return m.model;
    expected += (expected.empty() ? "" : ", ") + std::string(m.name);
  }
  throw Error("unknown model '" + name + "' (expected " + expected + ")");
}

const char* brdf_model_name(BrdfModel model) { return model_entry(model).name; }

const std::vector<BrdfModel>& brdf_models() {
  static const std::vector<BrdfModel> models = [] {
    std::vector<BrdfModel> v;
    for (const ModelName& m : kModels) v.push_back(m.model);
    return v;
  }();
  return models;
}

TableLayout table_layout_from_name(const std::string& name) {
  return detail::enum_from_name(detail::kTableLayoutNames, name, "layout");
}

const char* table_layout_name(TableLayout layout) { return detail::enum_name(detail::kTableLayoutNames, layout); }

// ---- Lobes ----------------------------------------------------------------------------------------

Lobes lobes_used(BrdfModel model, const std::vector<Material>& materials) {
  Lobes l;
  for (const Material& m : materials) {
    switch (model) {
      case BrdfModel::Disney:
        l.diffuse |= m.metallic < 1.0;
        l.subsurface |= m.metallic < 1.0 && m.subsurface > 0.0;
        l.sheen |= m.metallic < 1.0 && m.sheen > 0.0;
        l.clearcoat |= m.clearcoat > 0.0;
        l.anisotropic |= m.anisotropic > 0.0;
        break;
      case BrdfModel::Gltf:
      case BrdfModel::GltfCorrelated: {
        l.diffuse |= m.metallic < 1.0;
        l.metal |= m.metallic > 0.0;
        const double q = (1.0 - m.ior) / (1.0 + m.ior), f0 = q * q;
        const Rgb& s = m.specular_color_factor;
        const bool grey =
            std::min(f0 * s.r, 1.0) == std::min(f0 * s.g, 1.0) && std::min(f0 * s.g, 1.0) == std::min(f0 * s.b, 1.0);
        l.specular_color |= m.metallic < 1.0 && (!grey || m.specular_factor != 1.0);
        l.sheen |= max3(m.sheen_color) > 0.0;
        l.clearcoat |= m.clearcoat > 0.0;
        break;
      }
      case BrdfModel::CookTorrance:
        l.beckmann |= m.distribution == MicrofacetDistribution::Beckmann;
        l.ggx |= m.distribution == MicrofacetDistribution::Ggx;
        break;
      default:
        break;
    }
  }
  return l;
}

Lobes all_lobes(BrdfModel model) {
  Lobes l;
  switch (model) {
    case BrdfModel::Disney:
      l.diffuse = l.subsurface = l.sheen = l.clearcoat = l.anisotropic = true;
      break;
    case BrdfModel::Gltf:
    case BrdfModel::GltfCorrelated:
      l.diffuse = l.metal = l.specular_color = l.sheen = l.clearcoat = true;
      break;
    case BrdfModel::CookTorrance:
      l.beckmann = l.ggx = true;
      break;
    default:
      break;
  }
  return l;
}

std::string lobes_name(BrdfModel, const Lobes& l) {
  std::string s;
  const std::pair<bool, const char*> flags[] = {{l.diffuse, "diffuse"},
                                                {l.subsurface, "subsurface"},
                                                {l.sheen, "sheen"},
                                                {l.clearcoat, "clearcoat"},
                                                {l.anisotropic, "anisotropic"},
                                                {l.metal, "metal"},
                                                {l.specular_color, "specular-color"},
                                                {l.beckmann, "beckmann"},
                                                {l.ggx, "ggx"}};
  for (const auto& [on, name] : flags)
    if (on) s += (s.empty() ? "" : ",") + std::string(name);
  return s.empty() ? "none" : s;
}

}  // namespace brdfbake
