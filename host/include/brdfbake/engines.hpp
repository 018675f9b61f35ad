// Engine targets: what each engine loads as it is (docs/ENGINES.md). A target fixes the roughness
// schedule of the prefiltered chain, the face sizes, the pixel format, the SH convention and
// scaling, the orientation and the file set; write_engine_files() writes that file set, atomically,
// from what a bake produced (the prefiltered chain, the irradiance SH, the skybox cube).
//
//   generic         today's output: prefiltered.ktx2 (RGBA16F, linear schedule) + irradiance_sh.json
//   filament        what `cmgen -x DIR -f ktx` writes: DIR/NAME_ibl.ktx (R11F_G11F_B10F, the chain
//                   with the "sh" key), DIR/NAME_skybox.ktx, DIR/sh.txt; Filament's schedule
//   gltf            NAME.gltf with EXT_lights_image_based (RGBD PNG faces per level, 3 x 9 SH)
//   babylon         NAME.env, Babylon.js's own environment format (RGBD PNG faces, full chain)
//   khronos-viewer  the glTF-IBL-Sampler convention: KTX2 RGBA16F cubes, linear schedule, a
//                   Lambertian (irradiance) cube
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/io.hpp"

namespace brdfbake {

enum class EngineTarget { Generic, Filament, Gltf, Babylon, KhronosViewer };

// "generic" | "filament" | "gltf" | "babylon" | "khronos-viewer"; throws Error listing them.
EngineTarget engine_target_from_name(const std::string& name);
const char* engine_target_name(EngineTarget target);
std::vector<std::string> engine_target_names();

// How the irradiance SH is stored for a target.
enum class ShConvention {
  IrradianceOverPi,   // ours: c_lm = (A_l / pi) w_l L_lm, E(n)/pi = sum c_lm Y_lm(n) (docs/CONVENTIONS.md)
  FilamentPrescaled,  // Filament: 9 RGB, c_k = Y-constant_k (A_l / pi) w_l L_lm: E/pi = sum c_k poly_k(n)
  GltfIrradiance,     // EXT_lights_image_based as Babylon.js reads it: E_lm = A_l w_l L_lm in the basis
                      // with the Condon-Shortley phase (Babylon's SphericalHarmonics), 9 x RGB
  BabylonPolynomial,  // Babylon .env "irradiance": the spherical polynomial x..xy of
                      // SphericalPolynomial.FromHarmonics, E/pi = polynomial(n)
};

// Everything a target fixes. Text fields are what docs/ENGINES.md and the metadata say.
struct EngineSettings {
  EngineTarget target = EngineTarget::Generic;
  std::string engine;  // e.g. "Filament 1.9 (cmgen -x DIR -f ktx)"
  RoughnessSchedule schedule = RoughnessSchedule::Linear;
  std::string schedule_source;       // where the engine's mapping comes from
  std::string lod_formula;           // the engine's shader lookup
  int size = 256;                    // face size of level 0
  int min_size = 16;                 // smallest level's face size (1: the full chain)
  bool power_of_two = false;         // sizes must be powers of two
  PixelType pixel = PixelType::F16;  // container texels (PNG targets: RGBD 8-bit, see pixel_format)
  std::string pixel_format;          // e.g. "KTX1 GL_R11F_G11F_B10F"
  ShWindow sh_window = ShWindow::None;
  ShConvention sh_convention = ShConvention::IrradianceOverPi;
  std::string sh_description;
  std::string orientation;         // faces, rows, handedness notes
  std::vector<std::string> files;  // the file set, NAME standing for the base name
  bool skybox = false;             // the file set holds a skybox cube
  // What the preview's split-sum emulation of this target was held to: the engine and version that
  // rendered the target's files in the test suite, and the agreement measured (docs/ENGINES.md).
  std::string held_to;
  std::string held_to_short;  // the same in a line (the preview's sheet)
  // What of a bake the engine reads beside its chain and SH, and the preview's emulation of it: a
  // target whose engine samples its own DFG table (its sheen from that table's third channel) and has
  // no Charlie IBL reads neither the bake's DFG tables nor its Charlie tables and chain, so a plan for
  // it bakes none of them (Filament).
  bool reads_dfg_tables = true;
  bool reads_charlie = true;
};

EngineSettings engine_settings(EngineTarget target);

// ---- SH in each engine's convention (from our ShCoefficients, order >= 3) -------------------

using Rgb3 = std::array<double, 3>;
// Filament's 9 pre-scaled coefficients (the KTX1 "sh" key, sh.txt, IndirectLight::irradiance).
std::array<Rgb3, 9> filament_sh(const ShCoefficients& sh);
// EXT_lights_image_based irradianceCoefficients (9 x RGB, order l00, l1-1, l10, l11, l2-2, l2-1,
// l20, l21, l22).
std::array<Rgb3, 9> gltf_irradiance_coefficients(const ShCoefficients& sh);
// Babylon's spherical polynomial, in the order x, y, z, xx, yy, zz, yz, zx, xy.
std::array<Rgb3, 9> babylon_polynomial(const ShCoefficients& sh);
inline constexpr const char* kBabylonPolynomialNames[9] = {"x", "y", "z", "xx", "yy", "zz", "yz", "zx", "xy"};

// ---- Writing a target's files -------------------------------------------------------------------

// What a bake produced. The chain must have been baked with engine_settings(target).schedule (the
// writer checks the chain's "roughness_schedule" metadata and its sizes against the target).
struct EngineBake {
  const CubeLevels* prefiltered = nullptr;      // required: the GGX chain
  const ShCoefficients* sh = nullptr;           // required by every target (order >= 3)
  const CubeLevels* skybox = nullptr;           // optional: the skybox cube; default level 0 of the chain
  const CubeLevels* irradiance_cube = nullptr;  // khronos-viewer: the Lambertian cube (E/pi); optional
  const CubeLevels* charlie = nullptr;          // khronos-viewer: a Charlie chain for sheen; optional
};

// ASTC HDR compression of KTX2 chains (generic, khronos-viewer).
enum class AstcBlock { None, Astc4x4, Astc6x6 };

// The Babylon.js scene an EXT_lights_image_based light is written for (docs/ENGINES.md, "Row order
// and frame"): Babylon.js's default left-handed scene (rotation identity) or a right-handed one
// (scene.useRightHandedSystem; rotation (0, 1, 0, 0)). Both store the environment mirrored in x.
enum class GltfScene { LeftHanded, RightHanded };

struct EngineWriteOptions {
  std::string name;             // base name of the files; default: the folder's name (as cmgen -x)
  bool override_pixel = false;  // use `pixel` instead of the target's (containers only)
  PixelType pixel = PixelType::F16;
  AstcBlock astc = AstcBlock::None;              // generic / khronos-viewer: ASTC HDR KTX2 instead of RGBA16F
  double astc_quality = 60.0;                    // astcenc effort 0..100 (ASTCENC_PRE_MEDIUM)
  double intensity = 1.0;                        // gltf: the light's intensity
  GltfScene gltf_scene = GltfScene::LeftHanded;  // gltf: the scene it is for (frame, rotation)
};

// One file of a target's set with its size and its delivered error: the file's bytes decoded as the
// engine decodes them (io/gpu_cube_read.hpp: R11F_G11F_B10F, binary16, ASTC through astcenc, RGBD
// PNG through Babylon.js's fromRGBD) against the float values the bake computed before encoding
// (docs/CONVENTIONS.md, "Error figures": error_rms_rel, error_max_rel).
struct EngineFileEntry {
  std::string path;         // relative to the folder
  std::uint64_t bytes = 0;  // the file's size
  std::string format;       // its encoding ("R11F_G11F_B10F", "RGBA16F", "ASTC 4x4 SFLOAT", "PNG RGBD 8-bit", "text")
  std::string values;       // what its values are ("the prefiltered chain", "level 2, face +X", ...); empty: none
  bool measured = false;    // false: a file without texel values (JSON, text)
  double error_rms_rel = 0.0;  // over every R, G, B of the file
  double error_max_rel = 0.0;
  std::vector<double> error_rms_rel_per_level, error_max_rel_per_level;  // a chain's levels (one for an image)
};
// The definitions the manifest, the summary and the page give the two figures.
inline constexpr const char* kEngineErrorRmsRelDefinition =
    "sqrt(sum (decoded - value)^2 / sum value^2) over R, G, B of every texel: the file decoded as the engine "
    "decodes it against the float values baked before encoding";
inline constexpr const char* kEngineErrorMaxRelDefinition =
    "max over texels of max_c |decoded_c - value_c| / max(largest channel of the value, 1e-6 x the level's "
    "largest value)";

struct EngineWriteResult {
  std::vector<std::string> files;        // paths written, in the order above
  Metadata delivered;                    // each file's format and clamping (storage, compression)
  std::vector<EngineFileEntry> entries;  // each file's size and delivered error, in the order of `files`
};

// Writes the target's file set into `out_dir` (created if missing): every file goes to a temporary
// folder beside it and the folder's content is moved into place only when all are complete, so a
// failure leaves `out_dir` as it was. Throws Error for a bake that does not fit the target (a
// missing SH, a schedule or size the engine would read differently, values a format cannot hold).
EngineWriteResult write_engine_files(EngineTarget target, const EngineBake& bake, const std::string& out_dir,
                                     const EngineWriteOptions& options = {});

}  // namespace brdfbake
