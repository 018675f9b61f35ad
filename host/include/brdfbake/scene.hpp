// glTF 2.0 scenes as far as baking needs them: each material's factors, textures present and
// extensions (docs/SCENES.md). Buffers and images are not read.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace brdfbake {

using Rgb3 = std::array<double, 3>;

// One glTF material, as far as the rules need it: factors (with the specification's defaults),
// which textures are present, and which extensions.
struct SceneMaterial {
  int index = -1;  // in materials[]; -1 for the default material
  std::string name;
  std::string label;                    // "#3 Name" (or "#3", or "default material")
  bool by_mesh = false;                 // referenced by a mesh primitive
  bool by_variant = false;              // referenced by a KHR_materials_variants mapping
  std::vector<std::string> extensions;  // the keys of its "extensions", in file order
  // Every texture it names, as the field's path inside the material, e.g.
  // "pbrMetallicRoughness.baseColorTexture", "normalTexture", "KHR_materials_sheen.sheenColorTexture".
  std::vector<std::string> textures;

  Rgb3 base_color{1, 1, 1};
  bool base_color_texture = false;
  double metallic = 1.0, roughness = 1.0;
  bool metallic_roughness_texture = false;
  // The image files of those two textures when the file was read from a folder and the image is a
  // file there (not a data: URI, not inside a GLB): the preview reads their means. "" otherwise.
  std::string base_color_image, metallic_roughness_image;
  Rgb3 emissive{0, 0, 0};
  bool emissive_texture = false;
  double emissive_strength = 1.0;
  bool unlit = false;

  bool sheen = false;
  Rgb3 sheen_color{0, 0, 0};
  bool sheen_color_texture = false;
  double sheen_roughness = 0.0;
  bool sheen_roughness_texture = false;

  bool clearcoat_ext = false;
  double clearcoat = 0.0;
  bool clearcoat_texture = false;
  double clearcoat_roughness = 0.0;
  bool clearcoat_roughness_texture = false;

  bool ior_ext = false;
  double ior = 1.5;

  bool specular_ext = false;
  double specular = 1.0;
  bool specular_texture = false;
  Rgb3 specular_color{1, 1, 1};
  bool specular_color_texture = false;

  bool transmission_ext = false;
  double transmission = 0.0;
  bool transmission_texture = false;

  bool volume_ext = false;
  double thickness = 0.0;
  bool thickness_texture = false;

  bool dispersion_ext = false;
  double dispersion = 0.0;

  bool iridescence_ext = false;
  double iridescence = 0.0;
  bool iridescence_texture = false;
  double iridescence_ior = 1.3;
  double iridescence_thickness_min = 100.0, iridescence_thickness_max = 400.0;  // nm
  bool iridescence_thickness_texture = false;

  bool anisotropy_ext = false;
  double anisotropy_strength = 0.0;
  bool anisotropy_texture = false;
};

struct Scene {
  std::string path;
  std::string container;                          // "gltf" or "glb"
  std::vector<SceneMaterial> materials;           // every material of the file, in order
  std::optional<SceneMaterial> default_material;  // when some primitive has no material
  bool has_meshes = false;
  std::vector<std::string> variants;  // KHR_materials_variants names
  std::vector<std::string> extensions_used, extensions_required;
  std::vector<std::string> warnings;  // missing .bin files and images, ignored extensions
};

// Reads the materials of a glTF 2.0 file: .gltf (JSON) or .glb (the JSON chunk). Buffers and images
// are not read; missing ones are warnings. Throws Error naming the file (and the field) for
// malformed JSON, a truncated or corrupt .glb, a version other than 2.x, a material field of the
// wrong type or out of range, and an extension in extensionsRequired that brdfbake does not know.
Scene read_scene(const std::string& path);
// The same from text already read (`origin` names it in messages; `base_dir` resolves URIs, "" to
// skip the check of buffers and images).
Scene parse_scene_json(const std::string& json_text, const std::string& origin, const std::string& base_dir);
Scene parse_glb(const std::string& bytes, const std::string& origin, const std::string& base_dir);

}  // namespace brdfbake
