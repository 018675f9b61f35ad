// manifest.json: what a run wrote, file by file.
#include "brdfbake/manifest.hpp"

#include "brdfbake/version.hpp"
#include "io/json_input.hpp"
#include "job/job_json.hpp"

namespace brdfbake {

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
    if (f.error_bound)
      e["error_bound"] = *f.error_bound;
    else
      e["error_bound"] = nullptr;
    e["error_bound_definition"] = f.error_bound_definition;
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
