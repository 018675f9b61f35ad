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
  std::string source;      // where it came from, for messages ("job.json", "bake plan")
  std::string output_dir;  // the folder the files and manifest.json go to
  std::string environment = kDefaultEnvironment;
  bool sanitize = false;  // replace NaN, infinite and negative environment pixels (recorded)
  // An engine's file set (brdfbake/engines.hpp, docs/ENGINES.md) written beside the tables from the
  // job's GGX chain and irradiance SH: "generic" (none), "filament", "gltf", "babylon",
  // "khronos-viewer".
  std::string target = "generic";
  // NAME of the engine's files (NAME.gltf, NAME_ibl.ktx, ...): empty is the output folder's name, as
  // cmgen names them; `run --server` sets it to the local folder's (the server's folder is a job id).
  std::string engine_name;
  // target gltf: the Babylon.js scene the light is for, "left-handed" (Babylon.js's default: rotation
  // identity) or "right-handed" (rotation (0, 1, 0, 0)); docs/ENGINES.md, "Engine truth".
  std::string gltf_scene = "left-handed";
  std::string device;  // default device selector of the tables ("reference": the oracle)
  Precision precision = Precision::Fp32;
  std::vector<TableRequest> tables;
  // `brdfbake bake --preview`: also render the preview of the files (the preview family, default grid)
  // into preview.png and its siblings, recorded in the manifest's "preview" (job documents: "preview").
  bool preview = false;
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
  int bake = 0, bakes = 0;  // which step, of how many: the distinct tables, then an engine target's file set
  std::string what;         // e.g. "ggx-multiscatter 128", "prefilter ggx 256: level 2/5"
  double fraction = 0.0;    // of this table
};
using JobProgress = std::function<void(const JobEvent&)>;

// How a run shares its output folder with other runs (docs/RELIABILITY.md, "Outputs"), and what a
// caller that runs many jobs (the server, host/server/) passes in.
struct RunOptions {
  // Another run writing the same folder: false fails at once (LockedError naming its pid), true
  // waits for it.
  bool wait_for_lock = false;
  // Called once when the run starts waiting, with the holder's pid (0 when unknown).
  std::function<void(long pid)> on_wait;
  // Where backends come from (kept warm across jobs, instead of one opened per run); empty: one
  // opened per run.
  std::function<std::shared_ptr<Backend>(const std::string& selector)> backend;
  // Called on the calling thread before each bake and before the files are moved in; may throw to
  // stop the job (cancelled, timed out); the folder is then left as it was.
  std::function<void()> checkpoint;
  // Asked at each step of a bake (between device launches, rows of a reference table, levels); true
  // stops the job there with Cancelled (the server's cancel, timeout and shutdown of one job).
  std::function<bool()> stop_requested;
  // Called with each warning a write gives (values clamped on request, clamp_f16), as it happens;
  // the manifest's warnings hold them too.
  std::function<void(const std::string& warning)> on_warning;
  // The base name of an engine target's files ("" = the output folder's name, as cmgen -x names
  // them); the server passes the name of the folder its client writes into.
  std::string engine_name;
  // The memory an environment image may take decoded (EnvLoadOptions::memory_budget; 0: the default).
  std::uint64_t memory_budget = 0;
};
using RunHooks = RunOptions;

// Bakes every distinct table once and writes the files and manifest.json into job.output_dir.
// The folder is locked for the run (a second run into it fails or waits, RunOptions), the
// temporaries that killed runs left beside it are removed, and everything is written into a
// temporary folder beside it first and moved in at the end, so a failure (bad input, a kind not
// available, a device error, SIGINT/SIGTERM through brdfbake/cancel.hpp, a checkpoint that throws)
// leaves the folder as it was. Throws NotAvailableError before any work when a kind cannot be baked
// by this build.
Manifest run_job(const Job& job, const JobProgress& progress = {}, const RunOptions& options = {});

}  // namespace brdfbake
