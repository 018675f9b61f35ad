// Internal: the JSON forms shared by jobs, plans and manifests.
#pragma once

#include <nlohmann/json.hpp>

#include "brdfbake/job.hpp"

namespace brdfbake::detail {

nlohmann::ordered_json param_json(const ParamDef* def, const ParamValue& value);
nlohmann::ordered_json params_json(TableKind kind, const Params& params);
nlohmann::ordered_json requests_json(const std::vector<Request>& requests);
nlohmann::ordered_json job_json(const Job& job);

}  // namespace brdfbake::detail
