// The error figure each table kind records, by a name that says what it is, with one definition a
// kind (docs/CONVENTIONS.md, "Error figures"): the manifest, the files' metadata (KTX2 key/values
// brdfbake:NAME, EXR and JSON metadata), the summary lines and the web page use these names. Older
// bake folders and files wrote every kind's figure as `error_bound`; readers still accept it
// (error_figure_value).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "brdfbake/tables.hpp"

namespace brdfbake {

struct ErrorFigure {
  const char* name;        // error_bound_mixed | error_bound_rel | error_rms_rel | error_rms_rel_bound
  const char* definition;  // what the number bounds or measures, in one sentence
};

// The figure of a kind's outputs.
const ErrorFigure& error_figure(TableKind kind);
// Every name error_figure gives, and the legacy name (for readers).
std::vector<std::string> error_figure_names();
inline constexpr const char* kLegacyErrorBoundName = "error_bound";

// An engine file's delivered error (the manifest's engine.file_entries, the file's own key/values,
// the server's error_figures): named error_rms_rel, with error_max_rel beside it; their definitions
// are kEngineErrorRmsRelDefinition and kEngineErrorMaxRelDefinition (brdfbake/engines.hpp).
inline constexpr const char* kEngineErrorName = "error_rms_rel";
inline constexpr const char* kEngineErrorMaxName = "error_max_rel";

// The figure's text among `meta` (a file's metadata): under its kind's name, else under any other
// figure's name, else under the legacy `error_bound`; empty when none is there.
std::optional<std::pair<std::string, std::string>> error_figure_value(
    const std::vector<std::pair<std::string, std::string>>& meta);

}  // namespace brdfbake
