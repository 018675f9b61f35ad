// A bake's files as a target engine loads them (bake_files.hpp).
#include "families/preview/bake_files.hpp"

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "brdfbake/error.hpp"
#include "engines/babylon_frame.hpp"
#include "engines/filament_dfg.hpp"
#include "io/babylon_env.hpp"
#include "io/gpu_cube_read.hpp"
#include "io/json_input.hpp"
#include "io/png_image.hpp"
#include "io/table_read.hpp"

namespace brdfbake::detail::preview {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

std::string join_path(const std::string& folder, const std::string& file) { return (fs::path(folder) / file).string(); }

// The engine file of the manifest's file set whose name ends in `tail`.
std::string engine_file(const json& manifest, const std::string& folder, const std::string& tail) {
  if (manifest.contains("engine") && manifest["engine"].contains("files"))
    for (const auto& f : manifest["engine"]["files"])
      if (f.is_string() && ends_with(f.get<std::string>(), tail)) return join_path(folder, f.get<std::string>());
  throw Error("'" + folder + "': the bake has no engine file *" + tail + " (bake with --target)");
}

// The first manifest entry of a kind (and, for the prefilter, the GGX distribution).
const json* manifest_file(const json& manifest, const std::string& kind, const std::string& distribution = "ggx") {
  if (!manifest.contains("files")) return nullptr;
  for (const auto& f : manifest["files"]) {
    if (!f.contains("kind") || f["kind"] != kind) continue;
    if (kind == "prefilter" && f.contains("parameters") && f["parameters"].contains("distribution") &&
        f["parameters"]["distribution"] != distribution)
      continue;
    if (kind == "irradiance" && !ends_with(f.value("path", std::string()), ".json")) continue;
    return &f;
  }
  return nullptr;
}

std::vector<double> numbers(const json& a, const std::string& what) {
  std::vector<double> out;
  for (const auto& row : a) {
    if (row.is_array()) {
      for (const auto& v : row) out.push_back(v.get<double>());
    } else {
      out.push_back(row.get<double>());
    }
  }
  if (out.size() < 27) throw Error(what + ": expected 9 RGB coefficients");
  return out;
}

// Filament's "sh" key: 9 lines of "r g b" (cmgen's layout).
std::vector<double> filament_sh(const std::vector<std::pair<std::string, std::string>>& kv, const std::string& path) {
  for (const auto& [k, v] : kv)
    if (k == "sh") {
      std::istringstream in(v);
      std::vector<double> out;
      double x = 0.0;
      while (in >> x) out.push_back(x);
      if (out.size() != 27)
        throw Error("'" + path + "': the sh key holds " + std::to_string(out.size()) + " numbers, expected 27");
      return out;
    }
  throw Error("'" + path + "': no sh key (Filament's spherical harmonics)");
}

// The manifest of a bake folder, checked to be of this target and (when given) of this environment.
json read_manifest(const std::string& folder, EngineTarget target, const std::string& environment) {
  const std::string manifest_path = join_path(folder, "manifest.json");
  std::error_code ec;
  if (!fs::is_regular_file(manifest_path, ec))
    throw Error("'" + folder + "' holds no manifest.json: give the output folder of brdfbake bake --target " +
                engine_target_name(target));
  const json manifest = io::parse_json(io::read_text_file(manifest_path, "manifest"), manifest_path);
  const std::string baked_for = manifest.contains("engine") && manifest["engine"].contains("target")
                                    ? manifest["engine"]["target"].get<std::string>()
                                    : std::string("generic");
  if (baked_for != engine_target_name(target))
    throw Error("'" + folder + "' was baked for target " + baked_for + ", not " + engine_target_name(target) +
                ": give --target " + baked_for + ", or bake again with --target " + engine_target_name(target));

  // The chain must be of this environment: the reference integrates it.
  if (!environment.empty())
    if (const json* chain = manifest_file(manifest, "prefilter"); chain && chain->contains("environment")) {
      const std::string baked = (*chain)["environment"].get<std::string>();
      std::error_code e1, e2;
      const bool same = baked == environment || (fs::exists(baked, e1) && fs::exists(environment, e2) &&
                                                 fs::equivalent(baked, environment, e1));
      if (!same)
        throw Error("'" + folder + "' was baked from '" + baked + "', not from '" + environment +
                    "': give the environment of the bake (--env), or bake again");
    }
  return manifest;
}

// The DFG table: ggx-multiscatter, or ggx (scale, bias); Filament's own for filament, which never
// reads the bake's (engines/filament_dfg.hpp).
void read_dfg(const json& manifest, BakeFiles& b) {
  const std::string& folder = b.folder;
  if (b.target == EngineTarget::Filament) {
    b.dfg = detail::filament_dfg_table();
    b.dfg_file = "Filament's built-in DFG table (light_iblDFG; its cmgen's DFV_Multiscatter and DFV_Charlie)";
    b.dfg_multiscatter = true;
    b.dfg_sqrt_n_dot_v = false;
    return;
  }
  const json* dfg = manifest_file(manifest, "ggx-multiscatter");
  if (!dfg) {
    dfg = manifest_file(manifest, "ggx");
    b.dfg_multiscatter = false;
  }
  if (!dfg) throw Error("'" + folder + "': the bake has no GGX DFG table");
  b.dfg_file = join_path(folder, (*dfg)["path"].get<std::string>());
  b.dfg = io::read_table(b.dfg_file);
  if (b.dfg.channel_count() < 2) throw Error("'" + b.dfg_file + "': a DFG table has at least 2 channels");
  if (dfg->contains("parameters") && (*dfg)["parameters"].value("n_dot_v_axis", std::string("uniform")) == "sqrt")
    b.dfg_sqrt_n_dot_v = true;
}

// Babylon.js's .env file: RGBD PNG faces per level, and the irradiance polynomial.
void read_babylon_lighting(const json& manifest, BakeFiles& b) {
  const std::string& folder = b.folder;
  b.specular_file = engine_file(manifest, folder, ".env");
  const io::BabylonEnv env = io::decode_babylon_env(io::read_binary_file(b.specular_file, ".env file"));
  std::vector<std::vector<std::vector<uint8_t>>> levels;
  for (size_t i = 0; i < env.images.size(); ++i) {
    if (i % 6 == 0) levels.emplace_back();
    levels.back().push_back(env.images[i]);
  }
  // in the environment's frame, as Babylon.js's left-handed world sees it (engines/babylon_frame.hpp)
  b.specular = detail::mirror_cube_x(io::decode_rgbd_cube(levels, env.width, b.specular_file));
  b.specular_format = "RGBD PNG, expanded to RGBA16F";
  b.lod_scale = env.lod_generation_scale;
  b.diffuse = DiffuseSource::BabylonPolynomial;
  b.diffuse_file = b.specular_file + " (irradiance polynomial)";
  for (const auto& c : detail::mirror_babylon_polynomial_x(env.polynomial)) b.sh.insert(b.sh.end(), c.begin(), c.end());
}

// EXT_lights_image_based in a glTF file: RGBD PNG faces per level, and SH irradiance coefficients.
void read_gltf_lighting(const json& manifest, BakeFiles& b) {
  const std::string& folder = b.folder;
  b.specular_file = engine_file(manifest, folder, ".gltf");
  const json doc = io::parse_json(io::read_text_file(b.specular_file, "glTF file"), b.specular_file);
  const json& light = doc.at("extensions").at("EXT_lights_image_based").at("lights").at(0);
  const int size = light.at("specularImageSize").get<int>();
  std::vector<std::vector<std::vector<uint8_t>>> levels;
  for (const auto& level : light.at("specularImages")) {
    levels.emplace_back();
    for (const auto& index : level) {
      const std::string uri = doc.at("images").at(index.get<size_t>()).at("uri").get<std::string>();
      levels.back().push_back(io::read_binary_file(join_path(folder, uri), "specular image"));
    }
  }
  b.specular = io::decode_rgbd_cube(levels, size, b.specular_file);
  b.specular_format = "RGBD PNG, expanded to RGBA16F";
  // Babylon.js's EXT_lights_image_based loader: lodGenerationScale = (N - 1) / log2(specularImageSize)
  b.lod_scale = double(levels.size() - 1) / std::log2(double(size));
  b.diffuse = DiffuseSource::GltfSh;
  b.diffuse_file = b.specular_file + " (irradianceCoefficients)";
  b.sh = numbers(light.at("irradianceCoefficients"), b.specular_file);
  // the scene its rotation is for, and the cube and harmonics as that scene samples them in the glTF
  // frame (engines/babylon_frame.hpp)
  std::array<double, 4> rotation = {0.0, 0.0, 0.0, 1.0};
  if (light.contains("rotation")) rotation = light.at("rotation").get<std::array<double, 4>>();
  b.gltf_scene = detail::gltf_scene_of_rotation(rotation, b.specular_file);
  std::array<Rgb3, 9> c{};
  for (size_t k = 0; k < 27; ++k) c[k / 3][k % 3] = b.sh[k];
  detail::gltf_light_to_scene_frame(b.specular, c);
  for (size_t k = 0; k < 27; ++k) b.sh[k] = c[k / 3][k % 3];
}

// The specular chain and the diffuse source the target's shader samples.
void read_lighting(const json& manifest, BakeFiles& b) {
  const std::string& folder = b.folder;
  std::vector<std::pair<std::string, std::string>> kv;
  switch (b.target) {
    case EngineTarget::Generic: {
      const json* chain = manifest_file(manifest, "prefilter");
      const json* irr = manifest_file(manifest, "irradiance");
      if (!chain || !irr) throw Error("'" + folder + "': the bake has no GGX chain or no irradiance SH JSON");
      b.specular_file = join_path(folder, (*chain)["path"].get<std::string>());
      b.specular = io::read_gpu_cube(b.specular_file, &b.specular_format);
      b.diffuse_file = join_path(folder, (*irr)["path"].get<std::string>());
      const json sh = io::parse_json(io::read_text_file(b.diffuse_file, "SH JSON"), b.diffuse_file);
      b.diffuse = DiffuseSource::OurSh;
      b.sh_order = sh.at("order").get<int>();
      b.sh = numbers(sh.at("irradiance_over_pi"), b.diffuse_file);
      break;
    }
    case EngineTarget::Filament:
      b.specular_file = engine_file(manifest, folder, "_ibl.ktx");
      b.specular = io::read_gpu_cube(b.specular_file, &b.specular_format, &kv);
      b.diffuse = DiffuseSource::FilamentSh;
      b.diffuse_file = b.specular_file + " (sh key)";
      b.sh = filament_sh(kv, b.specular_file);
      break;
    case EngineTarget::KhronosViewer:
      b.specular_file = engine_file(manifest, folder, "_ggx.ktx2");
      b.specular = io::read_gpu_cube(b.specular_file, &b.specular_format);
      b.diffuse = DiffuseSource::IrradianceCube;
      b.diffuse_file = engine_file(manifest, folder, "_lambertian.ktx2");
      b.irradiance = io::read_gpu_cube(b.diffuse_file);
      break;
    case EngineTarget::Babylon:
      read_babylon_lighting(manifest, b);
      break;
    case EngineTarget::Gltf:
      read_gltf_lighting(manifest, b);
      break;
  }
  if (b.specular.levels.empty()) throw Error("'" + b.specular_file + "': no levels");
}

// KHR_materials_sheen: the charlie table (the Estevez & Kulla one first: the extension's) and the
// Charlie chain the target's shader samples, when the bake holds them
void read_sheen(const json& manifest, BakeFiles& b) {
  const std::string& folder = b.folder;
  const json* charlie = nullptr;
  if (manifest.contains("files"))
    for (const auto& f : manifest["files"])
      if (f.value("kind", std::string()) == "charlie" &&
          (!charlie ||
           (f.contains("parameters") && f["parameters"].value("sheen_visibility", std::string()) == "estevez-kulla")))
        charlie = &f;
  if (charlie) {
    b.charlie_file = join_path(folder, (*charlie)["path"].get<std::string>());
    b.charlie = io::read_table(b.charlie_file);
    if (charlie->contains("parameters") &&
        (*charlie)["parameters"].value("n_dot_v_axis", std::string("uniform")) == "sqrt")
      b.charlie_sqrt_n_dot_v = true;
    if (charlie->contains("parameters"))
      b.charlie_visibility = (*charlie)["parameters"].value("sheen_visibility", std::string());
  }
  if (b.target == EngineTarget::Generic) {
    if (const json* chain = manifest_file(manifest, "prefilter", "charlie")) {
      b.sheen_file = join_path(folder, (*chain)["path"].get<std::string>());
      b.sheen = io::read_gpu_cube(b.sheen_file);
    }
  } else if (b.target == EngineTarget::KhronosViewer) {
    if (manifest.contains("engine") && manifest["engine"].contains("files"))
      for (const auto& f : manifest["engine"]["files"])
        if (f.is_string() && ends_with(f.get<std::string>(), "_charlie.ktx2")) {
          b.sheen_file = join_path(folder, f.get<std::string>());
          b.sheen = io::read_gpu_cube(b.sheen_file);
        }
  }
}

// The settings the preview reports: which files, their sizes and layouts.
void list_settings(BakeFiles& b) {
  b.settings = {{"folder", b.folder},
                {"target", engine_target_name(b.target)},
                {"specular", b.specular_file},
                {"specular_format", b.specular_format},
                {"specular_size", std::to_string(b.specular.size)},
                {"specular_levels", std::to_string(b.specular.level_count())},
                {"dfg", b.dfg_file},
                {"dfg_size", std::to_string(b.dfg.width) + "x" + std::to_string(b.dfg.height)},
                {"dfg_channels", b.dfg_multiscatter ? "bias,albedo" : "scale,bias"},
                {"diffuse", b.diffuse_file}};
  if (!b.sheen.levels.empty()) {
    b.settings.push_back({"sheen", b.sheen_file});
    b.settings.push_back({"sheen_levels", std::to_string(b.sheen.level_count())});
  }
  if (b.charlie.width > 0) {
    b.settings.push_back({"charlie", b.charlie_file});
    b.settings.push_back({"charlie_size", std::to_string(b.charlie.width) + "x" + std::to_string(b.charlie.height)});
  }
}

}  // namespace

BakeFiles read_bake_files(const std::string& folder, EngineTarget target, const std::string& environment) {
  BakeFiles b;
  b.target = target;
  b.folder = folder;
  const json manifest = read_manifest(folder, target, environment);
  read_dfg(manifest, b);
  read_lighting(manifest, b);
  read_sheen(manifest, b);
  list_settings(b);
  return b;
}

}  // namespace brdfbake::detail::preview
