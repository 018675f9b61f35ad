// Environment maps: loading HDR environments, the prefiltered radiance mip chain (GGX and Charlie),
// diffuse irradiance (spherical harmonics and an irradiance cube), and writing cubemaps.
// Conventions (face order and orientation, the equirect mapping, what a level holds, roughness
// schedules, the SH basis) are in docs/CONVENTIONS.md, "Environment maps", and in every output's
// metadata.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "brdfbake/device.hpp"
#include "brdfbake/io.hpp"
#include "brdfbake/table.hpp"

namespace brdfbake {

// ---- Environments ------------------------------------------------------------------------------

// Counts of the pixel values (per channel) that an environment may not hold.
struct EnvSanitizeReport {
  size_t nan = 0;
  size_t infinite = 0;
  size_t negative = 0;
  bool replaced = false;  // true when --sanitize replaced them (NaN, -inf and negatives by 0,
                          // +inf by the largest finite value of the image)
  size_t total() const { return nan + infinite + negative; }
};

// A loaded environment, linear RGB float: an equirectangular image (width = 2 height) or a cube
// (six square faces in KTX order +X, -X, +Y, -Y, +Z, -Z, row 0 first; width = height = face size).
struct EnvImage {
  enum class Layout { Equirect, Cube };
  Layout layout = Layout::Equirect;
  int width = 0;
  int height = 0;
  std::vector<float> rgb;   // equirect: width x height x 3, row 0 first; cube: 6 x size x size x 3
  std::string source;       // the file, files or builtin:NAME it came from
  std::string description;  // e.g. "equirect 1024x512 (OpenEXR, tiled, mip-mapped: level 0 read)"
  EnvSanitizeReport sanitize;
  // What reading changed or assumed that the user should hear of, one line each, e.g. "'sky.png':
  // 8-bit sRGB (its sRGB chunk) decoded to linear" (the commands print them, jobs record them).
  std::vector<std::string> notes;
};

struct EnvLoadOptions {
  bool sanitize = false;     // replace NaN, infinite and negative values instead of refusing them
  int builtin_width = 1024;  // equirect width of builtin:NAME (height = width / 2)
  // The memory an input image may take decoded (float32, every channel and copy), checked from its
  // header before any pixel buffer is allocated; 0: default_memory_budget().
  std::uint64_t memory_budget = 0;
};

// The default memory budget for input images: half of the memory this process may use (the
// machine's physical memory, or the cgroup's memory.max where that is lower).
std::uint64_t default_memory_budget();

// The largest environment, in pixels (16384 x 16384), files and in-memory arrays alike.
constexpr std::uint64_t kMaxEnvironmentPixels = std::uint64_t(1) << 28;
// Throws Error naming the limit when an equirect of width x height from `source` has more pixels than
// kMaxEnvironmentPixels, or when its float32 RGB pixels, held twice while they are taken in, pass
// the memory budget (options.memory_budget, else default_memory_budget()). For callers that hold
// the pixels in another form first (a NumPy array, which may be a broadcast view of one value):
// checked on the shape, before anything is allocated.
void check_environment_size(std::uint64_t width, std::uint64_t height, const std::string& source,
                            const EnvLoadOptions& options = {});
// "512MiB", "8GiB", "1.5G", "1000000" (bytes); K, M, G, T and KiB..TiB are powers of 1024, KB..TB
// of 1000. Throws Error naming the value for anything else, zero or more than 2^60.
std::uint64_t parse_byte_size(const std::string& text);

// Loads an environment:
//   FILE.hdr / FILE.exr / FILE.png (read directly; any other format OpenImageIO reads through the
//     lazily loaded OpenImageIO module, brdfbake_oiio.so; integer-coded values decoded to linear
//     from the file's colour encoding, said in EnvImage::notes; a FIFO or a device is refused,
//     docs/RELIABILITY.md, "Special files"): equirect if 2:1, horizontal cross if 4:3,
//     vertical cross if 3:4 (docs/CONVENTIONS.md); tiled and mip-mapped files read level 0;
//   FILE.ktx2: a cubemap (faceCount 6, RGBA16F/32F, level 0);
//   "PX,NX,PY,NY,PZ,NZ" (six files, comma separated) or a path holding "{face}" (replaced by px,
//     nx, py, ny, pz, nz): six square face images;
//   builtin:studio, builtin:sun: procedural environments (builtin_environment).
// Throws Error with a clear message for a missing, truncated, corrupt or unsupported file, a
// non-2:1 (and non-cross) image, faces of different sizes, and (unless options.sanitize) NaN,
// infinite or negative values, naming how many of each.
EnvImage load_environment(const std::string& spec, const EnvLoadOptions& options = {});
// An equirect already in memory (the Python package's NumPy arrays): width = 2 height, width x
// height x 3 linear RGB floats, row 0 first. Checked (and with options.sanitize, repaired) as
// load_environment checks a file; `source` names it in messages and metadata.
EnvImage environment_from_equirect(int width, int height, std::vector<float> rgb, const std::string& source,
                                   const EnvLoadOptions& options = {});

// The files an environment spec names: one, or six faces; none for builtin:NAME. Throws Error for
// a list of face files that is not six.
std::vector<std::string> environment_files(const std::string& spec);

// Checks cheaply, without reading pixels, that `spec` names something load_environment can open
// (a known builtin, existing readable files): commands call it before slow work.
void check_environment_source(const std::string& spec);
// A builtin:NAME environment names a builtin (nothing else is checked: no file is touched). Throws
// Error naming the builtins. Jobs check it when they are validated, before they are accepted.
void check_builtin_environment(const std::string& spec);

// The built-in environments, as equirects of width x width/2:
//   studio: soft area lights (three rectangular softboxes and a ring light) over a grey gradient;
//   sun:    a clear sky gradient over dark ground, a sun of 0.5 degree radius (2.4e-4 sr) and
//           radiance 5e4 carrying about 80% of the energy, and a faint aureole around it.
// Throws Error for an unknown name (listing the known ones).
EnvImage builtin_environment(const std::string& name, int width = 1024);
std::vector<std::string> builtin_environment_names();

// ---- Cubemaps ----------------------------------------------------------------------------------

// A float RGBA cubemap with levels: level l has faces of max(1, size >> l) texels a side, stored
// face after face in KTX order, each row after row (row 0 first), alpha 1.
struct CubeLevels {
  int size = 0;
  std::vector<std::vector<float>> levels;
  Metadata metadata;

