// Jobs: a JSON document listing the tables to bake with every parameter (docs/SCENES.md, "Jobs").
// run_job() bakes each distinct table once and writes the files plus manifest.json into the output
// folder, all or nothing. `brdfbake run job.json` executes a job; `brdfbake bake` plans one from a
// scene (brdfbake/plan.hpp) and runs it; the server and the Python package submit the same jobs.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "brdfbake/device.hpp"
#include "brdfbake/manifest.hpp"
#include "brdfbake/tables.hpp"

namespace brdfbake {

// The environment of a job or a plan that names none.
inline constexpr const char* kDefaultEnvironment = "builtin:studio";

struct Job {
  std::string source;           // where it came from, for messages ("job.json", "bake plan")
  std::string output_dir;       // the folder the files and manifest.json go to
  std::string environment = kDefaultEnvironment;
  bool sanitize = false;        // replace NaN, infinite and negative environment pixels (recorded)
  // An engine's file set (brdfbake/engines.hpp, docs/ENGINES.md) written beside the tables from the
  // job's GGX chain and irradiance SH: "generic" (none), "filament", "gltf", "babylon",
  // "khronos-viewer".
  std::string target = "generic";
  std::string device;           // default device selector of the tables ("reference": the oracle)
  Precision precision = Precision::Fp32;
  std::vector<TableRequest> tables;
  // Informative, carried into the manifest.
  std::string scene;
  std::vector<std::string> notes;
  std::vector<std::string> warnings;
};

// Parses a job document. Throws Error "<origin>: <field>: <problem>" for malformed JSON, unknown
// fields, wrong types, unknown table kinds, values out of range (a negative size, samples and
// max_error together, ...), bad or clashing output paths.
Job parse_job(const std::string& json_text, const std::string& origin);
Job read_job(const std::string& path);
// Checks a job built in code the same way, filling every table's defaults and default output, and
// merging identical requests of one output.
void validate_job(Job& job);
// The job as a document parse_job reads back.
std::string job_to_json(const Job& job);

struct JobEvent {
  int bake = 0, bakes = 0;   // which distinct table, of how many
  std::string what;          // e.g. "ggx-multiscatter 128", "prefilter ggx 256: level 2/5"
  double fraction = 0.0;     // of this table
};
using JobProgress = std::function<void(const JobEvent&)>;

// Bakes every distinct table once and writes the files and manifest.json into job.output_dir.
// Everything is written into a temporary folder beside it first and moved in at the end, so a
// failure (bad input, a kind not available, a device error) leaves the folder as it was. Throws
// NotAvailableError before any work when a kind cannot be baked by this build.
Manifest run_job(const Job& job, const JobProgress& progress = {});

// What a caller that runs many jobs (the server, host/server/) passes in: where backends come from
// (kept warm across jobs, instead of one opened per run) and a checkpoint called on the calling
// thread before each bake and before the files are moved in, which may throw to stop the job
// (cancelled, timed out); the folder is then left as it was.
struct RunHooks {
  std::function<std::shared_ptr<Backend>(const std::string& selector)> backend;
  std::function<void()> checkpoint;
};
Manifest run_job(const Job& job, const JobProgress& progress, const RunHooks& hooks);

}  // namespace brdfbake
