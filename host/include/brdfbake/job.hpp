// Jobs and scene-driven baking.
//
// A job lists the tables to bake with every parameter (kind, size, samples or error bound,
// precision, device, output path and format); run_job() bakes each distinct table once and writes
// the files plus manifest.json into the output folder, all or nothing. The planner reads a glTF 2.0
// scene's materials, applies the rules of docs/SCENES.md and returns the job that bakes what those
// materials call for: every table names the rules and the materials that asked for it.
//
// `brdfbake run job.json` executes a job; `brdfbake bake --scene FILE` plans one and runs it;
// `brdfbake bake --dry-run --json` prints the plan as a job document that `run` accepts.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "brdfbake/device.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/table.hpp"

namespace brdfbake {

// ---- Table kinds -------------------------------------------------------------------------------

enum class TableKind {
  Ggx,              // DFG: scale, bias, diffuse (brdfbake/lut.hpp)
  GgxMultiscatter,  // DFG: bias, albedo, diffuse (energy compensation)
  Charlie,          // DFG: Charlie sheen albedo
  Fresnel,          // a Fresnel reflectance table (brdfbake/fresnel.hpp)
  ThinFilm,         // thin-film interference Fresnel over (cos_theta, film thickness)
  Prefilter,        // a prefiltered radiance mip chain of the environment (brdfbake/environment.hpp)
  Irradiance,       // diffuse irradiance of the environment: SH coefficients (and a cube)
};
// "ggx" | "ggx-multiscatter" | "charlie" | "fresnel" | "thin-film" | "prefilter" | "irradiance";
// throws Error naming the known kinds otherwise.
TableKind table_kind_from_name(const std::string& name);
const char* table_kind_name(TableKind kind);
const std::vector<TableKind>& table_kinds();
// Whether this build bakes `kind`; when not, *why says what is missing.
bool table_kind_available(TableKind kind, std::string* why = nullptr);

// A kind this build cannot bake: the job stops before anything is written.
class NotAvailableError : public Error {
 public:
  explicit NotAvailableError(const std::string& m) : Error(m) {}
};

// ---- Jobs --------------------------------------------------------------------------------------

// A parameter value: a flag, a number, a name, or a list of numbers (an RGB triple).
using ParamValue = std::variant<bool, double, std::string, std::vector<double>>;
struct Param {
  std::string name;
  ParamValue value;
};
using Params = std::vector<Param>;  // in the kind's canonical order (docs/SCENES.md, "Jobs")

// Which rule asked for a table, what for, and for which materials.
struct Request {
  std::string rule;                    // e.g. "metallic-roughness", "KHR_materials_sheen"
  std::string purpose;                 // what the renderer does with the table
  std::vector<std::string> materials;  // material labels, "#3 Name"
  std::string note;                    // e.g. the clearcoat roughness range
};

struct TableRequest {
  TableKind kind = TableKind::Ggx;
  Params params;             // the kind's own parameters, defaults filled by parse_job/validate_job
  Precision precision = Precision::Fp32;
  std::string device;        // selector ("" = the job's), or "reference" (DFG and Fresnel kinds)
  std::string environment;   // prefilter, irradiance ("" = the job's)
  std::string output;        // path relative to the output folder
  std::string format;        // "" = from the output's extension
  std::string pixel = "f16"; // f16 | f32 (.ktx2, .h and cube containers)
  std::vector<Request> requested_by;

  const ParamValue* find(const std::string& name) const;
  double number(const std::string& name, double fallback = 0.0) const;
  std::string text(const std::string& name, const std::string& fallback = {}) const;
  bool flag(const std::string& name, bool fallback = false) const;
  // The materials of every request, in order of first appearance, without repeats.
  std::vector<std::string> materials() const;
};

struct Job {
  std::string source;           // where it came from, for messages ("job.json", "bake plan")
  std::string output_dir;       // the folder the files and manifest.json go to
  std::string environment = "builtin:studio";
  std::string device;           // default device selector of the tables
  Precision precision = Precision::Fp32;
  std::vector<TableRequest> tables;
  // Informative, carried into the manifest.
  std::string scene;
  std::vector<std::string> notes;
  std::vector<std::string> warnings;
};

// Parses a job document (docs/SCENES.md, "Jobs"). Throws Error "<origin>: <field>: <problem>" for
// malformed JSON, unknown fields, wrong types, unknown table kinds, values out of range (a negative
// size, samples and max_error together, ...), bad or clashing output paths.
Job parse_job(const std::string& json_text, const std::string& origin);
Job read_job(const std::string& path);
// Checks a job built in code the same way (fills parameter defaults).
void validate_job(Job& job);
// The job as a document parse_job reads back.
std::string job_to_json(const Job& job);

// ---- Scenes ------------------------------------------------------------------------------------

using Rgb3 = std::array<double, 3>;

// One glTF material, as far as the rules need it: factors (with the specification's defaults),
// which textures are present, and which extensions.
struct SceneMaterial {
  int index = -1;           // in materials[]; -1 for the default material
  std::string name;
  std::string label;        // "#3 Name" (or "#3", or "default material")
  bool by_mesh = false;     // referenced by a mesh primitive
  bool by_variant = false;  // referenced by a KHR_materials_variants mapping
  std::vector<std::string> extensions;  // the keys of its "extensions", in file order

  Rgb3 base_color{1, 1, 1};
  bool base_color_texture = false;
  double metallic = 1.0, roughness = 1.0;
  bool metallic_roughness_texture = false;
  Rgb3 emissive{0, 0, 0};
  bool emissive_texture = false;
  double emissive_strength = 1.0;
  bool unlit = false;

