// Jobs: parsing, validation and the job as JSON. Every error names the document and the field. The
// tables' own parameters are checked by the family registry (brdfbake/tables.hpp) from each kind's
// schema; this file knows only the fields every job and every table share.
#include "brdfbake/job.hpp"

#include <algorithm>
#include <filesystem>
#include <map>

#include "brdfbake/engines.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/output_checks.hpp"
#include "engines/babylon_frame.hpp"
#include "families/preview/bake_preview.hpp"
#include "io/json_input.hpp"
#include "job/job_json.hpp"
#include "text.hpp"

namespace brdfbake {

namespace {

using json = nlohmann::ordered_json;
namespace fs = std::filesystem;
using io::json_excerpt;

using detail::join;

// A JSON value as a parameter value (numbers, strings, booleans, arrays of numbers).
ParamValue to_param(const json& v, const std::string& where) {
  if (v.is_boolean()) return v.get<bool>();
  if (v.is_number()) return v.get<double>();
  if (v.is_string()) return v.get<std::string>();
  if (v.is_array()) {
    std::vector<double> out;
    for (const auto& e : v) {
      if (!e.is_number())
        throw Error(where + ": must be a number or an array of numbers (got " + json_excerpt(v) + ")");
      out.push_back(e.get<double>());
    }
    return out;
  }
  throw Error(where + ": must be a number, a string, a boolean or an array of numbers (got " + json_excerpt(v) + ")");
}

std::string get_string(const json& v, const std::string& field) {
  if (!v.is_string()) throw Error(field + ": must be a string (got " + json_excerpt(v) + ")");
  return v.get<std::string>();
}

std::vector<std::string> get_strings(const json& v, const std::string& field) {
  std::vector<std::string> out;
  if (!v.is_array()) throw Error(field + ": must be an array of strings (got " + json_excerpt(v) + ")");
  for (const auto& e : v) {
    if (!e.is_string()) throw Error(field + ": must be an array of strings");
    out.push_back(e.get<std::string>());
  }
  return out;
}

std::string kind_names() {
  std::vector<std::string> names;
  for (TableKind k : table_kinds()) names.push_back(table_kind_name(k));
  return join(names);
}

TableRequest parse_table(const json& o, const std::string& where, bool* precision_given) {
  if (!o.is_object()) throw Error(where + ": must be an object (got " + json_excerpt(o) + ")");
  TableRequest t;
  if (!o.contains("kind")) throw Error(where + ".kind: missing (one of " + kind_names() + ")");
  try {
    t.kind = table_kind_from_name(get_string(o["kind"], where + ".kind"));
  } catch (const Error& e) {
    if (std::string(e.what()).rfind(where, 0) == 0) throw;
    throw Error(where + ".kind: " + e.what());
  }
  const auto& schema = table_schema(t.kind);
  for (auto it = o.begin(); it != o.end(); ++it) {
    const std::string& key = it.key();
    const std::string field = where + "." + key;
    if (key == "kind") continue;
    if (key == "output") {
      t.output = get_string(*it, field);
      if (t.output.empty()) throw Error(field + ": must not be empty (leave it out for the default name)");
    } else if (key == "format")
      t.format = get_string(*it, field);
    else if (key == "pixel")
      t.pixel = get_string(*it, field);
    else if (key == "device")
      t.device = get_string(*it, field);
    else if (key == "environment")
      t.environment = get_string(*it, field);
    else if (key == "precision") {
      try {
        t.precision = precision_from_name(get_string(*it, field));
      } catch (const Error& e) {
        if (std::string(e.what()).rfind(where, 0) == 0) throw;
        throw Error(field + ": " + e.what());
      }
      *precision_given = true;
    } else if (key == "materials" && !(it->is_string() && find_param_def_or_alias(schema, key))) {
      // informative: derived from requested_by (a string is the preview's material file by its old
      // name, an alias of `material`)
      get_strings(*it, field);
    } else if (key == "requested_by") {
      if (!it->is_array()) throw Error(field + ": must be an array of {rule, purpose, materials, note}");
      for (size_t i = 0; i < it->size(); ++i) {
        const json& r = (*it)[i];
        const std::string rw = field + "[" + std::to_string(i) + "]";
        if (!r.is_object()) throw Error(rw + ": must be an object");
        Request q;
        for (auto f = r.begin(); f != r.end(); ++f) {
          if (f.key() == "rule")
            q.rule = get_string(*f, rw + ".rule");
          else if (f.key() == "purpose")
            q.purpose = get_string(*f, rw + ".purpose");
          else if (f.key() == "note")
            q.note = get_string(*f, rw + ".note");
          else if (f.key() == "materials")
            q.materials = get_strings(*f, rw + ".materials");
          else
            throw Error(rw + "." + f.key().substr(0, 60) + ": unknown field (expected rule, purpose, materials, note)");
        }
        t.requested_by.push_back(q);
      }
    } else if (find_param_def_or_alias(schema, key)) {
      t.params.push_back({key, to_param(*it, field)});  // an alias: renamed below
    } else {
      std::vector<std::string> names = table_common_fields();
      for (const auto& d : schema) names.push_back(d.name);
      throw Error(where + "." + key.substr(0, 60) + ": unknown field for kind '" + table_kind_name(t.kind) +
                  "' (expected " + join(names) + ")");
    }
  }
  canonicalize_params(t.params, schema, where + ".", false);
  return t;
}

// A path a job writes: relative to the output folder and inside it.
void check_job_path(const std::string& path, const std::string& field) {
  const fs::path p(path);
  if (path.empty()) throw Error(field + ": must not be empty");
  if (path.find('\0') != std::string::npos) throw Error(field + ": must not contain a NUL character");
  if (p.is_absolute()) throw Error(field + ": '" + path + "' must be relative to the output folder");
  for (const auto& part : p)
    if (part == "..") throw Error(field + ": '" + path + "' must stay inside the output folder (no '..')");
  if (p.lexically_normal() == "manifest.json") throw Error(field + ": 'manifest.json' is the job's manifest");
}

}  // namespace

// ---- Validation ----------------------------------------------------------------------------------

void validate_job(Job& job) {
  const std::string origin = job.source.empty() ? std::string("job") : job.source;
  if (job.environment.empty()) throw Error(origin + ": environment: must not be empty");
  try {  // a builtin's name is known now: a server refuses the job (400) instead of failing it later
    check_builtin_environment(job.environment);
    for (const auto& t : job.tables) check_builtin_environment(t.environment);
  } catch (const Error& e) {
    throw Error(origin + ": environment: " + e.what());
  }
  for (size_t i = 0; i < job.tables.size(); ++i) {
    TableRequest& t = job.tables[i];
    const std::string where = origin + ": tables[" + std::to_string(i) + "]";
    if (!t.output.empty()) check_job_path(t.output, where + ".output");
    FieldNaming naming;
    naming.prefix = where;
    validate_table(t, naming);
    check_job_path(t.output, where + ".output");
    // ASTC HDR chains: the engines that load KTX2 (an engine target's files hold the job's chain)
    if ((t.pixel == "astc4x4" || t.pixel == "astc6x6") && job.target != "generic" && job.target != "khronos-viewer")
      throw Error(where + ".pixel: " + t.pixel + ": the target " + job.target +
                  " cannot load ASTC (generic and khronos-viewer can; give f16 or f32)");
    // Every other file a table writes (e.g. irradiance's sh_json) stays inside the folder too.
    for (const auto& d : table_schema(t.kind))
      if (d.type == ParamType::Path && d.output_only && t.find(d.name))
        check_job_path(t.text(d.name), where + "." + d.name);
      else if (d.type == ParamType::Path && t.text(d.name) == "-")
        throw Error(where + "." + d.name + ": '-' (standard input) is for the command line; name a file");
  }
  // Identical requests merge; two different tables may not share an output.
  std::vector<TableRequest> merged;
  std::map<std::string, size_t> by_output;
  for (size_t i = 0; i < job.tables.size(); ++i) {
    TableRequest& t = job.tables[i];
    const std::string out = fs::path(t.output).lexically_normal().string();
    auto it = by_output.find(out);
    if (it == by_output.end()) {
      by_output[out] = merged.size();
      merged.push_back(t);
      continue;
    }
    TableRequest& first = merged[it->second];
    if (table_bake_key(first) != table_bake_key(t) || first.format != t.format || first.pixel != t.pixel) {
      size_t first_index = 0;
      for (size_t k = 0; k < i; ++k)
        if (fs::path(job.tables[k].output).lexically_normal().string() == out) {
          first_index = k;
          break;
        }
      throw Error(origin + ": tables[" + std::to_string(i) + "].output: '" + t.output +
                  "' is also the output of tables[" + std::to_string(first_index) + "], a different table");
    }
    for (const auto& r : t.requested_by) first.requested_by.push_back(r);
  }
  job.tables = std::move(merged);
  // Across fields and tables: a table's sh_json on another's output, an output inside another's
  // folder output or under another's file (brdfbake/output_checks.hpp).
  check_job_output_set(job, false);
  // bake --preview: what the preview needs of the job (a chain, SH, an OpenCL device), refused before
  // anything runs, from the command line, a job file and POST /v1/bake alike
  if (job.preview) detail::preview::check_bake_preview(job);
}

// ---- Parsing -------------------------------------------------------------------------------------

Job parse_job(const std::string& text, const std::string& origin) {
  const json root = io::parse_json(text, origin);
  if (!root.is_object()) throw Error(origin + ": a job is a JSON object with a \"tables\" array");
  Job job;
  job.source = origin;
  for (auto it = root.begin(); it != root.end(); ++it) {
    const std::string& key = it.key();
    const std::string field = origin + ": " + key;
    if (key == "brdfbake_job") {
      if (!it->is_number_integer() || it->get<long long>() != 1)
        throw Error(field + ": must be 1 (the job format's version; got " + json_excerpt(*it) + ")");
    } else if (key == "output_dir") {
      job.output_dir = get_string(*it, field);
    } else if (key == "environment") {
      if (!it->is_string()) throw Error(field + ": must be a string (FILE or builtin:NAME)");
      job.environment = it->get<std::string>();
    } else if (key == "target") {
      job.target = get_string(*it, field);
      try {
        engine_target_from_name(job.target);
      } catch (const Error& e) {
        throw Error(field + ": " + e.what());
      }
    } else if (key == "engine_name") {
      job.engine_name = get_string(*it, field);
      if (job.engine_name.empty() || job.engine_name == "." || job.engine_name == ".." ||
          job.engine_name.find_first_of("/\\") != std::string::npos)
        throw Error(field + ": must be a file name without a folder (got '" + job.engine_name + "')");
    } else if (key == "gltf_scene") {
      job.gltf_scene = get_string(*it, field);
      detail::parse_gltf_scene(job.gltf_scene, field);
    } else if (key == "sanitize") {
      if (!it->is_boolean()) throw Error(field + ": must be true or false (got " + json_excerpt(*it) + ")");
      job.sanitize = it->get<bool>();
    } else if (key == "preview") {
      if (!it->is_boolean()) throw Error(field + ": must be true or false (got " + json_excerpt(*it) + ")");
      job.preview = it->get<bool>();
    } else if (key == "device") {
      job.device = get_string(*it, field);
    } else if (key == "precision") {
      if (!it->is_string()) throw Error(field + ": must be a string (fp32 or fp64)");
      try {
        job.precision = precision_from_name(it->get<std::string>());
      } catch (const Error& e) {
        throw Error(field + ": " + e.what());
      }
    } else if (key == "scene") {
      job.scene = get_string(*it, field);
    } else if (key == "notes" || key == "warnings") {
      (key == "notes" ? job.notes : job.warnings) = get_strings(*it, field);
    } else if (key == "plan") {
      if (!it->is_object()) throw Error(field + ": must be an object");  // informative (bake --dry-run --json)
    } else if (key == "tables") {
      if (!it->is_array()) throw Error(field + ": must be an array of tables (got " + json_excerpt(*it) + ")");
    } else {
      throw Error(
          origin + ": " + key.substr(0, 60) +
          ": unknown field (expected brdfbake_job, output_dir, environment, sanitize, preview, target, engine_name, "
          "gltf_scene, device, precision, tables, scene, notes, warnings, plan)");
    }
  }
  if (!root.contains("tables")) throw Error(origin + ": tables: missing (the list of tables to bake)");
  const json& tables = root["tables"];
  for (size_t i = 0; i < tables.size(); ++i) {
    bool precision_given = false;
    TableRequest t = parse_table(tables[i], origin + ": tables[" + std::to_string(i) + "]", &precision_given);
    if (!precision_given) t.precision = job.precision;
    job.tables.push_back(std::move(t));
  }
  validate_job(job);
  return job;
}

Job read_job(const std::string& path) { return parse_job(io::read_text_file(path, "job"), path); }

// ---- JSON ----------------------------------------------------------------------------------------

namespace detail {

json param_json(const ParamDef* d, const ParamValue& v) {
  if (auto b = std::get_if<bool>(&v)) return *b;
  if (auto x = std::get_if<double>(&v)) {
    if (d && (d->type == ParamType::Int || d->type == ParamType::IntList)) return static_cast<long long>(*x);
    return *x;
  }
  if (auto s = std::get_if<std::string>(&v)) return *s;
  const auto& a = std::get<std::vector<double>>(v);
  if (d && d->type == ParamType::IntList) {
    json out = json::array();
    for (double x : a) out.push_back(static_cast<long long>(x));
    return out;
  }
  return a;
}

json params_json(TableKind kind, const Params& params) {
  json o = json::object();
  for (const auto& p : params) o[p.name] = param_json(find_param_def(table_schema(kind), p.name), p.value);
  return o;
}

json requests_json(const std::vector<Request>& reqs) {
  json a = json::array();
  for (const auto& r : reqs) {
    json o;
    o["rule"] = r.rule;
    o["purpose"] = r.purpose;
    o["materials"] = r.materials;
    if (!r.note.empty()) o["note"] = r.note;
    a.push_back(o);
  }
  return a;
}

json table_json(const TableRequest& t, const Job& job) {
  json o;
  o["kind"] = table_kind_name(t.kind);
  const json params = params_json(t.kind, t.params);
  for (auto it = params.begin(); it != params.end(); ++it) o[it.key()] = *it;
  if (t.precision != job.precision) o["precision"] = precision_name(t.precision);
  if (!t.device.empty()) o["device"] = t.device;
  if (!t.environment.empty()) o["environment"] = t.environment;
  o["output"] = t.output;
  if (!t.format.empty()) o["format"] = t.format;
  if (!t.pixel.empty() && t.pixel != table_kind_default_pixel(t.kind)) o["pixel"] = t.pixel;
  if (!t.requested_by.empty()) {
    o["requested_by"] = requests_json(t.requested_by);
    if (!find_param_def(table_schema(t.kind), "materials")) o["materials"] = t.materials();
  }
  return o;
}

json job_json(const Job& job) {
  json o;
  o["brdfbake_job"] = 1;
  if (!job.output_dir.empty()) o["output_dir"] = job.output_dir;
  if (!job.scene.empty()) o["scene"] = job.scene;
  o["environment"] = job.environment;
  if (job.sanitize) o["sanitize"] = true;
  if (job.preview) o["preview"] = true;
  if (job.target != "generic") o["target"] = job.target;
  if (!job.engine_name.empty()) o["engine_name"] = job.engine_name;
  if (job.gltf_scene != "left-handed") o["gltf_scene"] = job.gltf_scene;
  o["device"] = job.device;
  o["precision"] = precision_name(job.precision);
  json tables = json::array();
  for (const auto& t : job.tables) tables.push_back(table_json(t, job));
  o["tables"] = tables;
  if (!job.notes.empty()) o["notes"] = job.notes;
  if (!job.warnings.empty()) o["warnings"] = job.warnings;
  return o;
}

}  // namespace detail

std::string job_to_json(const Job& job) { return io::json_text(detail::job_json(job)) + "\n"; }

}  // namespace brdfbake
