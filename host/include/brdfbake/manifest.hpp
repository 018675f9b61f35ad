// manifest.json: what a job run wrote, file by file (docs/SCENES.md, "manifest.json").
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "brdfbake/engines.hpp"
#include "brdfbake/tables.hpp"

namespace brdfbake {

struct ManifestFile {
  std::string path;  // relative to the output folder
  TableKind kind = TableKind::Ggx;
  Params params;  // as baked (resolved defaults included)
  Precision precision = Precision::Fp32;
  std::string device;                 // the device's name
  std::string environment;            // prefilter, irradiance
  std::optional<double> error_bound;  // measured; empty when the module gives none
  std::string error_bound_definition;
  Metadata details;  // what else the family reports (channels, levels, error against exact, ...)
  std::vector<Request> requested_by;
  std::vector<std::string> materials;
  std::uint64_t bytes = 0;
  double seconds = 0.0;  // the bake's wall time (0 for a second file of the same bake)
  int bake = 0;          // index of the bake that produced it: files of one bake share it
};

struct Manifest {
  std::string output_dir;
  std::string job_source;
  std::string scene;
  std::vector<ManifestFile> files;
  int bakes = 0;  // distinct tables baked
  double seconds = 0.0;
  std::vector<std::string> notes, warnings;
  std::string target;                           // the engine target, when not generic
  std::vector<std::string> engine_files;        // the files of its file set, relative to the folder
  Metadata engine_delivered;                    // their formats and clamping (storage, compression)
  std::vector<EngineFileEntry> engine_entries;  // each file's size and delivered error (engines.hpp)
  std::vector<std::string> preview_files;       // bake --preview: the preview's files (docs/PREVIEW.md)
  Metadata preview;                             // ... and its summary (the sheet, errors, bound, seconds)
};
std::string manifest_to_json(const Manifest& manifest);

}  // namespace brdfbake
