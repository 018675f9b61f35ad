// Fresnel reflectance tables: every model a renderer uses, exact and approximate, baked on an
// OpenCL device (kernels/fresnel.cl) or by the scalar double reference, with what each
// approximation costs in error against the exact equations (the family fresnel:
// host/src/families/fresnel/, host/reference/src/fresnel.cpp).
//
// Tables (docs/CONVENTIONS.md, "Fresnel tables"):
//   1-D: width cells over cos_theta, one row, channels r, g, b.
//   2-D: cos_theta x F0 (schlick, f82-tint) or cos_theta x IOR (schlick-ior, dielectric), one
//        channel f; the y axis is the parameter the model takes from the row.
// cos_theta = (i + 0.5) / width (cell centres), or i / (width - 1) with `endpoints` so that 0 and 1
// are cells. The same rule places the y axis inside its range.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "brdfbake/device.hpp"
#include "brdfbake/material_presets.hpp"
#include "brdfbake/math/types.hpp"
#include "brdfbake/table.hpp"

namespace brdfbake {

enum class FresnelModel {
  Schlick,          // Schlick 1994: F0 + (F90 - F0)(1 - cos)^5
  SchlickMetallic,  // Schlick with F0 = mix(dielectric_f0, base_color, metallic) (Burley 2012, glTF)
  SchlickIor,       // Schlick with F0 = ((n1 - n2) / (n1 + n2))^2
  Dielectric,       // exact, real IOR, both directions (total internal reflection)
  Conductor,        // exact, complex IOR n + ik per channel
  F82Tint,          // Schlick with Hoffman's F82 tint (OpenPBR metal)
  Empirical,        // the Cg tutorial rim term clamp(bias + scale (1 - cos)^power, 0, 1)
};
// "schlick" | "schlick-metallic" | "schlick-ior" | "dielectric" | "conductor" | "f82-tint" |
// "empirical"; throws Error naming the choices otherwise.
FresnelModel fresnel_model_from_name(const std::string& name);
const char* fresnel_model_name(FresnelModel model);
// Every model, in the order above.
const std::vector<FresnelModel>& fresnel_models();
// Whether a model is an exact solution of the Fresnel equations (dielectric, conductor).
bool fresnel_model_is_exact(FresnelModel model);

enum class FresnelTableKind { OneD, TwoD };
FresnelTableKind fresnel_table_kind_from_name(const std::string& name);  // "1d" | "2d"
const char* fresnel_table_kind_name(FresnelTableKind kind);

// What to tabulate. Give either `material` (a preset of material_presets()) or the
// model's own parameters; each parameter belongs to the models named beside it, and giving one to
// another model is an error. An RGB parameter with equal channels is a grey one.
//
// From a material the models take: schlick F0 = the exact F0; schlick-metallic: conductors
// base_color = exact F0, metallic 1, dielectrics metallic 0 (F0 = dielectric_f0, glTF's 0.04: the
// constant the workflow assumes); schlick-ior and dielectric the preset's n (dielectrics only);
// conductor n, k; f82-tint F0 and the fitted tint (fit_conductor). `empirical` takes no
// material.
struct FresnelSpec {
  FresnelModel model = FresnelModel::Schlick;
  std::string material;

  std::optional<Rgb> f0;                     // schlick, f82-tint: in [0, 1]
  std::optional<Rgb> f90;                    // schlick: in [0, 1] (default 1)
  std::optional<Rgb> f82_tint;               // f82-tint: >= 0 (1 is plain Schlick)
  std::optional<Rgb> base_color;             // schlick-metallic: in [0, 1]
  std::optional<double> metallic;            // schlick-metallic: in [0, 1]
  std::optional<double> dielectric_f0;       // schlick-metallic: in [0, 1] (default 0.04)
  std::optional<Rgb> ior;                    // schlick-ior, dielectric: index of the far side, > 0
  std::optional<double> ior_outside;         // schlick-ior, dielectric: > 0 (default 1, air)
  std::optional<Rgb> n;                      // conductor: real part of the index, > 0
  std::optional<Rgb> k;                      // conductor: extinction coefficient, >= 0
  std::optional<double> bias, scale, power;  // empirical: finite, power >= 0

