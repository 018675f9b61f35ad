// The options of a scene bake, read once for every front end (brdfbake/plan.hpp): `brdfbake bake`,
// POST /v1/bake and brdfbake.bake_scene give them as typed values and name them in messages as
// their users spell them.
#include <set>

#include "brdfbake/plan.hpp"

namespace brdfbake {

namespace {

std::string join_names(const std::vector<ParamDef>& schema) {
  std::string s;
  for (const auto& d : schema) s += (s.empty() ? "" : ", ") + d.name;
  return s;
}

int integer(const ParamValue& v) { return static_cast<int>(std::get<double>(v)); }

// Sets the plan option `name` (a field of plan_schema, already checked).
void set_plan_option(PlanOptions& o, const std::string& name, const ParamValue& v) {
  if (name == "energy_compensation")
    o.energy_compensation = std::get<bool>(v);
  else if (name == "lut_size")
    o.lut_size = integer(v);
  else if (name == "chain_size")
    o.chain_size = integer(v);
  else if (name == "min_size")
    o.cube_min_size = integer(v);
  else if (name == "schedule")
    o.schedule = std::get<std::string>(v);
  else if (name == "chain_max_error")
    o.chain_max_error = std::get<double>(v);
  else if (name == "fresnel_size")
    o.fresnel_size = integer(v);
  else if (name == "thin_film_size")
    o.thin_film_size = integer(v);
  else if (name == "sh_order")
    o.sh_order = integer(v);
  else if (name == "sh_window")
    o.sh_window = std::get<std::string>(v);
  else if (name == "engine_name")
    o.engine_name = std::get<std::string>(v);
  else if (name == "sheen_visibility")
    o.sheen_visibility = std::get<std::string>(v);
  else if (name == "table_format")
    o.table_format = std::get<std::string>(v);
  else if (name == "target")
    o.target = std::get<std::string>(v);
  else if (name == "cube_format")
    o.cube_format = std::get<std::string>(v);
  else if (name == "clamp_f16")
    o.clamp_f16 = std::get<bool>(v);
}

}  // namespace

const std::vector<ParamDef>& bake_option_schema() {
  static const std::vector<ParamDef> s = [] {
    using T = ParamType;
    std::vector<ParamDef> out = plan_schema();
    out.push_back(ParamDef("scene", T::Path,
                           "FILE.gltf, FILE.glb or FILE.json (glTF JSON); none: the standard metallic-roughness set"));
    out.push_back(
        ParamDef("environment", T::Path, "environment: FILE (.hdr .exr .ktx2) or builtin:studio / builtin:sun")
            .def(std::string(kDefaultEnvironment))
            .alias("env"));
    out.push_back(ParamDef("sanitize", T::Flag,
                           "replace NaN, infinite and negative environment pixels instead of refusing the input")
                      .def(false));
    out.push_back(ParamDef("pixel", T::Name,
                           "the texels of .ktx2, .h and cube containers (default: each kind's); astc4x4 | astc6x6: "
                           "the prefiltered chains as ASTC HDR KTX2 (targets generic, khronos-viewer)")
                      .one_of({"f16", "f32", "astc4x4", "astc6x6"}));
    out.push_back(ParamDef("preview", T::Flag,
                           "also render the target's preview of the files: preview.png, preview_splitsum.exr, "
                           "preview_reference.exr, preview.json (docs/PREVIEW.md)")
                      .def(false));
    out.push_back(ParamDef("precision", T::Name, "the precision of the kernels")
                      .one_of({"fp32", "fp64"})
                      .def(std::string("fp32")));
    out.push_back(ParamDef("device", T::Name, "the device selector, or reference"));
    return out;
  }();
  return s;
}

std::string OptionNaming::field(const ParamDef& d) const {
  if (cli) return "--" + d.cli_name();
  if (prefix.empty()) return d.name;
  return prefix + (dotted ? "." : ": ") + d.name;
}

BakeOptions parse_bake_options(const Params& given, const OptionNaming& naming) {
  const auto& schema = bake_option_schema();
  BakeOptions out;
  PlanOptions& o = out.plan;
  std::set<std::string> seen;
  // Old and short spellings (aliases: cube_size for chain_size) to the schema's names.
  Params canonical = given;
  canonicalize_params(canonical, schema,
                      naming.cli || naming.prefix.empty() ? "" : naming.prefix + (naming.dotted ? "." : ": "),
                      naming.cli);
  for (const Param& p : canonical) {
    const ParamDef* d = find_param_def(schema, p.name);
    if (!d)
      throw Error((naming.prefix.empty() ? std::string() : naming.prefix + ": ") + p.name.substr(0, 60) + ": " +
                  naming.unknown + " (expected " + join_names(schema) + ")");
    const std::string field = naming.field(*d);
    if (!seen.insert(p.name).second) throw Error(field + ": given twice");
    if (const std::string* text = std::get_if<std::string>(&p.value);
        text && text->empty() && d->type == ParamType::Path)
      throw Error(field + ": must not be empty");
    check_param(*d, p.value, field);
    if (p.name == "scene")
      out.scene = std::get<std::string>(p.value);
    else if (p.name == "environment")
      o.environment = std::get<std::string>(p.value);
    else if (p.name == "sanitize")
      o.sanitize = std::get<bool>(p.value);
    else if (p.name == "pixel")
      o.pixel = std::get<std::string>(p.value);
    else if (p.name == "preview")
      out.preview = std::get<bool>(p.value);
    else if (p.name == "precision")
      o.precision = precision_from_name(std::get<std::string>(p.value));
    else if (p.name == "device")
      o.device = std::get<std::string>(p.value);
    else
      set_plan_option(o, p.name, p.value);
  }
  // The rules across options.
  const auto named = [&](const char* name) { return naming.field(*find_param_def(schema, name)); };
  if (!o.engine_name.empty() &&
      (o.engine_name.size() > 100 || o.engine_name[0] == '.' ||
       o.engine_name.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789._-") !=
           std::string::npos))
    throw Error(named("engine_name") + ": '" + o.engine_name.substr(0, 60) +
                "' must be a file name of letters, digits, '.', '_' and '-' (at most 100, not starting with '.')");
  if (o.sh_order && *o.sh_order != 3 && *o.sh_order != 5)
    throw Error(named("sh_order") + ": must be 3 or 5 (got " + std::to_string(*o.sh_order) + ")");
  if ((o.pixel == "astc4x4" || o.pixel == "astc6x6") && o.target != "generic" && o.target != "khronos-viewer")
    throw Error(named("pixel") + ": " + o.pixel + ": the target " + o.target +
                " cannot load ASTC (generic and khronos-viewer can; give f16 or f32)");
  const int size = o.chain_size.value_or(
      static_cast<int>(std::get<double>(*find_param_def(table_schema(TableKind::Prefilter), "chain_size")->fallback)));
  if (o.cube_min_size && *o.cube_min_size > size)
    throw Error(named("min_size") + ": must be at most " + named("chain_size") + " (got " +
                std::to_string(*o.cube_min_size) + " > " + std::to_string(size) + ")");
  return out;
}

Plan plan_bake(const BakeOptions& options) {
  Plan plan = options.scene.empty() ? plan_default(options.plan) : plan_scene(read_scene(options.scene), options.plan);
  plan.job.preview = options.preview;
  return plan;
}

}  // namespace brdfbake
