// A bake's files as a target engine loads them (bake_files.hpp).
#include "families/preview/bake_files.hpp"

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

#include "brdfbake/error.hpp"
#include "engines/bake_read.hpp"
#include "engines/registry.hpp"
#include "io/json_input.hpp"
#include "io/table_read.hpp"

namespace brdfbake::detail::preview {

namespace {

namespace fs = std::filesystem;
using bake_read::Field;
using json = nlohmann::ordered_json;

// The manifest of a bake folder, checked to be of this target and (when given) of this environment.
void check_manifest(const Field& manifest, const std::string& folder, EngineTarget target,
                    const std::string& environment) {
  std::string baked_for = "generic";
  if (const std::optional<Field> engine = manifest.find("engine"))
    if (const std::optional<Field> t = engine->find("target")) baked_for = t->string();
  if (baked_for != engine_target_name(target))
    throw Error("'" + folder + "' was baked for target " + baked_for + ", not " + engine_target_name(target) +
                ": give --target " + baked_for + ", or bake again with --target " + engine_target_name(target));

  // The chain must be of this environment: the reference integrates it.
  if (!environment.empty())
    if (const std::optional<Field> chain = bake_read::manifest_entry(manifest, "prefilter"))
      if (const std::optional<Field> source = chain->find("environment")) {
        const std::string baked = source->string();
        std::error_code e1, e2;
        const bool same = baked == environment || (fs::exists(baked, e1) && fs::exists(environment, e2) &&
                                                   fs::equivalent(baked, environment, e1));
        if (!same)
          throw Error("'" + folder + "' was baked from '" + baked + "', not from '" + environment +
                      "': give the environment of the bake (--env), or bake again");
      }
}

// The DFG table: ggx-multiscatter, or ggx (scale, bias); or the one built into the engine
// (engines/registry.hpp, engine_dfg), which never reads the bake's.
void read_dfg(const Field& manifest, BakeFiles& b, const engines::TargetDef& def) {
  if (def.engine_dfg) {
    def.engine_dfg(b);
    return;
  }
  std::optional<Field> dfg = bake_read::manifest_entry(manifest, "ggx-multiscatter");
  if (!dfg) {
    dfg = bake_read::manifest_entry(manifest, "ggx");
    b.dfg_multiscatter = false;
  }
  if (!dfg) throw Error("'" + b.folder + "': the bake has no GGX DFG table");
  b.dfg_file = bake_read::entry_file(*dfg, b.folder);
  b.dfg = io::read_table(b.dfg_file);
  if (b.dfg.channel_count() < 2) throw Error("'" + b.dfg_file + "': a DFG table has at least 2 channels");
  bake_read::check_table(b.dfg, b.dfg_file, 2);
  if (const std::optional<Field> p = dfg->find("parameters"))
    if (p->string_or("n_dot_v_axis", "uniform") == "sqrt") b.dfg_sqrt_n_dot_v = true;
}

// KHR_materials_sheen: the charlie table (the Estevez & Kulla one first: the extension's) and the
// Charlie chain the target's shader samples, when the bake holds them
void read_sheen(const Field& manifest, BakeFiles& b, const engines::TargetDef& def) {
  std::optional<Field> charlie;
  if (const std::optional<Field> files = manifest.find("files"))
    for (const Field& f : files->elements()) {
      if (f.at("kind").string() != "charlie") continue;
      const std::optional<Field> p = f.find("parameters");
      if (!charlie || (p && p->string_or("sheen_visibility", "") == "estevez-kulla")) charlie = f;
    }
  if (charlie) {
    b.charlie_file = bake_read::entry_file(*charlie, b.folder);
    b.charlie = io::read_table(b.charlie_file);
    bake_read::check_table(b.charlie, b.charlie_file, 1);
    if (const std::optional<Field> p = charlie->find("parameters")) {
      if (p->string_or("n_dot_v_axis", "uniform") == "sqrt") b.charlie_sqrt_n_dot_v = true;
      b.charlie_visibility = p->string_or("sheen_visibility", "");
    }
  }
  if (def.read_sheen_chain) def.read_sheen_chain(manifest, b);
  if (!b.sheen.levels.empty()) bake_read::check_cube(b.sheen, b.sheen_file);
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
                {"diffuse", b.diffuse == DiffuseSource::None
                                ? std::string("none: the bake holds no irradiance (its scene has no diffuse lobe)")
                                : b.diffuse_file}};
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
  const std::string manifest_path = bake_read::join_path(folder, "manifest.json");
  std::error_code ec;
  if (!fs::is_regular_file(manifest_path, ec))
    throw Error("'" + folder + "' holds no manifest.json: give the output folder of brdfbake bake --target " +
                engine_target_name(target));
  const json document = io::parse_json(io::read_text_file(manifest_path, "manifest"), manifest_path);
  const Field manifest(document, manifest_path);
  if (!manifest.is_object()) manifest.fail("expected an object");
  const engines::TargetDef& def = engines::target_def(target);
  check_manifest(manifest, folder, target, environment);
  read_dfg(manifest, b, def);
  def.read(manifest, b);  // the target's reader (engines/<target>/reader.cpp)
  bake_read::check_cube(b.specular, b.specular_file);
  if (!b.irradiance.levels.empty()) bake_read::check_cube(b.irradiance, b.diffuse_file);
  read_sheen(manifest, b, def);
  list_settings(b);
  return b;
}

}  // namespace brdfbake::detail::preview
