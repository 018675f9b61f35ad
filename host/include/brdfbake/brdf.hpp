// Bulk BRDF evaluation and tabulation: the Disney principled BRDF, the glTF 2.0 metallic-roughness
// BRDF (with KHR_materials_sheen, _clearcoat, _specular, _ior) and the classic models, evaluated for
// many materials and direction pairs at once on an OpenCL device (kernels/brdf_eval.cl), or by the
// scalar double reference (the *_reference functions; host/src/families/brdf_eval/reference.cpp).
//
// Conventions (docs/CONVENTIONS.md, "BRDF evaluation"): f is the BRDF without the cosine;
// directions are in tangent space, normal +z, tangent +x; f = 0 at and below the horizon.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "brdfbake/device.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/types.hpp"
#include "brdfbake/table.hpp"

namespace brdfbake {

// ---- Models and their parameters ----------------------------------------------------------------

enum class BrdfModel {
  Disney,             // Burley 2012, in the BRDF Explorer's disney.brdf formulation
  Gltf,               // glTF 2.0 Appendix B, separable Smith G
  GltfCorrelated,     // the same with the height-correlated Smith visibility (Khronos sample renderer)
  Lambert,            // Lambert 1760
  Phong,              // Phong 1975, reciprocal BRDF form
  BlinnPhong,         // Blinn 1977
  CookTorrance,       // Cook & Torrance 1982, Beckmann or GGX
  BlinnPhongFromPbr,  // metallic-roughness mapped to a normalised, Fresnel-weighted Blinn-Phong
};

// Cook-Torrance's distribution of normals.
enum class MicrofacetDistribution { Beckmann, Ggx };

// The largest Phong / Blinn-Phong exponent accepted (validate_material); the lobe is then 0.1
// degree wide.
inline constexpr double kMaxShininess = math::kMaxShininess;

// Every parameter of every model; a model reads only its own (docs/CONVENTIONS.md lists which and
// their file names). Ranges are checked by validate_material.
struct Material {
  // glTF 2.0 metallic-roughness core and Disney 2012 (baseColor, metallic, roughness).
  Rgb base_color{0.8, 0.8, 0.8};  // linear, [0, 1]
  double metallic = 0.0;          // [0, 1]
  double roughness = 0.5;         // perceptual, [0, 1]
  // Disney 2012 only, [0, 1] each (BRDF Explorer's defaults).
  double subsurface = 0.0;
  double specular = 0.5;  // F0 = 0.08 specular
  double specular_tint = 0.0;
  double anisotropic = 0.0;
  double sheen = 0.0;
  double sheen_tint = 0.5;
  double clearcoat = 0.0;  // Disney's clearcoat, and glTF's clearcoatFactor
  double clearcoat_gloss = 1.0;
  // glTF extensions.
  Rgb sheen_color{0.0, 0.0, 0.0};            // KHR_materials_sheen sheenColorFactor, [0, 1]
  double sheen_roughness = 0.0;              // sheenRoughnessFactor, [0, 1]
  double clearcoat_roughness = 0.0;          // KHR_materials_clearcoat clearcoatRoughnessFactor, [0, 1]
  double ior = 1.5;                          // KHR_materials_ior: 0 or >= 1
  double specular_factor = 1.0;              // KHR_materials_specular specularFactor, [0, 1]
  Rgb specular_color_factor{1.0, 1.0, 1.0};  // specularColorFactor, >= 0
  // KHR_materials_iridescence (read from glTF; rendered by the preview only, not by eval's gltf BRDF):
  // iridescenceFactor [0, 1], iridescenceIor, and the film's thickness in nm (iridescenceThicknessMaximum,
  // the thickness where there is no thickness texture).
  double iridescence = 0.0;
  double iridescence_ior = 1.3;
  double iridescence_thickness = 400.0;
  // Classic models. Unset colours and exponent derive from the metallic-roughness parameters:
  // kd = base_color (1 - metallic), ks = mix(0.04, base_color, metallic), n = 2048^(1 - roughness).
  std::optional<Rgb> diffuse_color;   // kd, [0, 1]
  std::optional<Rgb> specular_color;  // ks (Phong, Blinn-Phong), F0 (Cook-Torrance), [0, 1]
  std::optional<double> shininess;    // Phong / Blinn-Phong exponent, [0, kMaxShininess]
  bool normalized = true;             // energy-normalised lobes (false: the textbook forms)
  MicrofacetDistribution distribution = MicrofacetDistribution::Ggx;  // Cook-Torrance's D
};

// "disney", "gltf", "gltf-correlated", "lambert", "phong", "blinn-phong", "cook-torrance",
// "blinn-phong-from-pbr". Throws Error naming the unknown model and the known ones.
BrdfModel brdf_model_from_name(const std::string& name);
const char* brdf_model_name(BrdfModel model);
const std::vector<BrdfModel>& brdf_models();

// ---- Materials ------------------------------------------------------------------------------------

struct NamedMaterial {
  std::string name;
  std::optional<BrdfModel> model;  // the material's "model" (JSON files only)
  Material params;
  std::vector<std::string> notes;  // what of the source was not used (glTF textures, other extensions)
  // glTF: the image files of baseColorTexture and metallicRoughnessTexture when they are files beside
  // the scene (the preview reads their means; eval and tabulate do not); "" otherwise.
  std::string base_color_image, metallic_roughness_image;
};

// {"materials": [{"name": ..., "model": ..., parameters by their glTF or Disney names}]}, linear
// colours (docs/CONVENTIONS.md lists every name). Unknown keys, wrong types, values out of range and
// NaN throw Error naming `origin`, the material and the field.
std::vector<NamedMaterial> parse_materials_json(const std::string& text, const std::string& origin);
// The "materials" of a glTF 2.0 JSON document (.gltf): pbrMetallicRoughness factors and the
// KHR_materials_sheen, _clearcoat, _specular and _ior factors, with the specification's defaults.
// Textures, buffers and images are not read (each ignored texture is listed in `notes`).
std::vector<NamedMaterial> parse_gltf_materials(const std::string& text, const std::string& origin);
// Reads `path`: a .gltf file (or any JSON with an "asset" object) as glTF, anything else as ours.
// A .glb file is refused with a message. A JSON document itself may stand in place of the path (text
// starting with '{' that names no file): the Python package passes in-memory materials this way, so
// that they reach the same parser, checks, metadata and bake key as a file.
std::vector<NamedMaterial> read_materials(const std::string& path);
// Throws Error("<where>: <field> must be ...") for a parameter out of range or NaN.
void validate_material(const Material& material, const std::string& where);
// The material called `name`, or the only one when `name` is empty. Throws Error listing the names.
const NamedMaterial& find_material(const std::vector<NamedMaterial>& materials, const std::string& name,
                                   const std::string& origin);
// The model a material is evaluated with: `chosen` if given, else the material's own, else Error.
BrdfModel resolve_model(const std::optional<BrdfModel>& chosen, const NamedMaterial& material);
// The parameters of a material as one line of JSON, by their file names (for metadata).
std::string material_to_json(const NamedMaterial& material);

// ---- Lobes ----------------------------------------------------------------------------------------

// The lobes a program is compiled with (kernels/brdf_eval.cl lists what each means per model).
struct Lobes {
  bool diffuse = false, subsurface = false, sheen = false, clearcoat = false, anisotropic = false, metal = false,
       specular_color = false, beckmann = false, ggx = false;
};
// The lobes that some of `materials` uses under `model`.
Lobes lobes_used(BrdfModel model, const std::vector<Material>& materials);
// Every lobe of the model (no specialisation).
Lobes all_lobes(BrdfModel model);
// "diffuse,sheen,..." (or "none").
std::string lobes_name(BrdfModel model, const Lobes& lobes);

// ---- Evaluation -----------------------------------------------------------------------------------

struct EvalOptions {
  Precision precision = Precision::Fp32;
  bool fast_math = false;  // build with -cl-fast-relaxed-math (an opt-in variant, docs/BENCHMARKS.md)
  bool specialize = true;  // compile only the lobes the materials use; false: every lobe of the model
  int lanes = 0;           // directions per work-item (4, 8 or 16); 0: the device's kernel shape's (cpu: the
                           // measured best per precision, 16 fp32 / 8 fp64; gpu: 4)
};

struct EvalTiming {
  double device_seconds = 0.0;  // kernel time from OpenCL event profiling
  double wall_seconds = 0.0;    // the whole call, conversions and transfers included
};

// One model's program built for a set of materials, with the materials on the device; evaluates
// batches of direction pairs against all of them. Construction builds (or fetches) the program;
// buffers grow to the largest batch and are reused. Not thread-safe.
class BrdfEvaluator {
 public:
  BrdfEvaluator(Device& device, BrdfModel model, std::vector<Material> materials, const EvalOptions& options = {});
  ~BrdfEvaluator();
  BrdfEvaluator(const BrdfEvaluator&) = delete;
  BrdfEvaluator& operator=(const BrdfEvaluator&) = delete;

