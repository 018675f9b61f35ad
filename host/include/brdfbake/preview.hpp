// Material previews (the family `preview`, docs/PREVIEW.md): a grid of spheres lit by an
// environment, rendered twice on one backend:
//   the split-sum render  what a target engine's shader computes from a bake's files, read in their
//                         stored encoding (docs/ENGINES.md says which shader function each step is);
//   the reference render  each pixel's converged integral of the same BRDF against the environment,
//                         no split sum, no prefiltering, no storage, with a stated error bound;
// and their difference per sphere (relative RMS, 99th percentile and max in linear radiance, and in
// 8-bit sRGB steps after the view's tone map). The result holds both renders as float images, the
// numbers and the layout, so that every pixel can be recomputed: each sphere's centre and radius in
// pixels, the camera in the environment's frame, the BRDF and its parameters.
//
// Front ends reach it through the registry (kind "preview", `brdfbake preview`); the family writes
// NAME.png (the contact sheet), NAME_splitsum.exr, NAME_reference.exr and NAME.json.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "brdfbake/backend.hpp"
#include "brdfbake/device.hpp"
#include "brdfbake/engines.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/math/types.hpp"
#include "brdfbake/table.hpp"

namespace brdfbake {

// ---- Materials ----------------------------------------------------------------------------------

// A sphere's material: the glTF 2.0 metallic-roughness core (what every target's split-sum shader
// reads) and the extensions the preview renders, linear colours, factors only (no textures).
// Specular Fresnel F = F0 + (F90 - F0) (1 - v.h)^5 with (glTF 2.0 Appendix B with KHR_materials_ior
// and KHR_materials_specular: dielectric_brdf's fresnel_mix, metal_brdf's conductor_fresnel)
//   F0  = mix(specular min(((ior - 1) / (ior + 1))^2 specular_color, 1), base_color, metallic),
//   F90 = mix(specular, 1, metallic);
// the defaults (ior 1.5, specular 1, specular_color 1) give F0 = mix(0.04, base_color, metallic),
// F90 = 1. Diffuse colour = base_color (1 - metallic), alpha = roughness^2.
// KHR_materials_clearcoat (the geometric normal: no clearcoat normal texture): a second GGX lobe of
// alpha clearcoat_roughness^2 layered over the rest by the extension's fresnel_coat, Schlick's F of
// ior 1.5 at n.v: f = (1 - clearcoat Fcoat(n.v)) f_base + clearcoat Fcoat(n.v) D_coat V_coat.
// KHR_materials_sheen: the Charlie lobe (Estevez & Kulla 2017: D_Charlie, their fitted visibility, the
// charlie DFG table's default) of alpha max(sheen_roughness^2, 1e-7) over the rest, scaled by the
// extension's albedo scaling at n.v: f = (1 - max(sheen_color) E(n.v)) f_base + sheen_color D V, E the
// lobe's exact directional albedo (the charlie table's quadrature). Under the clear coat (sheen first).
// KHR_materials_iridescence (factors only: the film is iridescence_thickness thick everywhere): the
// specular Fresnel becomes mix(F, F_irid(v.h), iridescence) with F_irid the thin film's (Belcour &
// Barla 2017 as the extension writes it; outside index 1) over the dielectric's F0 for the dielectric
// part and over base_color for the metal part (the extension's dielectric_brdf and metal_brdf), the
// specular factor weighting the dielectric's film as it weights its Fresnel. The diffuse weight and the
// compensation keep the material's own F0.
struct PreviewMaterial {
  std::string name;
  Rgb base_color{0.8, 0.8, 0.8};
  double metallic = 0.0;
  double roughness = 0.5;
  std::vector<std::string> notes;        // what of the source material the preview does not render
  double ior = 1.5;                      // KHR_materials_ior: 0 or >= 1 (0: F0 1)
  double specular = 1.0;                 // KHR_materials_specular specularFactor, [0, 1]
  Rgb specular_color{1.0, 1.0, 1.0};     // specularColorFactor, >= 0 (F0 clamped to 1 after it)
  double clearcoat = 0.0;                // KHR_materials_clearcoat clearcoatFactor, [0, 1]
  double clearcoat_roughness = 0.0;      // clearcoatRoughnessFactor, [0, 1]
  Rgb sheen_color{0.0, 0.0, 0.0};        // KHR_materials_sheen sheenColorFactor, [0, 1]
  double sheen_roughness = 0.0;          // sheenRoughnessFactor, [0, 1]
  double iridescence = 0.0;              // KHR_materials_iridescence iridescenceFactor, [0, 1]
  double iridescence_ior = 1.3;          // iridescenceIor, [1, 10]
  double iridescence_thickness = 400.0;  // the film's thickness in nm (iridescenceThicknessMaximum), >= 0
};
// Whether a material has an iridescent film (iridescence above 0).
bool preview_has_iridescence(const PreviewMaterial& m);
// Whether a material has a sheen lobe (a sheen colour above 0).
bool preview_has_sheen(const PreviewMaterial& m);
// The clear coat's Fresnel at n.v (KHR_materials_clearcoat's fresnel_coat: ior 1.5, F0 0.04).
double preview_coat_fresnel(double n_dot_v);
Rgb preview_f0(const PreviewMaterial& m);
double preview_f90(const PreviewMaterial& m);
// The dielectric's F0 before the specular factor: min(((ior - 1) / (ior + 1))^2 specular_color, 1)
// (exactly 0.04 at ior 1.5).
Rgb preview_dielectric_f0(const PreviewMaterial& m);
Rgb preview_diffuse_color(const PreviewMaterial& m);
// Whether the material uses KHR_materials_ior or KHR_materials_specular (a value not the default).
bool preview_has_specular_extension(const PreviewMaterial& m);

// The default grid, row by row: roughness 0, 0.05, 0.1, 0.2, ..., 1 (12 columns) for each of
// dielectric white, grey and dark, and the metals gold, copper and silver (6 rows).
std::vector<PreviewMaterial> preview_default_materials();
inline constexpr int kPreviewDefaultColumns = 12;

// ---- The request ----------------------------------------------------------------------------------

enum class PreviewBackground { Environment, Grey };
PreviewBackground preview_background_from_name(const std::string& name);  // "environment" | "grey"
const char* preview_background_name(PreviewBackground b);

struct PreviewSpec {
  EngineTarget target = EngineTarget::Generic;
  // A bake's output folder (`brdfbake bake --target T -o DIR`, its manifest.json and files); empty:
  // baked first, into a temporary folder, with the target's settings and the same environment.
  std::string bake;
  // With no `bake`: the folder the first bake is written to and kept (a new or empty folder), so
  // the files the preview rendered can be found; empty: a temporary folder removed after the render.
  std::string keep_bake;
  // The spheres: a material file (ours or glTF, as eval and tabulate read it, one sphere per
  // material); empty and `materials` empty: the default grid.
  std::string materials_file;
  std::vector<PreviewMaterial> materials;  // used as given when not empty (in-memory callers)
  int width = 512;
  int height = 512;
  int columns = 0;  // spheres per row; 0: 12 for the default grid, else about sqrt(n) (square cells)
  PreviewBackground background = PreviewBackground::Environment;
  // The camera: orthographic, looking along -Z of the environment's frame with +Y up at yaw = pitch
  // = 0; yaw turns it about +Y, then pitch about its right axis (degrees).
  double yaw = 0.0;
  double pitch = 0.0;
  // The reference render and the error (false: the split-sum render alone).
  bool reference = true;
  // The reference quadrature's refinement (kernels/preview.cl): a node of the environment's
  // quadtree is refined within refinement x its angular radius of the lobe's peak, down to the
  // lobe's width / refinement, and across the horizon of n. The bound is measured against twice it.
  double refinement = 4.0;
  // A sphere whose reference bound (relative RMS) exceeds this is integrated again at twice the
  // refinement, at most twice (0: never). The goal is 0.5 % a sphere; 0.4 % leaves a margin.
  double bound_goal = 0.004;
  // Every bound_stride-th pixel of each sphere (at least 16 a sphere) is rendered again at twice the
  // refinement: the reference's bound is measured on them.
  int bound_stride = 8;
  Precision precision = Precision::Fp32;
  // gltf, babylon: Babylon.js's PBRBRDFConfiguration.DEFAULT_MIX_IBL_RADIANCE_WITH_IRRADIANCE (true
  // in Babylon.js 8.46.2): the split-sum render mixes the reflection with the irradiance by alphaG as
  // Babylon.js does; false: as a scene that switched it off.
  bool mix_ibl_radiance_with_irradiance = true;
  // The error's two shares (docs/PREVIEW.md, "Engine share and bake share"): the target's shader
  // rendered once more from an ideal bake made in memory (every chain level converged at its own
  // roughness in float32 at a high face size, the DFG table at the texel centres' exact albedos in
  // float32, no storage), so that per sphere split-sum - reference = (split-sum - ideal) + (ideal -
  // reference). Needs the reference; false: not computed (the ideal bake's seconds saved).
  bool shares = true;
};

// ---- The result ---------------------------------------------------------------------------------

// Pixel (i, j) covers [i, i + 1) x [j, j + 1), row j = 0 at the top; its normal is taken at its
// centre (i + 0.5, j + 0.5). A pixel centre at (x, y) with d = ((x - centre_x), (y - centre_y)) /
// radius, |d| < 1, has the normal n = d.x right - d.y up + sqrt(1 - |d|^2) (-view_direction).
struct PreviewSphere {
  PreviewMaterial material;
  int row = 0, column = 0;
  double centre_x = 0.0, centre_y = 0.0;  // pixels
  double radius = 0.0;                    // pixels
};

struct PreviewCamera {
  Vec3 view_direction{0.0, 0.0, -1.0};  // the direction it looks along, in the environment's frame
  Vec3 up{0.0, 1.0, 0.0};
  Vec3 right{1.0, 0.0, 0.0};
  double yaw = 0.0, pitch = 0.0;  // degrees
  double background_fov = 60.0;   // degrees, vertical: the background is seen through a pinhole
};

// Linear RGB, row 0 (the top) first; pixels off the spheres hold the background.
struct PreviewImage {
  int width = 0, height = 0;
  std::vector<float> rgb;
};

// Over one sphere's pixels.
struct PreviewErrorStats {
  double rms = 0.0, p99 = 0.0, max = 0.0;
};
struct PreviewSphereStats {
  int pixels = 0;
  // |split-sum - reference| / |reference| (Euclidean norms of the RGB triples), linear radiance.
  PreviewErrorStats linear;
  // The largest difference of the three 8-bit sRGB channels after the sheet's exposure and tone map.
  PreviewErrorStats srgb8;
  // The reference's own error over the sphere, relative as `linear`: RMS and max over the bound's
  // sample pixels of |reference - reference at twice the refinement|, times kPreviewBoundFactor,
  // plus kPreviewBoundFloor.
  double reference_rms_bound = 0.0;
  double reference_max_bound = 0.0;
  int bound_pixels = 0;
  double refinement = 0.0;  // the refinement its reference was integrated at (spec.refinement, or more)
  // With spec.shares: the engine's share |ideal - reference| / |reference| (what no file can change:
  // the target's split-sum approximation rendered from an ideal bake) and the bake's share
  // |split-sum - ideal| / |reference| (what the files add: resolution, convergence, storage), per
  // pixel over the sphere as `linear`. The per-pixel difference images add up exactly to `linear`'s;
  // their RMS do not (the triangle inequality: |engine - bake| <= linear <= engine + bake).
  PreviewErrorStats engine_share;
  PreviewErrorStats bake_share;
};

// The shares of a group of spheres (the default grid's rows: one material, every roughness; a
// material file's spheres: one a group): the median and the worst sphere's relative RMS.
struct PreviewShareGroup {
  std::string name;
  std::vector<int> spheres;
  double error_median = 0.0, error_worst = 0.0;    // linear.rms
  double engine_median = 0.0, engine_worst = 0.0;  // engine_share.rms
  double bake_median = 0.0, bake_worst = 0.0;      // bake_share.rms
};
// A second-order quadrature's error at refinement r is about 4/3 of its difference to the result at
// 2r; the factor 2 leaves a margin for where the convergence is slower (kinks at texel edges).
inline constexpr double kPreviewBoundFactor = 2.0;
// Added to every sphere's bound: what no doubling of the refinement shows, and what an independent
// check resolves (docs/PREVIEW.md, "The bound"). Against Mitsuba 3 (16,384 samples a pixel, its noise
// removed) 13-14 of the default grid's 72 spheres differed from the reference by up to 0.045
// percentage points more than 2 x the refinement's difference stated (the roughness-0.05 metals
// stated 0.004 %, below what any check resolves); the float sums (1e-6-2e-5) and the environment's
// model (constant cells: an independent renderer interpolates the map) do not move with the
// refinement. 0.05 % covers the figure measured; added, not a minimum, since errors of separate
// sources add (|reference - truth| <= |reference - finer| + |finer - truth|).
inline constexpr double kPreviewBoundFloor = 5e-4;
// The largest refinement a render may use (spec.refinement's range, and the bound goal's reach).
inline constexpr double kPreviewMaxRefinement = 64.0;

struct PreviewTimes {
  double bake = 0.0;              // baking the folder first (0 with --bake)
  double read = 0.0;              // reading the bake's files
  double splitsum = 0.0;          // the split-sum render (host)
  double reference = 0.0;         // the reference render, wall
  double reference_device = 0.0;  // its kernels (event profiling)
  double bound = 0.0;             // the bound's second render, wall
  double ideal = 0.0;             // the ideal bake (spec.shares) and its split-sum render, wall
  double total = 0.0;
};

struct PreviewResult {
  PreviewSpec spec;  // as resolved (materials filled in, columns chosen)
  std::vector<PreviewSphere> spheres;
  PreviewCamera camera;
  PreviewImage splitsum;
  PreviewImage reference;                 // empty when spec.reference is false
  std::vector<PreviewSphereStats> stats;  // one per sphere (empty without the reference)
  // With spec.shares (and the reference): the ideal bake's split-sum render, what it holds, and the
  // shares per group.
  PreviewImage ideal;
  Metadata ideal_bake;
  std::vector<PreviewShareGroup> share_groups;
  double exposure = 0.0;            // EV of the sheet: 0.18 / the environment's median luminance,
                                    // at most 0.8 / the spheres' median (split-sum)
  double environment_median = 0.0;  // solid-angle-weighted median luminance
  std::string brdf;                 // the BRDF both renders use, in words
  bool multiscatter = false;        // multiple-scattering compensation applied
  std::string environment_model;    // the environment's continuous model of the reference
  std::string bound_definition;
  Metadata bake;     // the bake's settings (files, sizes, formats) and where it came from
  Metadata shading;  // per step of the target's shader: what it does and which function it is
  PreviewTimes times;
  std::string device;
};

using PreviewProgress = std::function<void(double fraction, const std::string& step)>;

// Renders the preview of `environment` (the map the bake was made from) on `backend`. Throws Error
// for a bake folder that does not hold the target's files, a material file it cannot read, sizes out
// of range; Cancelled at a progress report after a stop request (brdfbake/cancel.hpp).
// With no bake folder the target's files are baked first into a folder made in `scratch_dir` (""
// = the system's temporary folder) and removed when the render ends.
PreviewResult render_preview(Backend& backend, const EnvImage& environment, const PreviewSpec& spec,
                             const PreviewProgress& progress = {}, const std::string& scratch_dir = {});

// Limits: the image's sides, and the spheres.
inline constexpr int kPreviewMaxSize = 4096;
inline constexpr int kPreviewMaxSpheres = 1024;

}  // namespace brdfbake
