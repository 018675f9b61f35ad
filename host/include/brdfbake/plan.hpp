// The scene planner: the rules of docs/SCENES.md turn a scene's materials into the job that bakes
// what they call for; every table records the rules and the materials that asked for it.
#pragma once

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
  bool sanitize = false;            // replace NaN, infinite and negative environment pixels
  bool energy_compensation = true;  // ggx-multiscatter replaces ggx
  std::optional<int> lut_size;        // DFG tables: size x size
  std::optional<int> fresnel_size;    // Fresnel tables: cells along cos_theta
  std::optional<int> thin_film_size;  // thin-film tables: size x size (cos_theta x thickness)
  std::optional<int> cube_size;       // prefiltered chains: face size of level 0
  std::optional<int> cube_min_size;   // prefiltered chains: face size of the smallest level
  std::optional<std::string> schedule;  // prefiltered chains: roughness of each level
  double prefilter_max_error = 0.01;  // > 0: each level refined until successive refinements differ
                                      // by less (RMS relative luminance): the chain's measured bound
  std::optional<int> sh_order;
  std::optional<std::string> sheen_visibility;  // the Charlie DFG table's (the albedo table's is
                                                // always estevez-kulla, as the extension says)
  std::string target = "generic";   // an engine's file set too (brdfbake/engines.hpp): its schedule,
                                    // sizes and SH window unless given
  std::string table_format = "exr"; // 1-D and 2-D tables
  std::string cube_format = "ktx2";
  std::string pixel;                // "" = each kind's default
  bool clamp_f16 = false;           // binary16 outputs clamp values beyond 65504 (recorded) instead of refusing
  Precision precision = Precision::Fp32;
  std::string device;
};

// The planner's options as parameters (for `brdfbake bake`, the server and the bindings): types,
// ranges and help come from the table parameter each sets.
const std::vector<ParamDef>& plan_schema();
// Options from parameters checked against plan_schema (errors name the field as `naming` says).
PlanOptions plan_options_from_params(const Params& params, bool cli);

// What the planner decided about one material.
struct MaterialPlan {
  std::string label;
  std::string reached_by;            // "mesh", "variant", "mesh+variant", "default", "unreferenced"
  bool counted = true;               // unreferenced materials of a scene with meshes are not
  std::vector<std::string> rules;    // the rules that fired for it
  std::vector<std::string> notes;    // e.g. "KHR_materials_anisotropy: anisotropyStrength 0, does not fire"
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

}  // namespace brdfbake
