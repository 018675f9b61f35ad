// glTF 2.0 scenes, the material part only: .gltf (JSON) and .glb (the JSON chunk of a binary glTF).
//
// Only what the planner's rules look at is read: the materials' factors (with the specification's
// defaults), which textures they name, their extensions, and which materials meshes and
// KHR_materials_variants mappings reach. Buffers, images and geometry are never loaded, so a .gltf
// whose .bin and images are missing still plans (each missing file is a warning). nlohmann_json
// reads the JSON (tinygltf would load and decode every buffer and image first).
#include "brdfbake/scene.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "brdfbake/error.hpp"
#include "io/json_input.hpp"
#include "io/special_files.hpp"
#include "text.hpp"

namespace brdfbake {

namespace {

using json = nlohmann::ordered_json;
namespace fs = std::filesystem;

// Extensions the planner has a rule for, or knows to be irrelevant to which tables a material
// needs (geometry, texture containers and transforms, lights, metadata). A file that *requires*
// anything else is refused: brdfbake cannot tell what it would call for.
const char* const kMaterialExtensions[] = {
    "KHR_materials_sheen",      "KHR_materials_clearcoat",         "KHR_materials_ior",
    "KHR_materials_specular",   "KHR_materials_transmission",      "KHR_materials_volume",
    "KHR_materials_dispersion", "KHR_materials_iridescence",       "KHR_materials_anisotropy",
    "KHR_materials_unlit",      "KHR_materials_emissive_strength",
};
const char* const kNeutralExtensions[] = {
    "KHR_materials_variants",
    "KHR_texture_transform",
    "KHR_texture_basisu",
    "EXT_texture_webp",
    "EXT_texture_avif",
    "KHR_mesh_quantization",
    "KHR_draco_mesh_compression",
    "EXT_meshopt_compression",
    "EXT_mesh_gpu_instancing",
    "KHR_lights_punctual",
    "KHR_xmp",
    "KHR_xmp_json_ld",
    "KHR_animation_pointer",
    "KHR_node_visibility",
};

bool in_list(const std::string& name, const char* const* begin, const char* const* end) {
  return std::any_of(begin, end, [&](const char* n) { return name == n; });
}
bool material_extension_known(const std::string& name) {
  return in_list(name, std::begin(kMaterialExtensions), std::end(kMaterialExtensions));
}
bool extension_known(const std::string& name) {
  return material_extension_known(name) || in_list(name, std::begin(kNeutralExtensions), std::end(kNeutralExtensions));
}

// A name or text from the file, as messages quote it.
std::string clip(const std::string& s, size_t n = 60) { return s.size() <= n ? s : s.substr(0, n) + "..."; }

// Reads the fields of one JSON object, every error naming the file and the field's path.
class Reader {
 public:
  Reader(const std::string& origin) : origin_(origin) {}

  [[noreturn]] void fail(const std::string& path, const std::string& problem) const {
    throw Error(origin_ + ": " + path + ": " + problem);
  }

  static std::string describe(const json& v) { return io::json_excerpt(v); }

