// manifest.json: what a run wrote, file by file.
#include "brdfbake/manifest.hpp"

#include "brdfbake/error_figures.hpp"
#include "brdfbake/version.hpp"
#include "io/json_input.hpp"
#include "job/job_json.hpp"

namespace brdfbake {

namespace detail {

nlohmann::ordered_json engine_entry_json(const EngineFileEntry& f) {
  nlohmann::ordered_json e;
  e["path"] = f.path;
  e["bytes"] = f.bytes;
  e["format"] = f.format;
  if (!f.measured) {
    e["error_rms_rel"] = nullptr;
    e["error_max_rel"] = nullptr;
    e["values"] = "none (text: no texel values)";
    return e;
  }
  e["values"] = f.values;
  e["error_rms_rel"] = f.error_rms_rel;
  e["error_max_rel"] = f.error_max_rel;
  e["error_rms_rel_per_level"] = f.error_rms_rel_per_level;
  e["error_max_rel_per_level"] = f.error_max_rel_per_level;
  return e;
}

std::vector<EngineFileEntry> engine_entries_from_json(const nlohmann::ordered_json& engine) {
  std::vector<EngineFileEntry> out;
  if (!engine.contains("file_entries") || !engine["file_entries"].is_array()) return out;
  for (const auto& j : engine["file_entries"]) {
    if (!j.is_object()) continue;
    EngineFileEntry f;
    f.path = j.value("path", "");
    f.bytes = j.value("bytes", std::uint64_t(0));
    f.format = j.value("format", "");
    f.values = j.value("values", "");
    f.measured = j.contains("error_rms_rel") && j["error_rms_rel"].is_number();
    if (f.measured) {
      f.error_rms_rel = j["error_rms_rel"].get<double>();
      f.error_max_rel = j.value("error_max_rel", 0.0);
      for (const char* key : {"error_rms_rel_per_level", "error_max_rel_per_level"})
        if (j.contains(key) && j[key].is_array())
          for (const auto& v : j[key])
            if (v.is_number())
              (std::string(key) == "error_rms_rel_per_level" ? f.error_rms_rel_per_level : f.error_max_rel_per_level)
                  .push_back(v.get<double>());
    }
    out.push_back(std::move(f));
  }
  return out;
}

}  // namespace detail

std::string manifest_to_json(const Manifest& m) {
  using json = nlohmann::ordered_json;
  json o;
  o["generator"] = std::string("brdfbake ") + kVersion;
  o["job"] = m.job_source;
  if (!m.scene.empty()) o["scene"] = m.scene;
  o["bakes"] = m.bakes;
  o["seconds"] = m.seconds;
  json files = json::array();
  for (const auto& f : m.files) {
    json e;
    e["path"] = f.path;
    e["kind"] = table_kind_name(f.kind);
    e["parameters"] = detail::params_json(f.kind, f.params);
    e["precision"] = precision_name(f.precision);
    e["device"] = f.device;
    if (!f.environment.empty()) e["environment"] = f.environment;
    // The error figure under its kind's name (docs/CONVENTIONS.md, "Error figures"); older
    // manifests wrote every kind's as error_bound (readers accept both)
    const ErrorFigure& figure = error_figure(f.kind);
    e["error_name"] = figure.name;
    if (f.error_bound)
      e[figure.name] = *f.error_bound;
    else
      e[figure.name] = nullptr;
    e["error_definition"] = figure.definition;
    e["error_measurement"] = f.error_bound_definition;
    for (const auto& [k, v] : f.details) e[k] = v;
    e["materials"] = f.materials;
    e["requested_by"] = detail::requests_json(f.requested_by);
    e["bytes"] = f.bytes;
    e["bake"] = f.bake;
    e["seconds"] = f.seconds;
    files.push_back(e);
  }
  o["files"] = files;
  if (!m.target.empty()) {
    nlohmann::ordered_json e;
    e["target"] = m.target;
    e["files"] = m.engine_files;
    nlohmann::ordered_json d = nlohmann::ordered_json::object();
    for (const auto& [k, v] : m.engine_delivered) d[k] = v;
    e["delivered"] = d;
    // Each file with its size and delivered error (docs/CONVENTIONS.md, "Error figures")
    json entries = json::array();
    for (const EngineFileEntry& f : m.engine_entries) entries.push_back(detail::engine_entry_json(f));
    e["file_entries"] = entries;
    e["error_rms_rel_definition"] = kEngineErrorRmsRelDefinition;
    e["error_max_rel_definition"] = kEngineErrorMaxRelDefinition;
    o["engine"] = e;
  }
  if (!m.preview_files.empty()) {
    nlohmann::ordered_json e;
    e["files"] = m.preview_files;
    for (const auto& [k, v] : m.preview) e[k] = v;
    o["preview"] = e;
  }
  if (!m.notes.empty()) o["notes"] = m.notes;
  if (!m.warnings.empty()) o["warnings"] = m.warnings;
  return io::json_text(o) + "\n";
}

}  // namespace brdfbake
