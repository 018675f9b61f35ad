// Internal: the JSON forms shared by jobs, plans and manifests.
#pragma once

#include <nlohmann/json.hpp>

#include "brdfbake/engines.hpp"
#include "brdfbake/job.hpp"

namespace brdfbake::detail {

nlohmann::ordered_json param_json(const ParamDef* def, const ParamValue& value);
nlohmann::ordered_json params_json(TableKind kind, const Params& params);
nlohmann::ordered_json requests_json(const std::vector<Request>& requests);
nlohmann::ordered_json job_json(const Job& job);
// A manifest's engine file entry (manifest.cpp), and the entries of its "engine" member read back.
nlohmann::ordered_json engine_entry_json(const EngineFileEntry& f);
std::vector<EngineFileEntry> engine_entries_from_json(const nlohmann::ordered_json& engine);

}  // namespace brdfbake::detail