  // pairs: 6 values per pair (wi.x, wi.y, wi.z, wo.x, wo.y, wo.z), finite and non-zero vectors of
  // any length (normalised here, in double). out: 3 values per pair per material, material-major:
  // out[(m * count + i) * 3 + c]. Throws Error naming the pair for a zero or non-finite vector.
  void eval(const double* pairs, std::size_t count, double* out, EvalTiming* timing = nullptr);

  const Lobes& lobes() const;
  std::size_t material_count() const;
  int lanes() const;
  std::size_t chunk_pairs() const;  // PairEvaluator::chunk_pairs for this evaluator's device

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class Backend;

// Evaluates one model for a set of materials at batches of direction pairs (see BrdfEvaluator).
class PairEvaluator {
 public:
  virtual ~PairEvaluator() = default;
  // pairs: 6 values a pair; out: 3 values a pair a material, material-major.
  virtual void eval(const double* pairs, std::size_t count, double* out, EvalTiming* timing = nullptr) = 0;
  // The pairs a batch should hold to fill the device (the streams of `brdfbake eval` and a job's
  // pairs go through in batches of this many): 65,536 on a CPU shape and the reference, the device's
  // compute units times kGpuPairsPerComputeUnit on a GPU shape.
  virtual std::size_t chunk_pairs() const { return std::size_t(1) << 16; }
};
// An evaluator on a backend (brdfbake/backend.hpp): a BrdfEvaluator on its OpenCL device, or the
// scalar reference (eval_reference); each batch holds the backend's call lock. The backend outlives
// it.
std::unique_ptr<PairEvaluator> make_evaluator(Backend& backend, BrdfModel model, const std::vector<Material>& materials,
                                              const EvalOptions& options = {});

// The same with the scalar reference, one material (pairs and out as above, count pairs).
void eval_reference(BrdfModel model, const Material& material, const double* pairs, std::size_t count, double* out);

// ---- Tabulation -----------------------------------------------------------------------------------

enum class TableLayout {
  Merl,    // MERL's 90 x 90 x 180 half/difference-angle table (Matusik et al. 2003)
  Grid,    // theta_i x theta_o x phi_d at cell centres
  Albedo,  // directional albedo over theta_o, one row per material
  Slice,   // f over (theta_h, theta_d) at one phi_d (Burley 2012's image slice)
};
TableLayout table_layout_from_name(const std::string& name);  // "merl" | "grid" | "albedo" | "slice"
const char* table_layout_name(TableLayout layout);

struct TabulateSpec {
  BrdfModel model = BrdfModel::Disney;
  std::vector<NamedMaterial> materials;  // merl, grid and slice take exactly one
  TableLayout layout = TableLayout::Merl;
  // grid: {n_theta_i, n_theta_o, n_phi_d}; albedo: {n_theta_o}; slice: {width (theta_h), height
  // (theta_d)}; one value stands for all; empty: the layout's default (merl has its fixed size).
  std::vector<int> res;
  double slice_phi_d = 1.5707963267948966;  // slice: phi_d in [0, pi]
  EvalOptions options;
};

// The resolved shape of a TabulateSpec (defaults filled, sizes checked): throws Error for a bad one.
std::vector<int> tabulate_resolution(const TabulateSpec& spec);

// A MERL table in memory: f at the 90 * 90 * 180 bin centres, channel-major in the file's order
// (values[(c * 90 + i) * 90 * 180 + j * 180 + k] for theta_h bin i, theta_d bin j, phi_d bin k), or
// kMerlBelowHorizon where the bin's directions fall below the horizon.
inline constexpr int kMerlThetaH = 90, kMerlThetaD = 90, kMerlPhiD = 180;
inline constexpr std::size_t kMerlBins = 90u * 90u * 180u;
inline constexpr double kMerlBelowHorizon = -1.0;
struct MerlTable {
  std::vector<double> values;  // 3 * kMerlBins
  Metadata metadata;
};

struct TabulateTiming {
  double device_seconds = 0.0;
  double wall_seconds = 0.0;
};

// merl on the device / by the reference.
MerlTable tabulate_merl(Device& device, const TabulateSpec& spec, TabulateTiming* timing = nullptr);
MerlTable tabulate_merl_reference(const TabulateSpec& spec, TabulateTiming* timing = nullptr);
// grid, albedo and slice (channels r, g, b), on the device / by the reference.
Table tabulate(Device& device, const TabulateSpec& spec, TabulateTiming* timing = nullptr);
Table tabulate_reference(const TabulateSpec& spec, TabulateTiming* timing = nullptr);
// Both on a backend (brdfbake/backend.hpp): its OpenCL device or the scalar reference.
MerlTable tabulate_merl(Backend& backend, const TabulateSpec& spec, TabulateTiming* timing = nullptr);
Table tabulate(Backend& backend, const TabulateSpec& spec, TabulateTiming* timing = nullptr);

// The MERL binary (three int32 dims 90, 90, 180, then 3 * kMerlBins doubles, channel-major, each f
// divided by the channel scale MERL's BRDFRead multiplies by: 1/1500, 1.15/1500, 1.66/1500; -1 in
// below-horizon bins), written atomically, with the metadata in a sidecar "<path>.json".
void write_merl(const MerlTable& table, const std::string& path);
// Reads a MERL binary back (values multiplied by the channel scales; negative bins read as
// kMerlBelowHorizon). Throws Error for a file that is not one.
MerlTable read_merl(const std::string& path);
// MERL's lookup_brdf_val: the value of the bin that (wi, wo) falls in (nearest bin, phi_d folded by
// reciprocity), or kMerlBelowHorizon.
Rgb merl_lookup(const MerlTable& table, const Vec3& wi, const Vec3& wo);

}  // namespace brdfbake