  const json* object(const json& parent, const std::string& key, const std::string& path) const {
    auto it = parent.find(key);
    if (it == parent.end()) return nullptr;
    if (!it->is_object()) fail(path, "must be an object (got " + describe(*it) + ")");
    return &*it;
  }
  const json* array(const json& parent, const std::string& key, const std::string& path) const {
    auto it = parent.find(key);
    if (it == parent.end()) return nullptr;
    if (!it->is_array()) fail(path, "must be an array (got " + describe(*it) + ")");
    return &*it;
  }
  // A number in [lo, hi] (values a hair outside from rounding in exporters are clamped).
  double number(const json& parent, const std::string& key, const std::string& path, double fallback, double lo,
                double hi) const {
    auto it = parent.find(key);
    if (it == parent.end()) return fallback;
    if (!it->is_number()) fail(path, "must be a number (got " + describe(*it) + ")");
    const double v = it->get<double>();
    if (!std::isfinite(v)) fail(path, "must be finite");
    const double slack = 1e-6;
    if (v < lo - slack || v > hi + slack)
      fail(path, "must be in " + range(lo, hi) + " (got " + detail::fmt_number(v) + ")");
    return std::clamp(v, lo, hi);
  }
  Rgb3 rgb(const json& parent, const std::string& key, const std::string& path, const Rgb3& fallback, double lo,
           double hi, size_t count = 3) const {
    auto it = parent.find(key);
    if (it == parent.end()) return fallback;
    if (!it->is_array() || it->size() != count)
      fail(path, "must be an array of " + std::to_string(count) + " numbers (got " + describe(*it) + ")");
    Rgb3 out = fallback;
    for (size_t c = 0; c < count; ++c) {
      const json& e = (*it)[c];
      const std::string p = path + "[" + std::to_string(c) + "]";
      if (!e.is_number()) fail(p, "must be a number (got " + describe(e) + ")");
      const double v = e.get<double>();
      if (!std::isfinite(v) || v < lo - 1e-6 || v > hi + 1e-6)
        fail(p, "must be in " + range(lo, hi) + " (got " + detail::fmt_number(v) + ")");
      if (c < 3) out[c] = std::clamp(v, lo, hi);
    }
    return out;
  }
  bool texture(const json& parent, const std::string& key, const std::string& path) const {
    const json* t = object(parent, key, path);
    if (!t) return false;
    auto it = t->find("index");
    if (it == t->end() || !it->is_number_integer() || it->get<long long>() < 0)
      fail(path + ".index", "must be a texture index (a non-negative integer)");
    return true;
  }
  int index(const json& v, const std::string& path, size_t count, const std::string& what) const {
    if (!v.is_number_integer()) fail(path, "must be an integer index (got " + describe(v) + ")");
    const long long i = v.get<long long>();
    if (i < 0 || static_cast<unsigned long long>(i) >= count)
      fail(path, std::to_string(i) + " is not " + what + " index (the file has " + std::to_string(count) + ")");
    return static_cast<int>(i);
  }
  std::vector<std::string> strings(const json& parent, const std::string& key, const std::string& path) const {
    std::vector<std::string> out;
    const json* a = array(parent, key, path);
    if (!a) return out;
    for (size_t i = 0; i < a->size(); ++i) {
      if (!(*a)[i].is_string()) fail(path + "[" + std::to_string(i) + "]", "must be a string");
      out.push_back((*a)[i].get<std::string>());
    }
    return out;
  }

