// The scene planner: the rules of docs/SCENES.md turn a scene's materials into the job that bakes
// what they call for; every table records the rules and the materials that asked for it.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "brdfbake/job.hpp"
#include "brdfbake/scene.hpp"

namespace brdfbake {

// The planner's choices. Unset optionals leave the table's own default (table_schema), so each
// default is written once; plan_schema() names them for the command line.
struct PlanOptions {
  std::string environment = kDefaultEnvironment;
  bool sanitize = false;                // replace NaN, infinite and negative environment pixels
  bool energy_compensation = true;      // ggx-multiscatter replaces ggx
  std::optional<int> lut_size;          // DFG tables: size x size
  std::optional<int> fresnel_size;      // Fresnel tables: cells along cos_theta
  std::optional<int> thin_film_size;    // thin-film tables: size x size (cos_theta x thickness)
  std::optional<int> chain_size;        // prefiltered chains: face size of level 0
  std::optional<int> cube_min_size;     // prefiltered chains: face size of the smallest level
  std::optional<std::string> schedule;  // prefiltered chains: roughness of each level
  double chain_max_error = 0.01;        // > 0: each level refined until successive refinements differ
                                        // by less (RMS relative luminance): the chain's measured bound
  std::optional<int> sh_order;
  std::optional<std::string> sh_window;         // irradiance: the SH window; default the target's
  std::string engine_name;                      // NAME of an engine target's files; "" = the output folder's
  std::optional<std::string> sheen_visibility;  // the Charlie DFG table's (the albedo table's is
                                                // always estevez-kulla, as the extension says)
  std::string target = "generic";               // an engine's file set too (brdfbake/engines.hpp): its schedule,
                                                // sizes and SH window unless given
  std::string table_format = "exr";             // 1-D and 2-D tables
  std::string cube_format = "ktx2";
  std::string pixel;       // "" = each kind's default
  bool clamp_f16 = false;  // binary16 outputs clamp values beyond 65504 (recorded) instead of refusing
  Precision precision = Precision::Fp32;
  std::string device;
};

// The planner's options as parameters (for `brdfbake bake`, the server and the bindings): types,
// ranges and help come from the table parameter each sets.
const std::vector<ParamDef>& plan_schema();

// What the planner decided about one material.
struct MaterialPlan {
  std::string label;
  std::string reached_by;          // "mesh", "variant", "mesh+variant", "default", "unreferenced"
  bool counted = true;             // unreferenced materials of a scene with meshes are not
  std::vector<std::string> rules;  // the rules that fired for it
  std::vector<std::string> notes;  // e.g. "KHR_materials_anisotropy: anisotropyStrength 0, does not fire"
};

struct Plan {
  Job job;
  std::vector<MaterialPlan> materials;
  std::vector<std::string> rules_fired;  // in rule order
  PlanOptions options;
};

// The plan for a scene, and for no scene: the standard set for metallic-roughness materials.
Plan plan_scene(const Scene& scene, const PlanOptions& options = {});
Plan plan_default(const PlanOptions& options = {});
// The plan as a job document (parse_job reads it back) with a "plan" section: options, materials
// and the rules that fired.
std::string plan_to_json(const Plan& plan);

// ---- Bake options: one parser for `brdfbake bake`, POST /v1/bake and brdfbake.bake_scene ----------

// Every option of a scene bake: plan_schema()'s, then scene, environment (--env), sanitize, pixel,
// precision and device.
const std::vector<ParamDef>& bake_option_schema();

// How a front end names an option in its messages.
struct OptionNaming {
  bool cli = false;                       // "--chain-size"
  std::string prefix;                     // "bake_scene" (Python), "bake" (the server)
  bool dotted = false;                    // "bake_scene.chain_size" (true) or "bake: chain_size"
  std::string unknown = "unknown field";  // what an unknown name is called
  std::string field(const ParamDef& d) const;
};

struct BakeOptions {
  std::string scene;  // "" = no scene: the standard set for metallic-roughness materials
  PlanOptions plan;
  bool preview = false;  // also render the target's preview of the files (Job::preview)
};

// Reads the options given, each a field of bake_option_schema() with a typed value (command-line
// text through parse_param_text; JSON and Python values as they come): refuses unknown names,
// options given twice, wrong types, values out of range and options that contradict each other,
// with one line naming the option as `naming` says.
BakeOptions parse_bake_options(const Params& given, const OptionNaming& naming);
// The plan of the options: the scene read (read_scene) and planned, or the standard set.
Plan plan_bake(const BakeOptions& options);

}  // namespace brdfbake

// ---- Dry-run estimates: each table's wall time on a device and the bytes of its files -----------

namespace brdfbake {

class Backend;

// What a bake of one table of a job would cost (docs/SCENES.md, "Before a long bake").
struct TableEstimate {
  std::string output;  // as the job names it
  TableKind kind = TableKind::Ggx;
  // Wall time of its bake and of writing its files, in seconds; 0 for a second output of one bake
  // (as the manifest records it).
  double seconds = 0.0;
  std::uint64_t bytes = 0;  // its files: the output and any sidecar
  // "measured": baked at its own size; "scaled": fitted from bakes at 1/2 and 1/4 of its sizes.
  std::string method;
  // Index of the bake that makes it, as the manifest's ManifestFile::bake: outputs of one bake
  // share it (run_job's groups: the estimate measures the bakes the run makes).
  int bake = 0;
};

struct PlanEstimate {
  std::vector<TableEstimate> tables;  // in the job's order
  double environment_seconds = 0.0;   // reading each environment once
  double seconds = 0.0;               // the whole bake: environments and tables (not an engine's file set)
  std::uint64_t bytes = 0;            // every table's files
  double calibration_seconds = 0.0;   // what making the estimate took (0 when every table was cached)
};

// One step the estimate times (EstimateOptions::timer): a measuring bake or an environment's read.
struct EstimateStep {
  // A measuring bake of this request (a group's first table, its sides divided or not) and the
  // delivery of each output of its group; null for an environment's read.
  const TableRequest* bake = nullptr;
  std::string environment;  // the environment read (its spec), when bake is null
};

struct EstimateOptions {
  // Runs `work` on the device a selector names (the server: on its warm device, before queued jobs);
  // empty: a backend opened once per selector.
  std::function<void(const std::string& selector, const std::function<void(Backend&)>& work)> on_device;
  std::uint64_t memory_budget = 0;  // for reading environments (EnvLoadOptions), 0 = its default
  // The measuring bakes stop at their next step (Cancelled is thrown) once this returns true: the
  // server's deadline for POST /v1/plan.
  std::function<bool()> stop_requested;
  // Times one step: runs `work` once and returns its seconds. Empty: its wall time (steady_clock).
  // Given (a test's clock with known times: tests/host/test_job.cpp), what it returns is the
  // measurement, and the process's kept measurements are neither read nor added to.
  std::function<double(const EstimateStep& step, const std::function<void()>& work)> timer;
};

// Estimates a job's bake (validated or not: a validated copy is estimated) from measured speed on
// the device: a table of at most kEstimateMeasureBelow work units is baked at its own size, a
// larger one at 1/2 and 1/4 of its sizes and its time and bytes fitted as a + b * work (work: the
// texels it bakes, every level and face), then extrapolated. Nothing is written beside a scratch
// folder in the system's temporary folder. Measurements are kept for the process (by device, table
// and environment), so a second estimate of the same tables bakes nothing.
PlanEstimate estimate_job(const Job& job, const EstimateOptions& options = {});
inline constexpr double kEstimateMeasureBelow = 8192.0;

}  // namespace brdfbake
