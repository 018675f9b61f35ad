// The Fresnel family's names: the models (with their kernel switches and definitions), the table
// kinds, the text of numbers in its messages and metadata, and the material presets by name.
#include <cstdio>
#include <string>
#include <vector>

#include "brdfbake/error.hpp"
#include "families/fresnel/model.hpp"

namespace brdfbake {

namespace {

const detail::FresnelModelInfo kModels[] = {
    {FresnelModel::Schlick, "schlick", "BRDFBAKE_FRESNEL_SCHLICK",
     "F = F0 + (F90 - F0)(1 - cos_theta)^5 (Schlick 1994)"},
    {FresnelModel::SchlickMetallic, "schlick-metallic", "BRDFBAKE_FRESNEL_SCHLICK_METALLIC",
     "Schlick with F90 = 1 and F0 = mix(dielectric_f0, base_color, metallic) (Burley 2012; glTF 2.0 "
     "metallic-roughness)"},
    {FresnelModel::SchlickIor, "schlick-ior", "BRDFBAKE_FRESNEL_SCHLICK_IOR",
     "Schlick with F90 = 1 and F0 = ((n1 - n2) / (n1 + n2))^2, n1 = ior_outside, n2 = ior"},
    {FresnelModel::Dielectric, "dielectric", "BRDFBAKE_FRESNEL_DIELECTRIC",
     "exact unpolarised Fresnel equations for a real relative index eta = ior / ior_outside (Born & "
     "Wolf 1.5.2); eta < 1 reflects totally past the critical angle"},
    {FresnelModel::Conductor, "conductor", "BRDFBAKE_FRESNEL_CONDUCTOR",
     "exact unpolarised Fresnel equations for a complex index n + ik seen from air (Born & Wolf 14.2)"},
    {FresnelModel::F82Tint, "f82-tint", "BRDFBAKE_FRESNEL_F82_TINT",
     "Schlick (F90 = 1) minus a cos_theta (1 - cos_theta)^6, a set so that F(1/7) = f82_tint * "
     "Schlick(1/7) (Hoffman 2023; OpenPBR metal)"},
    {FresnelModel::Empirical, "empirical", "BRDFBAKE_FRESNEL_EMPIRICAL",
     "R = clamp(bias + scale (1 - cos_theta)^power, 0, 1) (Fernando & Kilgard 2003, The Cg "
     "Tutorial, eq. 7-3, with I.N = -cos_theta)"},
};

}  // namespace

const detail::FresnelModelInfo& detail::fresnel_model_info(FresnelModel m) {
  for (const FresnelModelInfo& i : kModels)
    if (i.model == m) return i;
  throw Error("invalid FresnelModel value");
}

std::string detail::fresnel_number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

std::string detail::fresnel_number(const Rgb& c) {
  if (is_grey(c)) return fresnel_number(c.r);
  return "(" + fresnel_number(c.r) + ", " + fresnel_number(c.g) + ", " + fresnel_number(c.b) + ")";
}

std::string detail::fresnel_join(const std::vector<std::string>& v, const char* last_sep) {
  std::string s;
  for (size_t i = 0; i < v.size(); ++i) {
    if (i > 0) s += i + 1 == v.size() ? last_sep : ", ";
    s += v[i];
  }
  return s;
}

const MaterialPreset* detail::find_fresnel_preset(const std::string& name) {
  const MaterialPreset* p = find_material_preset(name);
  if (!p) {
    std::vector<std::string> names;
    for (const MaterialPreset& m : material_presets()) names.push_back(m.name);
    throw Error("unknown material '" + name + "' (expected one of " + fresnel_join(names, ", ") + ")");
  }
  return p;
}

FresnelModel fresnel_model_from_name(const std::string& name) {
  std::vector<std::string> names;
  for (const detail::FresnelModelInfo& i : kModels) {
    if (name == i.name) return i.model;
    names.push_back(i.name);
  }
  throw Error("unknown Fresnel model '" + name + "' (expected " + detail::fresnel_join(names, " or ") + ")");
}

const char* fresnel_model_name(FresnelModel model) { return detail::fresnel_model_info(model).name; }

const std::vector<FresnelModel>& fresnel_models() {
  static const std::vector<FresnelModel> models = [] {
    std::vector<FresnelModel> v;
    for (const detail::FresnelModelInfo& i : kModels) v.push_back(i.model);
    return v;
  }();
  return models;
}

bool fresnel_model_is_exact(FresnelModel model) {
  return model == FresnelModel::Dielectric || model == FresnelModel::Conductor;
}

FresnelTableKind fresnel_table_kind_from_name(const std::string& name) {
  return detail::enum_from_name(detail::kFresnelTableKindNames, name, "table kind");
}

const char* fresnel_table_kind_name(FresnelTableKind kind) {
  return detail::enum_name(detail::kFresnelTableKindNames, kind);
}

}  // namespace brdfbake