  bool sheen = false;
  Rgb3 sheen_color{0, 0, 0};
  bool sheen_color_texture = false;
  double sheen_roughness = 0.0;
  bool sheen_roughness_texture = false;

  bool clearcoat_ext = false;
  double clearcoat = 0.0;
  bool clearcoat_texture = false;
  double clearcoat_roughness = 0.0;
  bool clearcoat_roughness_texture = false;

  bool ior_ext = false;
  double ior = 1.5;

  bool specular_ext = false;
  double specular = 1.0;
  bool specular_texture = false;
  Rgb3 specular_color{1, 1, 1};
  bool specular_color_texture = false;

  bool transmission_ext = false;
  double transmission = 0.0;
  bool transmission_texture = false;

  bool volume_ext = false;
  double thickness = 0.0;
  bool thickness_texture = false;

  bool dispersion_ext = false;
  double dispersion = 0.0;

  bool iridescence_ext = false;
  double iridescence = 0.0;
  bool iridescence_texture = false;
  double iridescence_ior = 1.3;
  double iridescence_thickness_min = 100.0, iridescence_thickness_max = 400.0;  // nm
  bool iridescence_thickness_texture = false;

  bool anisotropy_ext = false;
  double anisotropy_strength = 0.0;
  bool anisotropy_texture = false;
};

struct Scene {
  std::string path;
  std::string container;  // "gltf" or "glb"
  std::vector<SceneMaterial> materials;        // every material of the file, in order
  std::optional<SceneMaterial> default_material;  // when some primitive has no material
  bool has_meshes = false;
  std::vector<std::string> variants;           // KHR_materials_variants names
  std::vector<std::string> extensions_used, extensions_required;
  std::vector<std::string> warnings;           // missing .bin files and images, ignored extensions
};

// Reads the materials of a glTF 2.0 file: .gltf (JSON) or .glb (the JSON chunk). Buffers and images
// are not read; missing ones are warnings. Throws Error naming the file (and the field) for
// malformed JSON, a truncated or corrupt .glb, a version other than 2.x, a material field of the
// wrong type or out of range, and an extension in extensionsRequired that brdfbake does not know.
Scene read_scene(const std::string& path);
// The same from text already read (`origin` names it in messages; `base_dir` resolves URIs, "" to
// skip the check of buffers and images).
Scene parse_scene_json(const std::string& json_text, const std::string& origin, const std::string& base_dir);
Scene parse_glb(const std::string& bytes, const std::string& origin, const std::string& base_dir);

// ---- Planning ----------------------------------------------------------------------------------

struct PlanOptions {
  std::string environment = "builtin:studio";
  bool energy_compensation = true;  // ggx-multiscatter replaces ggx
  int lut_size = 128;               // DFG tables: size x size
  int fresnel_size = 256;           // Fresnel tables: cells along cos_theta
  int thin_film_size = 128;         // thin-film tables: size x size (cos_theta x thickness)
  int cube_size = 256;              // prefiltered chains: face size of level 0
  int cube_min_size = 16;
  double prefilter_max_error = 0.01;  // > 0: each level refined until successive refinements differ
                                      // by less (RMS relative luminance): the chain's measured bound
  int sh_order = 3;
  std::string sheen_visibility = "estevez-kulla";  // the Charlie DFG table's (the albedo table's
                                                   // is always estevez-kulla, as the extension says)
  std::string table_format = "exr"; // 1-D and 2-D tables
  std::string cube_format = "ktx2";
  std::string pixel = "f16";
  Precision precision = Precision::Fp32;
  std::string device;
};

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

// ---- Running -----------------------------------------------------------------------------------

struct ManifestFile {
  std::string path;          // relative to the output folder
  TableKind kind = TableKind::Ggx;
  Params params;             // as baked (resolved defaults included)
  Precision precision = Precision::Fp32;
  std::string device;        // the device's name
  std::string environment;   // prefilter, irradiance
  std::optional<double> error_bound;  // measured; empty when the module gives none
  std::string error_bound_definition;
  Metadata details;          // what else the family reports (channels, levels, error against exact, ...)
  std::vector<Request> requested_by;
  std::vector<std::string> materials;
  std::uint64_t bytes = 0;
  double seconds = 0.0;      // the bake's wall time (0 for a second file of the same bake)
  int bake = 0;              // index of the bake that produced it: files of one bake share it
};

struct Manifest {
  std::string output_dir;
  std::string job_source;
  std::string scene;
  std::vector<ManifestFile> files;
  int bakes = 0;             // distinct tables baked
  double seconds = 0.0;
  std::vector<std::string> notes, warnings;
};
std::string manifest_to_json(const Manifest& manifest);

struct JobEvent {
  int bake = 0, bakes = 0;   // which distinct table, of how many
  std::string what;          // e.g. "ggx-multiscatter 128x128", "prefilter ggx: level 2/5"
  double fraction = 0.0;     // of this table
};
using JobProgress = std::function<void(const JobEvent&)>;

// Bakes every distinct table once and writes the files and manifest.json into job.output_dir.
// Everything is written into a temporary folder beside it first and moved in at the end, so a
// failure (bad input, a kind not available, a device error) leaves the folder as it was. Throws
// NotAvailableError before any work when a kind cannot be baked by this build.
Manifest run_job(const Job& job, const JobProgress& progress = {});

}  // namespace brdfbake