  FresnelTableKind table = FresnelTableKind::OneD;
  int size = 256;          // cells along cos_theta
  int height = 0;          // 2-D: cells along the y axis (0: same as size)
  bool endpoints = false;  // cos_theta (and y) include both ends of their range as cells
  // 2-D: the y range, default [0, 1] for F0 and [1, 3] for IOR.
  std::optional<std::pair<double, double>> range;
  Precision precision = Precision::Fp32;
  // When non-empty, evaluate at these cosines instead of the grid (tests, edge cases); `size`
  // and `endpoints` are then ignored.
  std::vector<double> cos_theta;
};

// Largest index (n, k, IOR) accepted: far beyond any measured material at visible wavelengths,
// and small enough that no intermediate of the kernels' arithmetic overflows in fp32.
inline constexpr double kFresnelMaxIndex = 1000.0;
// Most cells in one table (the output alone is 192 MiB at this size).
inline constexpr long long kFresnelMaxCells = 1ll << 24;

// Throws Error with a one-line message for anything the bake would reject: unknown material,
// missing or foreign parameters, values out of range or not finite, bad sizes or ranges.
void validate_fresnel_spec(const FresnelSpec& spec);

// The exact model for the same material or index: the conductor for conductor presets (and for
// n, k), the dielectric for dielectric presets and for an IOR pair. Throws Error where the spec
// names no material (an F0 alone, base colour, empirical parameters). The result tabulates the
// same cosines as `spec`, as a 1-D table.
FresnelSpec exact_fresnel_spec(const FresnelSpec& spec);

struct FresnelTiming {
  // Kernel time from OpenCL event profiling. The output buffer is filled (made resident) by a
  // separate command first, so a CPU device's first-touch page faults are not counted here.
  double device_seconds = 0.0;
  double wall_seconds = 0.0;  // the whole call: program build, transfers, fill, kernel
};

class Backend;

// Bakes on a backend (brdfbake/backend.hpp): its OpenCL device or the scalar reference.
Table bake_fresnel(Backend& backend, const FresnelSpec& spec, FresnelTiming* timing = nullptr);
// Bakes on an OpenCL device in spec.precision.
Table bake_fresnel(Device& device, const FresnelSpec& spec, FresnelTiming* timing = nullptr);
// Evaluates the scalar double reference at the same cells (spec.precision is ignored).
Table bake_fresnel_reference(const FresnelSpec& spec, FresnelTiming* timing = nullptr);

// The error of `approx` against `exact` (same shape, same channels): max and mean |approx - exact|
// over every cell and channel, and where the max is.
struct FresnelError {
  double max_abs = 0.0;
  double mean_abs = 0.0;
  double x_at_max = 0.0;  // cos_theta of the worst cell
  int row_at_max = 0;
  int channel_at_max = 0;
};
FresnelError fresnel_error(const Table& approx, const Table& exact);

// `table` with one more column per channel: err_<channel> = table - exact, signed (approximation
// minus exact), after the value columns (`brdfbake fresnel --vs exact`).
Table with_error_columns(const Table& table, const Table& exact);

// ---- What each approximation costs, for one material -------------------------------------------

struct FresnelModelReport {
  FresnelModel model;
  std::string setting;            // how the model was set from the material
  Rgb max_abs;                    // per channel, max |model - exact| over the cosine grid
  Rgb mean_abs;                   // per channel, mean |model - exact|
  double worst = 0.0;             // the largest of max_abs
  double cos_at_worst = 0.0;      // where it occurs
  double cells_per_second = 0.0;  // device evaluation rate (RGB cells), 0 when not measured
  double device_seconds = 0.0;    // the median kernel time behind the rate
};
struct FresnelComparison {
  std::string material;
  FresnelModel exact_model;  // conductor or dielectric
  int grid = 0;              // cosines of the error grid, [0, 1] with both ends
  int rate_cells = 0;        // cells of the table the rates were measured on
  std::string device;        // "" when the rates were not measured
  std::vector<FresnelModelReport> rows;
};
// Cosines of the error grids of compare_fresnel_models and fit_conductor: [0, 1] with both ends.
inline constexpr int kFresnelErrorGrid = 4097;
struct FresnelCompareOptions {
  int grid = kFresnelErrorGrid;
  int rate_cells = 1 << 20;  // 0: do not measure rates
  int rate_runs = 5;         // timed runs after a warm-up; the median is kept
  Precision precision = Precision::Fp32;
  // The empirical model's parameters (grey, as the Cg tutorial's); unset, bias = the mean of the
  // exact F0's channels, scale = 1 - bias, power = 5: a grey Schlick.
  std::optional<double> bias, scale, power;
};
// Every model set for `material` (a preset name), against the material's exact model, with its
// device rate when `device` is given. Throws Error for an unknown material.
FresnelComparison compare_fresnel_models(const std::string& material, Device* device,
                                         const FresnelCompareOptions& options = {});

// ---- Conversions ---------------------------------------------------------------------------------

// A conductor's (n, k) -> the Schlick F0 that matches it at normal incidence and the F82 tint that
// matches it at cos = 1/7, with the error each leaves against the exact conductor of the scalar
// reference (max |approx - exact| per channel over kFresnelErrorGrid cosines).
struct ConductorFit {
  Rgb f0;
  Rgb f82_tint;
  Rgb schlick_max_error;
  Rgb f82_max_error;
};
ConductorFit fit_conductor(const Rgb& n, const Rgb& k);

// F0 values that shaders commonly hard-code for a material, with where each comes from: the
// preset's own (Real-Time Rendering 4th ed.) and the older values still in circulation
// (Hoffman 2010's course-notes table, from Real-Time Rendering 3rd ed.).
struct HardCodedF0 {
  Rgb f0;
  std::string source;
};
std::vector<HardCodedF0> hard_coded_f0(const MaterialPreset& preset);

}  // namespace brdfbake