  int level_count() const { return static_cast<int>(levels.size()); }
  int level_size(int level) const { return size >> level > 0 ? size >> level : 1; }
  float* texel(int level, int face, int i, int j) {
    const size_t s = static_cast<size_t>(level_size(level));
    return &levels[static_cast<size_t>(level)]
                  [4 * ((static_cast<size_t>(face) * s + static_cast<size_t>(j)) * s + static_cast<size_t>(i))];
  }
  const float* texel(int level, int face, int i, int j) const {
    const size_t s = static_cast<size_t>(level_size(level));
    return &levels[static_cast<size_t>(level)]
                  [4 * ((static_cast<size_t>(face) * s + static_cast<size_t>(j)) * s + static_cast<size_t>(i))];
  }
  void set_meta(const std::string& key, const std::string& value);
  std::string meta(const std::string& key) const;
};

// Output containers of a cubemap.
enum class CubeFormat {
  Ktx2,       // KTX 2.0, faceCount 6, every level, RGBA16F or RGBA32F, key/value metadata
  Ktx1,       // KTX 1.1 (what Filament loads), GL_RGBA16F / GL_RGBA32F, every level
  Dds,        // DDS with the DX10 header (DXGI_FORMAT_R16G16B16A16_FLOAT / R32G32B32A32_FLOAT)
  DdsLegacy,  // DDS with the legacy header only (D3DFMT_A16B16G16R16F = 113 / A32B32G32R32F = 116)
  Directory,  // a folder of images per level (CubeImageLayout), plus a JSON of the metadata
};
enum class CubeImageLayout { Faces, HorizontalCross, VerticalCross, Equirect };
enum class CubeImageFormat { Exr, Hdr };

struct CubeWriteOptions {
  PixelType pixel = PixelType::F16;                     // containers: RGBA16F or RGBA32F; R11G11B10: .ktx, .dds only
  CubeImageLayout layout = CubeImageLayout::Faces;      // Directory only
  CubeImageFormat image_format = CubeImageFormat::Exr;  // Directory only (.exr float, .hdr RGBE)
  std::string stem = "level";                           // Directory only: file name prefix
};

// .ktx2, .ktx, .dds; anything else (an existing folder, or a path ending in '/') is a Directory.
CubeFormat cube_format_from_path(const std::string& path);
// Writes all levels. Containers are written atomically; a Directory is filled in a temporary
// folder beside it and renamed into place, so a failure leaves no partial output.
void write_cubemap(const CubeLevels& cube, const std::string& path, CubeFormat format,
                   const CubeWriteOptions& options = {});
// Reads level `level` of a cubemap KTX2 file (RGBA16F/32F) as an RGB cube environment.
EnvImage read_ktx2_cube(const std::string& path, int level = 0);

// ---- Prefiltered radiance ---------------------------------------------------------------------

enum class EnvDistribution { Ggx, Charlie };
EnvDistribution env_distribution_from_name(const std::string& name);  // "ggx" | "charlie"
const char* env_distribution_name(EnvDistribution d);

// The perceptual roughness of level l of L, t = l / (L - 1):
//   linear:   roughness = t              lod = (L - 1) roughness            (Khronos; the default)
//   filament: roughness = 1 - sqrt(1 - t)  lod = (L - 1) roughness (2 - roughness)   (Filament)
//   sqrt:     roughness = t^2            lod = (L - 1) sqrt(roughness)
//   babylon:  Babylon.js's .env chain (HDRFiltering), a full chain down to 1x1 so that the face
//             size is S = 2^(L - 1): level 0 the mirror, level l >= 1 has GGX alpha
//             2^(l / 0.8) / S (roughness = sqrt(alpha), capped at 1); the shader's lookup is
//             lod = 0.8 log2(S (roughness^2 + 0.0005)) (getLodFromAlphaG with Babylon's
//             MINIMUMVARIANCE 0.0005, lodGenerationScale 0.8), clamped to [0, L - 1]. It is the
//             inverse of the schedule up to that 0.0005 and the cap, as in Babylon itself.
enum class RoughnessSchedule { Linear, Filament, Sqrt, Babylon };
RoughnessSchedule roughness_schedule_from_name(const std::string& name);
const char* roughness_schedule_name(RoughnessSchedule s);
double schedule_roughness(RoughnessSchedule s, int level, int levels);
double schedule_lod(RoughnessSchedule s, double roughness, int levels);  // the inverse (see babylon)
// Babylon.js's lodGenerationScale of .env files and of its own prefiltering (HDRFiltering), and
// its shader's MINIMUMVARIANCE added to roughness^2 before the lookup.
inline constexpr double kBabylonLodGenerationScale = 0.8;
inline constexpr double kBabylonMinimumVariance = 0.0005;
// The shader formula of the inverse, e.g. "lod = (levels - 1) * roughness".
std::string schedule_lod_formula(RoughnessSchedule s);

// How a level's lobe integral is evaluated (docs/CONVENTIONS.md, "Environment maps"):
//   quadrature: deterministic hierarchical quadrature over a solid-angle pyramid of the source,
//               refined where the lobe varies (the default: no noise, < 1% RMS against the reference);
//   sampling:   importance sampling of the lobe at Hammersley points with filtered importance
//               sampling (Krivanek & Colbert 2008) from a mip chain, --samples per texel.
// Both add the bright texels exactly (environment sampling; see PrefilterSpec::bright_texels).
enum class EnvEstimator { Quadrature, Sampling };
EnvEstimator env_estimator_from_name(const std::string& name);  // "quadrature" | "sampling"
const char* env_estimator_name(EnvEstimator e);

// Limits: the largest level-0 face, and the most lobe samples per texel of the sampling estimator.
inline constexpr int kPrefilterMaxSize = 2048;
inline constexpr int kPrefilterMaxSamples = 1 << 16;

struct PrefilterSpec {
  int size = 256;     // face size of level 0 (the source cube, the mirror)
  int min_size = 16;  // the smallest level's face size (levels size, size/2, ..., >= min_size)
  EnvDistribution distribution = EnvDistribution::Ggx;
  RoughnessSchedule schedule = RoughnessSchedule::Linear;
  EnvEstimator estimator = EnvEstimator::Quadrature;
  int samples = 0;         // sampling: lobe samples per texel of every level; 0: 1024
  double max_error = 0.0;  // > 0: samples (sampling) or refinement (quadrature) per level from
                           // measurement (see prefilter.cpp)
  Precision precision = Precision::Fp32;
  // Quadrature: a pyramid texel of angular size h is refined when it lies within refinement * h of
  // R; the finest level used for the lobe's core has h <= lobe width / core_refinement; across the
  // horizon, texels are refined while h > horizon_texel (radians) where the kink matters.
  double refinement = 4.0;
  double core_refinement = 4.0;
  double horizon_texel = 0.1;
  // Quadrature: blocks of 8 x 8 texels share one walk of the pyramid, refined for every texel of
  // the block (each texel's partition is its own or finer; kernels/prefilter.cl) on levels whose
  // size is a multiple of 8; false: a walk per texel (the former path, kept as the reference).
  bool strips = true;
  // Estimator switches (defaults are the tool's; the bench turns them off to measure them):
  bool filtered_importance_sampling = true;  // false: every sample reads the source level
  double lod_bias = 0.0;                     // added to the filtered-importance-sampling lod
                                             // (Krivanek & Colbert use 1; 0 measured better here)
  int bright_texels = -1;                    // environment sampling: the brightest texels summed explicitly;
                                             // -1: automatic (up to kDefaultBrightTexels), 0: off
  double clamp_luminance = 0.0;              // > 0: opt-in, biased: compress source luminance above it
};

// Resolves defaults and validates: sizes >= 1, min_size <= size, samples >= 0, max_error finite,
// clamp >= 0. Non-power-of-two sizes are accepted (levels are max(1, size >> l) a side).
PrefilterSpec resolve_prefilter_spec(const PrefilterSpec& spec);
// The number of output levels and their face sizes.
int prefilter_level_count(const PrefilterSpec& spec);

struct PrefilterTiming {
  double device_seconds = 0.0;  // every kernel (conversion, mips, filtering)
  double wall_seconds = 0.0;
  std::vector<double> level_device_seconds;  // the filtering of each level (level 0: conversion)
  // With max_error: per level, the RMS relative luminance difference between its two finest
  // estimates, and the largest of them (the chain's measured bound); empty / -1 otherwise.
  std::vector<double> measured_error_per_level;
  double measured_error = -1.0;
  // Wall seconds of each host-side stage in order ("convert", "bright texels", "pyramid",
  // "level 1", ...), for bench/startup_stages: where the time of a chain goes.
  std::vector<std::pair<std::string, double>> stage_seconds;
};

// Progress: fraction done (0..1) and a short label ("level 2/4").
using EnvProgress = std::function<void(double, const std::string&)>;

// Converts `env` to a cube of `size` on the device (equirect: k x k supersampled bilinear per
// texel; cube: resampled when the sizes differ). Level 0 of every prefiltered output.
CubeLevels environment_to_cube(Device& device, const EnvImage& env, int size, double* device_seconds = nullptr);

// The whole chain: conversion, source mips, every level. Output metadata: conventions, schedule,
// roughness per level, samples per level, estimator, device. `source_done`, where given, is called
// once the environment's pixels are no longer read (after the conversion to a cube), so that a
// caller who owns them can free them before the levels are filtered (a 4k map holds 96 MiB); only
// env's source, description and sanitize report are read after it.
CubeLevels prefilter_environment(Device& device, const EnvImage& env, const PrefilterSpec& spec,
                                 PrefilterTiming* timing = nullptr, const EnvProgress& progress = {},
                                 const std::function<void()>& source_done = {});
class Backend;
// The whole chain on a backend (brdfbake/backend.hpp): its OpenCL device (as above) or the scalar
// reference (prefilter_environment_reference; source_done is not called).
CubeLevels prefilter_environment(Backend& backend, const EnvImage& env, const PrefilterSpec& spec,
                                 PrefilterTiming* timing = nullptr, const EnvProgress& progress = {},
                                 const std::function<void()>& source_done = {});
// The same from a source cube already at spec.size (level 0 of `source`).
CubeLevels prefilter_cube(Device& device, const CubeLevels& source, const PrefilterSpec& spec,
                          PrefilterTiming* timing = nullptr, const EnvProgress& progress = {});

// The same chain by the scalar double reference (host/src/families/prefilter/reference.cpp): the
// environment converted to a cube by brute force (every texel the solid-angle-weighted mean of the
// source's bilinear interpolation over q x q sub-cells), and every level l >= 1 the lobe integral
// over every source texel split into sub-cells (brdfbake/reference/envmap.hpp, prefilter_cube), in
// double, stored as float. The estimator and its settings (samples, refinement, max_error, bright
// texels) do not apply; clamp_luminance does. The metadata has the keys of prefilter_environment's
// with the reference's values (estimator "reference", device "reference (scalar double)").
// Practical on small cubes only: the work, sum over levels of (output texels) x (source sub-cells),
// grows like size^4; a request above kPrefilterReferenceMaxWork lobe evaluations (a few seconds on
// two cores) throws Error naming the limit and suggesting an OpenCL device.
inline constexpr double kPrefilterReferenceMaxWork = 6e8;
CubeLevels prefilter_environment_reference(const EnvImage& env, const PrefilterSpec& spec,
                                           PrefilterTiming* timing = nullptr, const EnvProgress& progress = {});
// The lobe evaluations prefilter_environment_reference would make for a spec (resolved).
double prefilter_reference_work(const PrefilterSpec& spec);

// The default number of explicitly summed bright texels, and the luminance ratio to the mean
// above which a texel counts as bright.
inline constexpr int kDefaultBrightTexels = 256;
inline constexpr double kBrightRatio = 16.0;

// A texel of level 0 that environment sampling sums explicitly.
struct BrightTexel {
  int face = 0, i = 0, j = 0;
  float rgb[3] = {0, 0, 0};
};
// The bright texels of level 0 of `cube`: those whose luminance (0.2126 R + 0.7152 G + 0.0722 B)
// exceeds both ratio x the mean luminance (solid-angle weighted) and the luminance of the
// (max_count + 1)-th brightest texel, so that at most max_count are chosen and equal texels are
// never split (a flat area light is taken whole or not at all). Sorted by face, row, column.
std::vector<BrightTexel> find_bright_texels(const CubeLevels& cube, int max_count, double ratio = kBrightRatio);
// The bright texels of a cube of face size `size` as points for an exact sum: each texel's bilinear
// footprint (the tent over +-1 texel that seamless bilinear interpolation gives it, continued onto
// the neighbouring face past an edge) split into (2 q)^2 sub-cells, each with its unit direction and
// value L * tent * exact solid angle * scale. Structure of arrays x, y, z, r, g, b, each padded with
// zero-valued points to a multiple of 8 (and at least 8); *count is the number of real points.
std::vector<double> bright_texel_points(const std::vector<BrightTexel>& bright, int size, int q, double scale,
                                        int* count);

// ---- Irradiance ---------------------------------------------------------------------------------

// None; Sloan's fixed hanning and lanczos windows of width `order`; Auto: cmgen's default deringing
// (`--sh-window auto`), sinc^4 with the widest cutoff that keeps the irradiance non-negative, chosen
// from the coefficients (host/src/sh_window.cpp).
enum class ShWindow { None, Hanning, Lanczos, Auto };
ShWindow sh_window_from_name(const std::string& name);  // "none" | "hanning" | "lanczos" | "auto"
const char* sh_window_name(ShWindow w);

// Limits: the largest irradiance cube face and source cube face.
inline constexpr int kIrradianceMaxCube = 1024;
inline constexpr int kIrradianceMaxSource = 2048;

struct IrradianceSpec {
  int sh_order = 3;  // bands: 3 (9 coefficients) or 5 (25)
  ShWindow window = ShWindow::None;
  int cube_size = 32;     // the irradiance cube's face size; 0: no cube
  int source_size = 256;  // the cube the environment is converted to first
  Precision precision = Precision::Fp32;
};

struct ShCoefficients {
  int order = 0;                           // bands
  std::vector<double> radiance;            // L_lm, order^2 x RGB
  std::vector<double> irradiance_over_pi;  // (A_l / pi) w_l L_lm: E(n) / pi = sum c_lm Y_lm(n)
  ShWindow window = ShWindow::None;
  std::vector<double> window_weights;  // w_l per band
  double window_cutoff = 0.0;          // ShWindow::Auto: the chosen sinc^4 cutoff, in bands
  std::string projection;              // how L_lm was computed (recorded in the JSON)
};

struct IrradianceResult {
  ShCoefficients sh;
  CubeLevels cube;  // one level of cube_size, texels E / pi
  double device_seconds = 0.0;
};

// The SH (project_sh, on the host) and, when spec.cube_size > 0, the irradiance cube (on the
// device, from the environment converted to a cube of spec.source_size). With cube_size 0 the
// device is not used at all.
IrradianceResult compute_irradiance(Device& device, const EnvImage& env, const IrradianceSpec& spec,
                                    const EnvProgress& progress = {});
class Backend;
// The same on a backend (brdfbake/backend.hpp): SH on the host and the cube on its OpenCL device
// (its device opened only for a cube), or the scalar reference (compute_irradiance_reference).
IrradianceResult compute_irradiance(Backend& backend, const EnvImage& env, const IrradianceSpec& spec,
                                    const EnvProgress& progress = {});
// The SH projection of an environment on the host, in double precision, without a device: an
// equirect exactly as its pixels define it (each constant over its cell, integrated against the
// basis), a cube at its texel centres with their exact solid angles. order 3 or 5.
ShCoefficients project_sh(const EnvImage& env, int order, ShWindow window = ShWindow::None);

// The same by the scalar double reference (host/src/families/irradiance/reference.cpp): the source
// cube converted by brute force (as prefilter_environment_reference), the SH coefficients projected
// over every source sub-cell (brdfbake/reference/envmap.hpp, sh_project), the irradiance cube by
// direct cosine convolution over every source sub-cell (irradiance_directions). Same result type and
// cube metadata keys as compute_irradiance, device "reference (scalar double)". Practical on small
// cubes only: above kIrradianceReferenceMaxSourceSize, or above kIrradianceReferenceMaxWork cosine
// terms for the cube (cube texels x source sub-cells, a few seconds on two cores), it throws Error
// naming the limit and suggesting an OpenCL device.
inline constexpr int kIrradianceReferenceMaxSourceSize = 512;
inline constexpr double kIrradianceReferenceMaxWork = 4e9;
IrradianceResult compute_irradiance_reference(const EnvImage& env, const IrradianceSpec& spec,
                                              const EnvProgress& progress = {});
// The window weights w_l, l < order: hanning 0.5 (1 + cos(pi l / order)), lanczos sinc(l / order).
// Not for ShWindow::Auto (its weights depend on the coefficients: apply_sh_window).
std::vector<double> sh_window_weights(ShWindow w, int order);
// sinc(pi l / cutoff)^4 for l < cutoff, 0 beyond (cmgen's window of `cutoff` bands).
std::vector<double> sh_sinc4_window_weights(double cutoff, int order);
// The minimum over the unit sphere of sum c_k Y_k (one channel, order^2 coefficients).
double sh_minimum(const std::vector<double>& coefficients, int order);
// Sloan's estimate of that minimum for 3 bands (9 coefficients), as cmgen decides "negative" with
// it: exact when band 2 is zonal about the linear part's axis; otherwise each band-2 part is taken at
// its own worst phase, an estimate that may lie below the minimum (cmgen's deringing is stronger).
double sh_minimum_estimate(const std::vector<double>& coefficients);
// cmgen's automatic cutoff for unwindowed irradiance coefficients (order^2 x RGB): per channel, the
// widest cutoff in [order, 4 order + 1] (bisection to 0.1 band) whose windowed function is nowhere
// negative (by sh_minimum_estimate for 3 bands, as cmgen; by sh_minimum for 5); the smallest over
// the channels.
double sh_auto_window_cutoff(const std::vector<double>& irradiance, int order);
// Fills sh.irradiance_over_pi = (A_l / pi) w_l L_lm from sh.radiance and sh.order, with the weights
// of `window` (for Auto, chosen from the unwindowed irradiance; the cutoff in sh.window_cutoff).
void apply_sh_window(ShCoefficients& sh, ShWindow window);
// JSON text of the coefficients with the basis and conventions, and `metadata`.
std::string sh_to_json(const ShCoefficients& sh, const Metadata& metadata);
// Writes the JSON atomically.
void write_sh_json(const ShCoefficients& sh, const Metadata& metadata, const std::string& path);

}  // namespace brdfbake
