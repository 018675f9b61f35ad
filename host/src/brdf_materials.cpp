// Materials for bulk BRDF evaluation: our JSON material files, the materials of glTF 2.0 documents,
// and the range checks every parameter goes through.
//
// glTF documents are read with nlohmann_json rather than tinygltf: only the "materials" array is
// needed, and tinygltf's loaders insist on the buffers and images a .gltf refers to, which material
// tooling does not have (shared/scenes holds the JSON alone).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "brdfbake/brdf.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/scene.hpp"
#include "io/json_input.hpp"
#include "text.hpp"

namespace brdfbake {
namespace {

// Untrusted input: read with io::parse_json's limits, quoted by io::json_excerpt only.
using json = nlohmann::ordered_json;
using io::json_excerpt;

// A name from a file, as messages quote it.
std::string clip(const std::string& s, size_t n = 60) { return s.size() <= n ? s : s.substr(0, n) + "..."; }

// The names of `materials` for a message: the first few, then how many more.
std::string name_list(const std::vector<NamedMaterial>& materials, size_t shown = 8) {
  std::string names;
  for (size_t i = 0; i < materials.size() && i < shown; ++i) names += (i ? ", '" : "'") + clip(materials[i].name) + "'";
  if (materials.size() > shown) names += " and " + std::to_string(materials.size() - shown) + " more";
  return names;
}

// ---- Range checks ---------------------------------------------------------------------------------

void check_unit(const std::string& where, const char* field, double v) {
  if (!(v >= 0.0 && v <= 1.0))
    throw Error(where + ": " + field + " must be in [0, 1] (got " + detail::fmt_number(v) + ")");
}

void check_unit(const std::string& where, const char* field, const Rgb& c) {
  for (double v : {c.r, c.g, c.b})
    if (!(v >= 0.0 && v <= 1.0))
      throw Error(where + ": " + field + " must have every channel in [0, 1] (got [" + detail::fmt_number(c.r) + ", " +
                  detail::fmt_number(c.g) + ", " + detail::fmt_number(c.b) + "])");
}

// ---- Field names --------------------------------------------------------------------------------
// One table drives parsing, defaults and the metadata dump: the name in our files (glTF's and
// Disney's own names), its glTF alias, and where it goes.
enum class Kind { Scalar, Colour, OptionalColour, OptionalScalar, Boolean, Distribution };
struct Field {
  const char* name;
  const char* alias;  // glTF's name of the same parameter ("" when none)
  Kind kind;
  double Material::*scalar;
  Rgb Material::*colour;
  std::optional<Rgb> Material::*optional_colour;
  std::optional<double> Material::*optional_scalar;
};

const Field kFields[] = {
    {"baseColor", "baseColorFactor", Kind::Colour, nullptr, &Material::base_color, nullptr, nullptr},
    {"metallic", "metallicFactor", Kind::Scalar, &Material::metallic, nullptr, nullptr, nullptr},
    {"roughness", "roughnessFactor", Kind::Scalar, &Material::roughness, nullptr, nullptr, nullptr},
    {"subsurface", "", Kind::Scalar, &Material::subsurface, nullptr, nullptr, nullptr},
    {"specular", "", Kind::Scalar, &Material::specular, nullptr, nullptr, nullptr},
    {"specularTint", "", Kind::Scalar, &Material::specular_tint, nullptr, nullptr, nullptr},
    {"anisotropic", "", Kind::Scalar, &Material::anisotropic, nullptr, nullptr, nullptr},
    {"sheen", "", Kind::Scalar, &Material::sheen, nullptr, nullptr, nullptr},
    {"sheenTint", "", Kind::Scalar, &Material::sheen_tint, nullptr, nullptr, nullptr},
    {"clearcoat", "clearcoatFactor", Kind::Scalar, &Material::clearcoat, nullptr, nullptr, nullptr},
    {"clearcoatGloss", "", Kind::Scalar, &Material::clearcoat_gloss, nullptr, nullptr, nullptr},
    {"sheenColor", "sheenColorFactor", Kind::Colour, nullptr, &Material::sheen_color, nullptr, nullptr},
    {"sheenRoughness", "sheenRoughnessFactor", Kind::Scalar, &Material::sheen_roughness, nullptr, nullptr, nullptr},
    {"clearcoatRoughness", "clearcoatRoughnessFactor", Kind::Scalar, &Material::clearcoat_roughness, nullptr, nullptr,
     nullptr},
    {"ior", "", Kind::Scalar, &Material::ior, nullptr, nullptr, nullptr},
    {"specularFactor", "", Kind::Scalar, &Material::specular_factor, nullptr, nullptr, nullptr},
    {"specularColorFactor", "", Kind::Colour, nullptr, &Material::specular_color_factor, nullptr, nullptr},
    {"diffuseColor", "", Kind::OptionalColour, nullptr, nullptr, &Material::diffuse_color, nullptr},
    {"specularColor", "", Kind::OptionalColour, nullptr, nullptr, &Material::specular_color, nullptr},
    {"shininess", "", Kind::OptionalScalar, nullptr, nullptr, nullptr, &Material::shininess},
    {"normalized", "", Kind::Boolean, nullptr, nullptr, nullptr, nullptr},
    {"distribution", "", Kind::Distribution, nullptr, nullptr, nullptr, nullptr},
};

std::string known_fields() {
  std::string s = "name, model";
  for (const Field& f : kFields) s += std::string(", ") + f.name;
  return s;
}

double number(const json& v, const std::string& where, const std::string& key) {
  if (!v.is_number()) throw Error(where + ": " + key + " must be a number (got " + json_excerpt(v) + ")");
  const double x = v.get<double>();
  if (!std::isfinite(x)) throw Error(where + ": " + key + " must be a finite number (got " + json_excerpt(v) + ")");
  return x;
}

// A colour: [r, g, b], or [r, g, b, a] (glTF's baseColorFactor; alpha is not a BRDF parameter).
Rgb colour(const json& v, const std::string& where, const std::string& key, bool allow_alpha) {
  if (!v.is_array() || !(v.size() == 3 || (allow_alpha && v.size() == 4)))
    throw Error(where + ": " + key + " must be an array of 3 numbers" + (allow_alpha ? " (or 4 with alpha)" : "") +
                " (got " + json_excerpt(v) + ")");
  return Rgb{number(v[0], where, key + "[0]"), number(v[1], where, key + "[1]"), number(v[2], where, key + "[2]")};
}

void set_field(const Field& f, Material& m, const json& v, const std::string& where, const std::string& key) {
  switch (f.kind) {
    case Kind::Scalar:
      m.*(f.scalar) = number(v, where, key);
      break;
    case Kind::Colour:
      m.*(f.colour) = colour(v, where, key, std::string(f.name) == "baseColor");
      break;
    case Kind::OptionalColour:
      m.*(f.optional_colour) = colour(v, where, key, false);
      break;
    case Kind::OptionalScalar:
      m.*(f.optional_scalar) = number(v, where, key);
      break;
    case Kind::Boolean:
      if (!v.is_boolean()) throw Error(where + ": " + key + " must be true or false (got " + json_excerpt(v) + ")");
      m.normalized = v.get<bool>();
      break;
    case Kind::Distribution: {
      const std::string d = v.is_string() ? v.get<std::string>() : std::string();
      if (d == "ggx")
        m.distribution = MicrofacetDistribution::Ggx;
      else if (d == "beckmann")
        m.distribution = MicrofacetDistribution::Beckmann;
      else
        throw Error(where + ": distribution must be \"ggx\" or \"beckmann\" (got " + json_excerpt(v) + ")");
      break;
    }
  }
}

}  // namespace

void validate_material(const Material& m, const std::string& where) {
  check_unit(where, "baseColor", m.base_color);
  check_unit(where, "metallic", m.metallic);
  check_unit(where, "roughness", m.roughness);
  check_unit(where, "subsurface", m.subsurface);
  check_unit(where, "specular", m.specular);
  check_unit(where, "specularTint", m.specular_tint);
  check_unit(where, "anisotropic", m.anisotropic);
  check_unit(where, "sheen", m.sheen);
  check_unit(where, "sheenTint", m.sheen_tint);
  check_unit(where, "clearcoat", m.clearcoat);
  check_unit(where, "clearcoatGloss", m.clearcoat_gloss);
  check_unit(where, "sheenColor", m.sheen_color);
  check_unit(where, "sheenRoughness", m.sheen_roughness);
  check_unit(where, "clearcoatRoughness", m.clearcoat_roughness);
  // KHR_materials_ior: "Valid values for ior are numbers greater than or equal to 1. In addition, a
  // value of 0 is allowed." (0 gives F0 = 1.)
  if (!(m.ior == 0.0 || (m.ior >= 1.0 && std::isfinite(m.ior))))
    throw Error(where + ": ior must be 0 or a finite number >= 1 (got " + detail::fmt_number(m.ior) + ")");
  check_unit(where, "specularFactor", m.specular_factor);
  // KHR_materials_specular: specularColorFactor may exceed 1 (F0 is clamped to 1 after scaling).
  for (double v : {m.specular_color_factor.r, m.specular_color_factor.g, m.specular_color_factor.b})
    if (!(v >= 0.0 && std::isfinite(v)))
      throw Error(where + ": specularColorFactor must have every channel finite and >= 0 (got " +
                  detail::fmt_number(v) + ")");
  if (m.diffuse_color) check_unit(where, "diffuseColor", *m.diffuse_color);
  if (m.specular_color) check_unit(where, "specularColor", *m.specular_color);
  if (m.shininess && !(*m.shininess >= 0.0 && *m.shininess <= kMaxShininess))
    throw Error(where + ": shininess must be in [0, " + detail::fmt_number(kMaxShininess) + "] (got " +
                detail::fmt_number(*m.shininess) + ")");
}

std::vector<NamedMaterial> parse_materials_json(const std::string& text, const std::string& origin) {
  const json doc = io::parse_json(text, origin);
  if (!doc.is_object() || !doc.contains("materials") || !doc.at("materials").is_array())
    throw Error(origin + ": expected {\"materials\": [...]} at the top level");
  std::vector<NamedMaterial> out;
  const json& list = doc.at("materials");
  if (list.empty()) throw Error(origin + ": the materials array is empty");
  for (size_t i = 0; i < list.size(); ++i) {
    const json& item = list[i];
    std::string where = origin + ": material #" + std::to_string(i);
    if (!item.is_object()) throw Error(where + " must be an object (got " + json_excerpt(item) + ")");
    NamedMaterial nm;
    nm.name = "material_" + std::to_string(i);
    if (auto it = item.find("name"); it != item.end()) {
      if (!it->is_string()) throw Error(where + ": name must be a string (got " + json_excerpt(*it) + ")");
      nm.name = it->get<std::string>();
    }
    where = origin + ": material '" + clip(nm.name) + "'";
    for (auto it = item.begin(); it != item.end(); ++it) {
      const std::string& key = it.key();
      if (key == "name") continue;
      if (key == "model") {
        if (!it->is_string()) throw Error(where + ": model must be a string (got " + json_excerpt(*it) + ")");
        try {
          nm.model = brdf_model_from_name(it->get<std::string>());
        } catch (const Error& e) {
          throw Error(where + ": " + e.what());
        }
        continue;
      }
      const Field* field = nullptr;
      for (const Field& f : kFields)
        if (key == f.name || (f.alias[0] != '\0' && key == f.alias)) field = &f;
      if (!field)
        throw Error(where + ": unknown parameter '" + key.substr(0, 60) + "' (expected " + known_fields() + ")");
      set_field(*field, nm.params, *it, where, key);
    }
    validate_material(nm.params, where);
    for (const NamedMaterial& other : out)
      if (other.name == nm.name) throw Error(where + ": the name is used twice");
    out.push_back(std::move(nm));
  }
  return out;
}

namespace {

// The materials of a glTF document as the gltf BRDF takes them (one reader of glTF: scene.cpp).
std::vector<NamedMaterial> gltf_materials(const Scene& scene, const std::string& origin) {
  if (scene.materials.empty()) throw Error(origin + ": the glTF document has no materials");
  std::vector<NamedMaterial> out;
  for (const SceneMaterial& s : scene.materials) {
    NamedMaterial nm;
    nm.model = BrdfModel::Gltf;
    nm.name = s.name.empty() ? "material_" + std::to_string(s.index) : s.name;
    Material& m = nm.params;
    // The scene reader has applied glTF 2.0's defaults and ranges (scene.cpp).
    m.base_color = Rgb{s.base_color[0], s.base_color[1], s.base_color[2]};
    m.metallic = s.metallic;
    m.roughness = s.roughness;
    m.sheen_color = Rgb{s.sheen_color[0], s.sheen_color[1], s.sheen_color[2]};
    m.sheen_roughness = s.sheen_roughness;
    m.clearcoat = s.clearcoat;
    m.clearcoat_roughness = s.clearcoat_roughness;
    m.specular_factor = s.specular;
    m.specular_color_factor = Rgb{s.specular_color[0], s.specular_color[1], s.specular_color[2]};
    m.ior = s.ior;
    if (s.iridescence_ext) {
      m.iridescence = s.iridescence;
      m.iridescence_ior = s.iridescence_ior;
      m.iridescence_thickness = s.iridescence_thickness_max;
    }
    for (const std::string& t : s.textures) nm.notes.push_back(t + " ignored (textures are not read)");
    nm.base_color_image = s.base_color_image;
    nm.metallic_roughness_image = s.metallic_roughness_image;
    for (const std::string& ext : s.extensions)
      if (ext != "KHR_materials_sheen" && ext != "KHR_materials_clearcoat" && ext != "KHR_materials_specular" &&
          ext != "KHR_materials_ior")
        nm.notes.push_back(clip(ext) + " ignored (not part of the gltf BRDF here)");
    validate_material(m, origin + ": materials[" + std::to_string(s.index) + "] ('" + clip(nm.name) + "')");
    out.push_back(std::move(nm));
  }
  return out;
}

}  // namespace

std::vector<NamedMaterial> parse_gltf_materials(const std::string& text, const std::string& origin) {
  return gltf_materials(parse_scene_json(text, origin, ""), origin);
}

std::vector<NamedMaterial> read_materials(const std::string& path) {
  // In-memory material JSON (the Python package): text starting with '{' that names no file.
  if (const size_t first = path.find_first_not_of(" \t\r\n"); first != std::string::npos && path[first] == '{') {
    std::error_code ec;  // a name too long for a path is no file either
    if (!std::filesystem::exists(path, ec)) {
      const json doc = io::parse_json(path, "material JSON");
      if (doc.is_object() && doc.contains("asset") && doc["asset"].is_object())
        return parse_gltf_materials(path, "material JSON");
      return parse_materials_json(path, "material JSON");
    }
  }
  auto ends_with = [&](const char* ext) {
    const std::string e(ext);
    if (path.size() < e.size()) return false;
    std::string tail = path.substr(path.size() - e.size());
    std::transform(tail.begin(), tail.end(), tail.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return tail == e;
  };
  if (ends_with(".glb") || ends_with(".gltf")) return gltf_materials(read_scene(path), path);
  const std::string text = io::read_text_file(path, "material file");
  if (text.compare(0, 4, "glTF") == 0) return gltf_materials(read_scene(path), path);
  const json doc = io::parse_json(text, path);
  if (doc.is_object() && doc.contains("asset") && doc.at("asset").is_object()) return parse_gltf_materials(text, path);
  return parse_materials_json(text, path);
}

const NamedMaterial& find_material(const std::vector<NamedMaterial>& materials, const std::string& name,
                                   const std::string& origin) {
  const std::string names = name_list(materials);
  if (name.empty()) {
    if (materials.size() == 1) return materials.front();
    throw Error(origin + " holds " + std::to_string(materials.size()) + " materials (" + names +
                "); name the one to use");
  }
  for (const NamedMaterial& m : materials)
    if (m.name == name) return m;
  throw Error(origin + " has no material named '" + clip(name) + "' (it has " + names + ")");
}

BrdfModel resolve_model(const std::optional<BrdfModel>& chosen, const NamedMaterial& material) {
  if (chosen) return *chosen;
  if (material.model) return *material.model;
  throw Error("material '" + material.name + "' names no model; choose one (" + [] {
    std::string s;
    for (BrdfModel m : brdf_models()) s += (s.empty() ? "" : ", ") + std::string(brdf_model_name(m));
    return s;
  }() + ")");
}

std::string material_to_json(const NamedMaterial& nm) {
  nlohmann::ordered_json j;
  j["name"] = nm.name;
  if (nm.model) j["model"] = brdf_model_name(*nm.model);
  const Material& m = nm.params;
  for (const Field& f : kFields) {
    switch (f.kind) {
      case Kind::Scalar:
        j[f.name] = m.*(f.scalar);
        break;
      case Kind::Colour: {
        const Rgb c = m.*(f.colour);
        j[f.name] = {c.r, c.g, c.b};
        break;
      }
      case Kind::OptionalColour:
        if (const auto& c = m.*(f.optional_colour)) j[f.name] = {c->r, c->g, c->b};
        break;
      case Kind::OptionalScalar:
        if (const auto& v = m.*(f.optional_scalar)) j[f.name] = *v;
        break;
      case Kind::Boolean:
        j[f.name] = m.normalized;
        break;
      case Kind::Distribution:
        j[f.name] = m.distribution == MicrofacetDistribution::Beckmann ? "beckmann" : "ggx";
        break;
    }
  }
  return io::json_text(j, -1);
}

}  // namespace brdfbake