 private:
  static std::string range(double lo, double hi) {
    return "[" + detail::fmt_number(lo) + ", " + (std::isinf(hi) ? std::string("inf)") : detail::fmt_number(hi) + "]");
  }
  std::string origin_;
};

constexpr double kInf = HUGE_VAL;

// Material extensions without a rule, and the materials that use them.
using UnknownExtensions = std::map<std::string, std::vector<std::string>>;

// The keys of `obj` that name a texture ("...Texture"), with `prefix`.
void list_textures(const json& obj, const std::string& prefix, std::vector<std::string>& out) {
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    const std::string& k = it.key();
    if (k.size() > 7 && k.compare(k.size() - 7, 7, "Texture") == 0) out.push_back(prefix + clip(k, 80));
  }
}

// The factors of the KHR_materials_* extensions the rules know, from the material's "extensions"
// object `ext` (with the specification's defaults and ranges).
void read_material_extensions(const Reader& r, const json& ext_object, const std::string& at, SceneMaterial& s) {
  const json* ext = &ext_object;
  auto get = [&](const char* name) -> const json* { return r.object(*ext, name, at + ".extensions." + name); };
  auto path = [&](const char* name, const char* field) { return at + ".extensions." + name + "." + field; };

  if (get("KHR_materials_unlit")) s.unlit = true;
  if (const json* e = get("KHR_materials_emissive_strength"))
    s.emissive_strength =
        r.number(*e, "emissiveStrength", path("KHR_materials_emissive_strength", "emissiveStrength"), 1.0, 0, kInf);
  if (const json* e = get("KHR_materials_sheen")) {
    const char* n = "KHR_materials_sheen";
    s.sheen = true;
    s.sheen_color = r.rgb(*e, "sheenColorFactor", path(n, "sheenColorFactor"), {0, 0, 0}, 0, 1);
    s.sheen_color_texture = r.texture(*e, "sheenColorTexture", path(n, "sheenColorTexture"));
    s.sheen_roughness = r.number(*e, "sheenRoughnessFactor", path(n, "sheenRoughnessFactor"), 0.0, 0, 1);
    s.sheen_roughness_texture = r.texture(*e, "sheenRoughnessTexture", path(n, "sheenRoughnessTexture"));
  }
  if (const json* e = get("KHR_materials_clearcoat")) {
    const char* n = "KHR_materials_clearcoat";
    s.clearcoat_ext = true;
    s.clearcoat = r.number(*e, "clearcoatFactor", path(n, "clearcoatFactor"), 0.0, 0, 1);
    s.clearcoat_texture = r.texture(*e, "clearcoatTexture", path(n, "clearcoatTexture"));
    s.clearcoat_roughness = r.number(*e, "clearcoatRoughnessFactor", path(n, "clearcoatRoughnessFactor"), 0.0, 0, 1);
    s.clearcoat_roughness_texture = r.texture(*e, "clearcoatRoughnessTexture", path(n, "clearcoatRoughnessTexture"));
    r.texture(*e, "clearcoatNormalTexture", path(n, "clearcoatNormalTexture"));
  }
  if (const json* e = get("KHR_materials_ior")) {
    s.ior_ext = true;
    // at most 10: the thin-film tables' indices (a base for KHR_materials_iridescence) end there,
    // and every planned table must take what the reader accepts (found by fuzz_scene)
    s.ior = r.number(*e, "ior", path("KHR_materials_ior", "ior"), 1.5, 0, 10);
    if (s.ior > 0 && s.ior < 1)
      r.fail(path("KHR_materials_ior", "ior"), "must be 0 or at least 1 (got " + detail::fmt_number(s.ior) + ")");
  }
  if (const json* e = get("KHR_materials_specular")) {
    const char* n = "KHR_materials_specular";
    s.specular_ext = true;
    s.specular = r.number(*e, "specularFactor", path(n, "specularFactor"), 1.0, 0, 1);
    s.specular_texture = r.texture(*e, "specularTexture", path(n, "specularTexture"));
    s.specular_color = r.rgb(*e, "specularColorFactor", path(n, "specularColorFactor"), {1, 1, 1}, 0, kInf);
    s.specular_color_texture = r.texture(*e, "specularColorTexture", path(n, "specularColorTexture"));
  }
  if (const json* e = get("KHR_materials_transmission")) {
    const char* n = "KHR_materials_transmission";
    s.transmission_ext = true;
    s.transmission = r.number(*e, "transmissionFactor", path(n, "transmissionFactor"), 0.0, 0, 1);
    s.transmission_texture = r.texture(*e, "transmissionTexture", path(n, "transmissionTexture"));
  }
  if (const json* e = get("KHR_materials_volume")) {
    const char* n = "KHR_materials_volume";
    s.volume_ext = true;
    s.thickness = r.number(*e, "thicknessFactor", path(n, "thicknessFactor"), 0.0, 0, kInf);
    s.thickness_texture = r.texture(*e, "thicknessTexture", path(n, "thicknessTexture"));
    r.number(*e, "attenuationDistance", path(n, "attenuationDistance"), 1.0, 0, kInf);
    r.rgb(*e, "attenuationColor", path(n, "attenuationColor"), {1, 1, 1}, 0, 1);
  }
  if (const json* e = get("KHR_materials_dispersion")) {
    s.dispersion_ext = true;
    // 20 / Abbe number: about 0.2-1 for glass; 1000 keeps the channels' indices within the Fresnel
    // tables' range (kFresnelMaxIndex)
    s.dispersion = r.number(*e, "dispersion", path("KHR_materials_dispersion", "dispersion"), 0.0, 0, 1000);
  }
  if (const json* e = get("KHR_materials_iridescence")) {
    const char* n = "KHR_materials_iridescence";
    s.iridescence_ext = true;
    s.iridescence = r.number(*e, "iridescenceFactor", path(n, "iridescenceFactor"), 0.0, 0, 1);
    s.iridescence_texture = r.texture(*e, "iridescenceTexture", path(n, "iridescenceTexture"));
    s.iridescence_ior = r.number(*e, "iridescenceIor", path(n, "iridescenceIor"), 1.3, 1, 10);  // the thin film's range
    s.iridescence_thickness_min =
        r.number(*e, "iridescenceThicknessMinimum", path(n, "iridescenceThicknessMinimum"), 100.0, 0, 1e5);
    s.iridescence_thickness_max =
        r.number(*e, "iridescenceThicknessMaximum", path(n, "iridescenceThicknessMaximum"), 400.0, 0, 1e5);
    s.iridescence_thickness_texture =
        r.texture(*e, "iridescenceThicknessTexture", path(n, "iridescenceThicknessTexture"));
  }
  if (const json* e = get("KHR_materials_anisotropy")) {
    const char* n = "KHR_materials_anisotropy";
    s.anisotropy_ext = true;
    s.anisotropy_strength = r.number(*e, "anisotropyStrength", path(n, "anisotropyStrength"), 0.0, 0, 1);
    r.number(*e, "anisotropyRotation", path(n, "anisotropyRotation"), 0.0, -kInf, kInf);
    s.anisotropy_texture = r.texture(*e, "anisotropyTexture", path(n, "anisotropyTexture"));
  }
}

SceneMaterial read_material(const Reader& r, const json& m, int index, UnknownExtensions& unknown) {
  const std::string at = "materials[" + std::to_string(index) + "]";
  if (!m.is_object()) r.fail(at, "must be an object");
  SceneMaterial s;
  s.index = index;
  if (auto it = m.find("name"); it != m.end()) {
    if (!it->is_string()) r.fail(at + ".name", "must be a string");
    s.name = it->get<std::string>();
  }
  s.label = "#" + std::to_string(index) + (s.name.empty() ? "" : " " + clip(s.name, 80));

  if (const json* pbr = r.object(m, "pbrMetallicRoughness", at + ".pbrMetallicRoughness")) {
    const std::string p = at + ".pbrMetallicRoughness";
    s.base_color = r.rgb(*pbr, "baseColorFactor", p + ".baseColorFactor", {1, 1, 1}, 0, 1, 4);
    s.base_color_texture = r.texture(*pbr, "baseColorTexture", p + ".baseColorTexture");
    s.metallic = r.number(*pbr, "metallicFactor", p + ".metallicFactor", 1.0, 0, 1);
    s.roughness = r.number(*pbr, "roughnessFactor", p + ".roughnessFactor", 1.0, 0, 1);
    s.metallic_roughness_texture = r.texture(*pbr, "metallicRoughnessTexture", p + ".metallicRoughnessTexture");
    list_textures(*pbr, "pbrMetallicRoughness.", s.textures);
  }
  list_textures(m, "", s.textures);
  s.emissive = r.rgb(m, "emissiveFactor", at + ".emissiveFactor", {0, 0, 0}, 0, 1);
  s.emissive_texture = r.texture(m, "emissiveTexture", at + ".emissiveTexture");

  const json* ext = r.object(m, "extensions", at + ".extensions");
  if (!ext) return s;
  for (auto it = ext->begin(); it != ext->end(); ++it) {
    s.extensions.push_back(it.key());
    if (!it->is_object())
      r.fail(at + ".extensions." + clip(it.key()), "must be an object (got " + r.describe(*it) + ")");
    list_textures(*it, clip(it.key(), 80) + ".", s.textures);
  }
  read_material_extensions(r, *ext, at, s);
  for (const std::string& name : s.extensions)
    if (!material_extension_known(name)) unknown[name].push_back(s.label);
  return s;
}

// Percent-decodes a relative URI ("my%20file.bin" -> "my file.bin").
std::string decode_uri(const std::string& uri) {
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

// The file of texture `tex` ({"index": i}) of `root`: textures[i].source -> images[j].uri under
// `base_dir`, when that is a file there; "" otherwise (checked indices only: anything else is "").
std::string texture_file(const json& root, const json* tex, const std::string& base_dir) {
  if (!tex || !tex->is_object() || base_dir.empty()) return "";
  const auto idx = tex->find("index");
  const auto textures = root.find("textures"), images = root.find("images");
  if (idx == tex->end() || !idx->is_number_integer() || textures == root.end() || !textures->is_array() ||
      images == root.end() || !images->is_array())
    return "";
  const long long i = idx->get<long long>();
  if (i < 0 || size_t(i) >= textures->size() || !(*textures)[size_t(i)].is_object()) return "";
  const auto src = (*textures)[size_t(i)].find("source");
  if (src == (*textures)[size_t(i)].end() || !src->is_number_integer()) return "";
  const long long j = src->get<long long>();
  if (j < 0 || size_t(j) >= images->size() || !(*images)[size_t(j)].is_object()) return "";
  const auto uri = (*images)[size_t(j)].find("uri");
  if (uri == (*images)[size_t(j)].end() || !uri->is_string()) return "";
  const std::string u = uri->get<std::string>();
  if (u.rfind("data:", 0) == 0 || u.find("://") != std::string::npos) return "";
  const fs::path file = fs::path(base_dir) / decode_uri(u);
  std::error_code ec;
  return fs::is_regular_file(file, ec) ? file.string() : std::string();
}

void check_resources(const Reader& r, const json& root, const std::string& key, const std::string& origin,
                     const std::string& base_dir, std::vector<std::string>& warnings) {
  const json* list = r.array(root, key, key);
  if (!list) return;
  std::vector<std::string> missing;
  for (size_t i = 0; i < list->size(); ++i) {
    const json& e = (*list)[i];
    if (!e.is_object()) continue;
    auto it = e.find("uri");
    if (it == e.end() || !it->is_string()) continue;  // GLB-stored or bufferView-backed
    const std::string uri = it->get<std::string>();
    if (uri.rfind("data:", 0) == 0 || uri.find("://") != std::string::npos) continue;
    std::error_code ec;
    if (!fs::exists(fs::path(base_dir) / decode_uri(uri), ec)) missing.push_back(uri);
  }
  if (missing.empty()) return;
  std::string names;
  for (size_t i = 0; i < missing.size() && i < 3; ++i)
    names += (i ? ", " : "") + std::string("'") + clip(missing[i]) + "'";
  if (missing.size() > 3) names += " and " + std::to_string(missing.size() - 3) + " more";
  warnings.push_back(origin + ": " + std::to_string(missing.size()) + " of " + std::to_string(list->size()) + " " +
                     key + " not found (" + names + "); only the materials are read, so the plan does not need them");
}

}  // namespace

namespace {

// Which materials the meshes' primitives and their KHR_materials_variants mappings reach (and the
// default material when a primitive names none).
void mark_reached_materials(const Reader& r, const json& root, Scene& scene) {
  const size_t material_count = scene.materials.size();
  if (const json* meshes = r.array(root, "meshes", "meshes")) {
    scene.has_meshes = !meshes->empty();
    for (size_t mi = 0; mi < meshes->size(); ++mi) {
      const std::string mp = "meshes[" + std::to_string(mi) + "]";
      const json& mesh = (*meshes)[mi];
      if (!mesh.is_object()) r.fail(mp, "must be an object");
      const json* prims = r.array(mesh, "primitives", mp + ".primitives");
      if (!prims) continue;
      for (size_t pi = 0; pi < prims->size(); ++pi) {
        const std::string pp = mp + ".primitives[" + std::to_string(pi) + "]";
        const json& prim = (*prims)[pi];
        if (!prim.is_object()) r.fail(pp, "must be an object");
        auto mat = prim.find("material");
        if (mat == prim.end()) {
          if (!scene.default_material) {
            SceneMaterial d;
            d.label = "default material";
            d.by_mesh = true;
            scene.default_material = d;
          }
        } else {
          const int idx = r.index(*mat, pp + ".material", material_count, "a material");
          scene.materials[static_cast<size_t>(idx)].by_mesh = true;
        }
        const json* pext = r.object(prim, "extensions", pp + ".extensions");
        if (!pext) continue;
        const json* kv = r.object(*pext, "KHR_materials_variants", pp + ".extensions.KHR_materials_variants");
        if (!kv) continue;
        const std::string kp = pp + ".extensions.KHR_materials_variants.mappings";
        const json* maps = r.array(*kv, "mappings", kp);
        if (!maps) continue;
        for (size_t k = 0; k < maps->size(); ++k) {
          const json& map = (*maps)[k];
          const std::string p = kp + "[" + std::to_string(k) + "]";
          if (!map.is_object() || !map.contains("material")) r.fail(p, "must be an object with a material");
          const int idx = r.index(map["material"], p + ".material", material_count, "a material");
          scene.materials[static_cast<size_t>(idx)].by_variant = true;
          if (const json* vv = r.array(map, "variants", p + ".variants"))
            for (size_t q = 0; q < vv->size(); ++q)
              r.index((*vv)[q], p + ".variants[" + std::to_string(q) + "]", scene.variants.size(), "a variant");
        }
      }
    }
  }
}

}  // namespace

Scene parse_scene_json(const std::string& text, const std::string& origin, const std::string& base_dir) {
  const json root = io::parse_json(text, origin);
  const Reader r(origin);
  if (!root.is_object()) throw Error(origin + ": not a glTF document (the JSON is not an object)");
  const json* asset = r.object(root, "asset", "asset");
  if (!asset) throw Error(origin + ": not a glTF 2.0 document (no 'asset' object)");
  auto version = asset->find("version");
  if (version == asset->end() || !version->is_string())
    r.fail("asset.version", "missing (a glTF 2.0 file has \"2.0\")");
  const std::string v = version->get<std::string>();
  if (v.rfind("2.", 0) != 0) r.fail("asset.version", "'" + clip(v) + "' is not glTF 2.x");

  Scene scene;
  scene.path = origin;
  scene.container = "gltf";
  scene.extensions_used = r.strings(root, "extensionsUsed", "extensionsUsed");
  scene.extensions_required = r.strings(root, "extensionsRequired", "extensionsRequired");
  for (size_t i = 0; i < scene.extensions_required.size(); ++i) {
    const std::string& name = scene.extensions_required[i];
    if (!extension_known(name))
      r.fail("extensionsRequired[" + std::to_string(i) + "]",
             "'" + clip(name) +
                 "' is required by the file but unknown to brdfbake (it cannot tell which tables it calls for)");
  }
  for (const std::string& name : scene.extensions_used)
    if (!extension_known(name) && std::find(scene.extensions_required.begin(), scene.extensions_required.end(), name) ==
                                      scene.extensions_required.end())
      scene.warnings.push_back(origin + ": extension " + clip(name) + " (extensionsUsed) has no rule and is ignored");

  if (const json* mats = r.array(root, "materials", "materials")) {
    UnknownExtensions unknown;
    for (size_t i = 0; i < mats->size(); ++i)
      scene.materials.push_back(read_material(r, (*mats)[i], static_cast<int>(i), unknown));
    for (const auto& [name, labels] : unknown) {
      std::string who;
      for (size_t i = 0; i < labels.size() && i < 3; ++i) who += (i ? ", " : "") + labels[i];
      if (labels.size() > 3) who += " and " + std::to_string(labels.size() - 3) + " more";
      scene.warnings.push_back(origin + ": material extension " + clip(name) + " (" + who +
                               ") has no rule; those materials are planned from the extensions brdfbake knows");
    }
  }

  // Variants: names, and which materials their mappings reach.
  if (const json* ext = r.object(root, "extensions", "extensions"))
    if (const json* kv = r.object(*ext, "KHR_materials_variants", "extensions.KHR_materials_variants"))
      if (const json* vs = r.array(*kv, "variants", "extensions.KHR_materials_variants.variants"))
        for (size_t i = 0; i < vs->size(); ++i) {
          const json& e = (*vs)[i];
          std::string name = "variant " + std::to_string(i);
          if (e.is_object() && e.contains("name") && e["name"].is_string()) name = e["name"].get<std::string>();
          scene.variants.push_back(name);
        }

  mark_reached_materials(r, root, scene);

  // The image files of the textures the preview reads the means of.
  if (const auto mats = root.find("materials"); mats != root.end() && mats->is_array())
    for (SceneMaterial& s : scene.materials) {
      if (s.index < 0 || size_t(s.index) >= mats->size() || !(*mats)[size_t(s.index)].is_object()) continue;
      const json& m = (*mats)[size_t(s.index)];
      const auto pbr = m.find("pbrMetallicRoughness");
      if (pbr == m.end() || !pbr->is_object()) continue;
      const auto bc = pbr->find("baseColorTexture"), mr = pbr->find("metallicRoughnessTexture");
      s.base_color_image = texture_file(root, bc == pbr->end() ? nullptr : &*bc, base_dir);
      s.metallic_roughness_image = texture_file(root, mr == pbr->end() ? nullptr : &*mr, base_dir);
    }

  if (!base_dir.empty()) {
    check_resources(r, root, "buffers", origin, base_dir, scene.warnings);
    check_resources(r, root, "images", origin, base_dir, scene.warnings);
  }
  return scene;
}

namespace {

uint32_t le32(const std::string& b, size_t at) {
  uint32_t v = 0;
  for (size_t i = 0; i < 4; ++i) v |= uint32_t(static_cast<unsigned char>(b[at + i])) << (8 * i);
  return v;
}

constexpr uint32_t kGlbMagic = 0x46546C67;   // "glTF"
constexpr uint32_t kChunkJson = 0x4E4F534A;  // "JSON"

}  // namespace

namespace {

// A binary glTF's JSON chunk, read through `read(offset, count)` from a container of `size` bytes,
// after checking the header and that every chunk lies inside the file (only chunk headers are read
// beyond the JSON: a .glb's buffers may be gigabytes).
template <class Read>
std::string glb_json_chunk(std::uint64_t size, const std::string& origin, Read read) {
  auto bad = [&](const std::string& what) { return Error(origin + ": " + what); };
  if (size < 12) throw bad("truncated GLB: " + std::to_string(size) + " bytes, shorter than the 12-byte header");
  const std::string header = read(0, 12);
  if (le32(header, 0) != kGlbMagic) throw bad("not a binary glTF (the first 4 bytes are not 'glTF')");
  const uint32_t version = le32(header, 4);
  if (version != 2) throw bad("GLB container version " + std::to_string(version) + " (only version 2 is read)");
  const uint32_t length = le32(header, 8);
  if (length > size)
    throw bad("truncated GLB: the header declares " + std::to_string(length) + " bytes, the file has " +
              std::to_string(size));
  if (length < size)
    throw bad("corrupt GLB: the header declares " + std::to_string(length) + " bytes, the file has " +
              std::to_string(size));
  if (length < 20) throw bad("truncated GLB: no JSON chunk after the header");
  const std::string chunk = read(12, 8);
  const uint32_t json_length = le32(chunk, 0);
  if (le32(chunk, 4) != kChunkJson) throw bad("corrupt GLB: the first chunk is not the JSON chunk");
  if (size_t(json_length) > length - 20)
    throw bad("truncated GLB: the JSON chunk declares " + std::to_string(json_length) + " bytes, " +
              std::to_string(length - 20) + " remain");
  if (json_length > io::kJsonMaxBytes)
    throw bad("the GLB's JSON chunk is larger than " + std::to_string(io::kJsonMaxBytes >> 20) + " MiB (" +
              std::to_string(json_length) + " bytes)");
  // Any further chunks (BIN, extensions') must lie inside the file too.
  std::uint64_t at = 20 + std::uint64_t(json_length);
  while (at < length) {
    if (length - at < 8) throw bad("truncated GLB: a chunk header at byte " + std::to_string(at) + " is cut off");
    const uint32_t chunk_length = le32(read(at, 8), 0);
    if (std::uint64_t(chunk_length) > length - at - 8)
      throw bad("truncated GLB: the chunk at byte " + std::to_string(at) + " declares " + std::to_string(chunk_length) +
                " bytes, " + std::to_string(length - at - 8) + " remain");
    at += 8 + std::uint64_t(chunk_length);
  }
  // The JSON chunk is padded with spaces to 4 bytes; some writers pad with zeros.
  std::string text = read(20, json_length);
  while (!text.empty() && (text.back() == '\0' || text.back() == ' ')) text.pop_back();
  return text;
}

}  // namespace

Scene parse_glb(const std::string& bytes, const std::string& origin, const std::string& base_dir) {
  const std::string text = glb_json_chunk(bytes.size(), origin, [&](std::uint64_t at, std::uint64_t n) {
    return bytes.substr(static_cast<size_t>(at), static_cast<size_t>(n));
  });
  Scene scene = parse_scene_json(text, origin, base_dir);
  scene.container = "glb";
  return scene;
}

Scene read_scene(const std::string& path) {
  std::error_code ec;
  if (path.empty()) throw Error("no scene file given");
  if (fs::is_directory(path, ec)) throw Error("cannot read scene '" + path + "': it is a folder");
  std::string base_dir = fs::path(path).parent_path().string();
  if (base_dir.empty()) base_dir = ".";
  if (const std::string problem = io::input_problem(path, io::Streams::Yes); !problem.empty())
    throw Error("cannot read scene '" + path + "': " + problem);
  if (io::file_type(path) != io::FileType::Regular) {
    // A stream (a pipe, /dev/stdin): read whole, at most the JSON limit, then .gltf or .glb by its bytes.
    const std::string text = io::read_text_file(path, "scene");
    if (text.size() >= 4 && le32(text, 0) == kGlbMagic) {
      const std::string json = glb_json_chunk(text.size(), path, [&](std::uint64_t at, std::uint64_t n) {
        return text.substr(static_cast<size_t>(at), static_cast<size_t>(n));
      });
      Scene scene = parse_scene_json(json, path, base_dir);
      scene.container = "glb";
      return scene;
    }
    return parse_scene_json(text, path, base_dir);
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int err = errno;
    const bool exists = fs::exists(path, ec);
    throw Error("cannot read scene '" + path + "': " + (exists ? std::strerror(err ? err : EACCES) : "no such file"));
  }
  std::string ext = fs::path(path).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  char magic[4] = {0, 0, 0, 0};
  in.read(magic, 4);
  const bool glb = in.gcount() == 4 && le32(std::string(magic, 4), 0) == kGlbMagic;
  in.clear();
  if (ext == ".glb" || glb) {
    const auto size = fs::file_size(path, ec);
    if (ec) throw Error("cannot read scene '" + path + "': " + ec.message());
    const std::string text = glb_json_chunk(size, path, [&](std::uint64_t at, std::uint64_t n) {
      std::string b(static_cast<size_t>(n), '\0');
      in.seekg(static_cast<std::streamoff>(at));
      in.read(b.data(), static_cast<std::streamsize>(n));
      if (static_cast<std::uint64_t>(in.gcount()) != n) throw IoError("cannot read scene '" + path + "': read error");
      return b;
    });
    Scene scene = parse_scene_json(text, path, base_dir);
    scene.container = "glb";
    return scene;
  }
  return parse_scene_json(io::read_text_file(path, "scene"), path, base_dir);
}

}  // namespace brdfbake
