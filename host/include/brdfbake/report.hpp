// `brdfbake report`: the accuracy-against-time sweep for chosen kinds on a chosen device, as a
// self-contained HTML page (inline SVG plots, no network resources) and a JSON of the numbers.
//   DFG kinds (ggx, ggx-multiscatter, charlie): every estimator over its sample counts against the
//     converged reference (brdfbake/accuracy.hpp), device time from event profiling;
//   fresnel: every model against the exact one for a few measured materials, with device rates;
//   prefilter: the error and device time of each level of a small chain against the brute-force
//     reference, for both estimators;
//   bake: what each bake setting costs at the level of the render (report/bake_sweep.cpp): for each
//     target, its default bake and one setting changed at a time (cube size, min size, schedule, DFG
//     size and axis, pixel, SH order, the chain's max error), each baked as `brdfbake bake` does
//     (wall time, bytes written) and rendered by the preview's split-sum against one reference
//     render per target (docs/REPORT.md).
// The page states the machine's load, which the times depend on (docs/BENCHMARKS.md).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "brdfbake/accuracy.hpp"
#include "brdfbake/device.hpp"
#include "brdfbake/fresnel.hpp"

namespace brdfbake {

// The sample counts of the report's DFG sweep: the full sweep's without its slowest counts.
inline const std::vector<int> kReportCounts = {16, 32, 64, 128, 256, 384, 512, 768, 1024, 2048, 4096};

// The bake sweep's choices (kind "bake").
struct BakeSweepOptions {
  std::vector<std::string> targets = {"generic", "filament", "gltf", "babylon", "khronos-viewer"};
  // The factors: a bake option (bake_option_schema: chain_size, min_size, schedule, lut_size,
  // sh_order, pixel, chain_max_error; an alias such as cube_size is taken and reported under the
  // canonical name) or n_dot_v_axis (the DFG table's), each with the values tried one at a time
  // around every target's default; empty: kDefaultBakeFactors.
  std::vector<std::pair<std::string, std::vector<std::string>>> factors;
  int preview_width = 512;  // the preview's width; its height is half (the default grid's 12 x 6 square cells)
  int runs = 3;             // bakes of each setting the recommendation may take (the median and spread); others once
  std::string keep_bakes;   // a folder: each setting's bake kept as DIR/TARGET/LABEL (else removed)
};

// ---- kernels: where each hot kernel stands against the device's measured peak (issue 36) ------------

struct KernelsOptions {
  // Count mode (scripts/count_kernel_ops.sh runs the report under Oclgrind with the flop counter of
  // bench/kernel_ops): every row's launch once at its counting size, a marker line before each in
  // $BRDFBAKE_FLOP_COUNTS, no peaks; the figures are not measurements.
  bool count = false;
  int runs = 3;  // timed runs of each row after a warm-up (the median)
};

// The flops and bytes of one row's launch as counted (host/src/report/kernel_ops.inc): `units` work
// units at the counting size, the flops (per lane: add, mul, fma = 2, div, sqrt, transcendentals)
// and the bytes of every global and constant load and store the kernel executed.
struct KernelOpCount {
  const char* row;          // the row's id
  const char* shape;        // "cpu" or "gpu": the kernel shape it was counted in
  const char* source_hash;  // FNV-1a of the kernel file's source (includes expanded) it was counted on
  double units;
  double flops, fp64_flops;
  double add, mul, fma, div, sqrt, transcendental;  // flops by kind (fma: 2 a lane)
  double load_bytes, store_bytes;
};
// The counts of a row in a shape, or nullptr.
const KernelOpCount* find_kernel_op_count(const std::string& row, const std::string& shape);
// How the counts were made, per the generated table (tool, date, sizes).
const char* kernel_op_count_source();

struct KernelPeak {
  double gflops = 0.0;   // the best of the runs
  double seconds = 0.0;  // device seconds of that run
  double flops = 0.0;    // its flops, exactly (work-items x iterations x 8 chains x 16 lanes x 2)
};
struct KernelRow {
  std::string id;               // "dfg_lut ggx fp32": the count's key
  std::string kernel;           // the OpenCL kernel measured (kernels/*.cl)
  std::string launch;           // the launch measured, in words
  std::string unit;             // "texel", "pair", "cell"
  std::string precision;        // "fp32" | "fp64"
  bool walk = false;            // a data-dependent walk per work-item (branches and gathers differ by lane)
  double units = 0.0;           // work units of the measured launch
  double device_seconds = 0.0;  // the row's kernels, OpenCL event profiling (median of the runs)
  double wall_seconds = 0.0;    // the whole call (transfers, host work, other kernels)
  // From the count (counted false: none for this row and shape, and nothing below is filled).
  bool counted = false;
  bool stale = false;  // a count exists, made on other sources of the kernel (not used)
  double flops_per_unit = 0.0, bytes_per_unit = 0.0;
  double special_share = 0.0;  // divisions, square roots and transcendentals, of the flops
  // place_kernel_row:
  double units_per_second = 0.0, gflops = 0.0, gbytes_per_second = 0.0;
  double intensity = 0.0;       // flops per byte
  std::string bound;            // "compute" (intensity at or above the ridge) or "memory"
  double fraction = 0.0;        // of the roof: GFLOP/s over the peak (compute), GB/s over the triad's (memory)
  double flops_fraction = 0.0;  // GFLOP/s over the peak of its precision, whichever side of the ridge
  std::string limit;            // below kKernelLowFraction of the roof, or above the triad: what bounds it, in words
};
inline constexpr double kKernelLowFraction = 0.25;
struct KernelsReport {
  std::string shape;  // the kernel shape the device was opened in
  KernelPeak fp32, fp64;
  double bandwidth = 0.0;          // GB/s, the best triad
  double bandwidth_bytes = 0.0;    // bytes of one triad (3 arrays)
  double bandwidth_seconds = 0.0;  // its device seconds
  std::vector<KernelRow> rows;
};
// Fills a row's derived figures from its units, device seconds and per-unit counts, against the
// peaks (GFLOP/s of its precision, GB/s): throughput, GFLOP/s, GB/s, intensity, the side of the
// ridge, the fraction of the roof and of the flops peak and, below kKernelLowFraction of the roof
// (or above the triad's bandwidth: loads the caches serve), what bounds it.
void place_kernel_row(KernelRow& row, double peak_gflops, double bandwidth_gbs, unsigned compute_units);
// The device's peaks alone (kernels/device_peak.cl): fp32 and, where the device has it, fp64 FMA
// rate, and the triad's bandwidth; the shape the device was opened in. No rows.
KernelsReport measure_device_peaks(Device& device);
// The peaks, then every hot kernel (or, with options.count, every row once at its counting size).
KernelsReport measure_kernels(Device& device, const KernelsOptions& options,
                              const std::function<void(const std::string&)>& log = {});

struct ReportOptions {
  std::vector<std::string> kinds = {"ggx", "ggx-multiscatter",
                                    "charlie"};  // and "fresnel", "prefilter", "bake", "kernels"
  std::string device;  // a device selector (brdfbake/device.hpp); the reference is the baseline, not a device
  DfgSweepOptions dfg = [] {
    DfgSweepOptions o;
    o.size = 64;
    o.counts = kReportCounts;
    o.max_seconds_per_bake = 1.5;
    return o;
  }();
  std::vector<std::string> materials = {"gold", "copper", "aluminium", "water"};  // fresnel
  int fresnel_rate_cells = 1 << 18;
  std::string environment = "builtin:studio";  // prefilter
  int prefilter_size = 32;
  BakeSweepOptions bake;   // bake: the sweep of bake settings
  KernelsOptions kernels;  // kernels: the hot kernels against the device's peak
  std::string command;     // the command line, recorded for reproduction
  std::function<void(const std::string&)> log;
};

// The kinds a report can measure.
const std::vector<std::string>& report_kinds();

struct PrefilterLevelReport {
  int level = 0;
  int size = 0;
  double roughness = 0.0;
  double device_seconds = 0.0;
  double rms_error = 0.0;  // per channel |P - P_ref| / max(P_ref, 1e-3 mean(P_ref)), at probe texels
  double max_error = 0.0;
  int samples = 0;  // sampling estimator: lobe samples per texel
  int probes = 0;   // texels compared
};
struct PrefilterReport {
  std::string environment;
  std::string distribution;
  std::string estimator;
  int size = 0;
  double device_seconds = 0.0;     // the whole chain's kernels
  double reference_seconds = 0.0;  // the brute-force reference at the probes
  std::vector<PrefilterLevelReport> levels;
};

// ---- bake: the sweep of bake settings --------------------------------------------------------------

// The default factors of the bake sweep (one changed at a time around each target's default).
extern const std::vector<std::pair<std::string, std::vector<std::string>>> kDefaultBakeFactors;

// The error of one material group (a row of the default grid: white, grey, dark, gold, copper,
// silver): over its spheres, the median and the largest relative RMS error in linear radiance, and
// the same of its two shares (docs/PREVIEW.md, "Engine share and bake share": the bake's, the files'
// split-sum against the ideal bake's, what a setting can move; the engine's, the ideal bake's against
// the reference, what no file changes), and the sharp-reflection probe's bake share (the worst of the
// group's spheres below roughness 0.1, drawn where one texel of level 0 spans 2 pixels: render.hpp,
// sharp_probe; -1: the group has none).
struct BakeSweepGroup {
  std::string name;
  double median_rms = 0.0, max_rms = 0.0;
  double bake_median = 0.0, bake_worst = 0.0;
  double engine_median = 0.0, engine_worst = 0.0;
  double sharp = -1.0;
};
struct BakeSweepPoint {
  std::string label;                 // "default", "chain_size=128", ...
  std::string option, value;         // empty for the default
  std::vector<double> wall_seconds;  // each run of the bake
  double seconds = 0.0;              // their median
  double spread = 0.0;               // their largest minus their smallest (0 for one run)
  std::uint64_t bytes = 0;           // every file the bake wrote (manifest.json included)
  int files = 0;
  double splitsum_seconds = 0.0;  // the split-sum render
  double ideal_seconds = 0.0;     // the ideal bake (0 when an earlier setting's is shared) and its render
  double error = 0.0;             // the median over every sphere of its relative RMS error
  double bake_error = 0.0;        // the median over every sphere of its bake share (RMS)
  double engine_error = 0.0;      // the median over every sphere of its engine share (RMS)
  std::vector<BakeSweepGroup> groups;
  std::vector<double> sphere_rms, sphere_p99, sphere_max;  // per sphere, linear radiance
  std::vector<double> sphere_bake, sphere_engine;          // per sphere, the shares' RMS
  std::vector<double> sphere_sharp;                        // per sphere, the probe's (-1: not probed)
  bool pareto_time = false;   // no other point of the target is at most as slow and as wrong, one strictly
  bool pareto_bytes = false;  // the same with bytes
  bool eligible = false;      // within the recommendation's tolerances (kBakeRecommendWithin, kBakeSharpWithin)
  std::string folder;         // the kept bake (keep_bakes), else empty
};
struct BakeSweepTarget {
  std::string target;
  double reference_seconds = 0.0;      // the reference render (once per target and BRDF)
  double reference_bound = 0.0;        // the reference's largest per-sphere RMS bound
  std::vector<BakeSweepPoint> points;  // points[0] is the target's default
  int recommended = -1;                // index into points (the rule below), -1: none
  std::vector<std::string> ties;       // the eligible settings whose time ties the recommended's
  std::string why;                     // the recommendation in words: the rule's outcome, its ties
  std::vector<std::string> skipped;    // "chain_size=100: why"
};
// The recommended setting (mark_bake_sweep): of the settings no blurrier than the default (their
// sharp-reflection probe within kBakeSharpWithin of the default's on every group) and read no worse by
// the engine (each group's median engine share within kBakeSharpWithin of the default's: a chain of
// another level count changes the engine's LOD from roughness), those whose bake
// share on every material group's worst sphere is within kBakeRecommendWithin of the best any of them
// reached for that group are eligible, and the fastest of these by its median time is taken; a
// setting whose median differs from the fastest's by less than either's spread (the largest minus
// the smallest of its runs) is a tie, and of the tied settings the one with the fewest bytes is
// taken (on equal bytes the first in the sweep's order: the default, when it ties). Where settings trade one group
// against another so that none is eligible, the one closest to the best on its worst group is taken, and `why` says so.
inline constexpr double kBakeRecommendWithin = 1.10;
inline constexpr double kBakeSharpWithin = 1.02;
struct BakeSweep {
  std::string environment;
  int preview_width = 0;
  std::vector<BakeSweepTarget> targets;
  double seconds = 0.0;
};

// Runs the sweep on `device` under `environment` (a file or builtin:NAME). Throws Error for an unknown
// target or factor, or a target whose default cannot be baked; a setting that cannot be baked is
// listed in the target's `skipped` with the reason.
// Throws Error for an unknown target or factor, runs or a preview width out of range.
void check_bake_sweep(const BakeSweepOptions& options);
BakeSweep sweep_bake(const std::string& environment, const std::string& device, const BakeSweepOptions& options,
                     const std::function<void(const std::string&)>& log = {});
// Marks each point's Pareto flags (time and bytes against error) and the recommended setting.
void mark_bake_sweep(BakeSweepTarget& target);

struct Report {
  std::string generator;
  std::string date;            // UTC, ISO 8601
  std::string device;          // name
  std::string device_details;  // platform, driver, compute units
  int cores = 0;
  double load_before[3] = {0, 0, 0};  // /proc/loadavg at the start and the end (-1: unknown)
  double load_after[3] = {0, 0, 0};
  double seconds = 0.0;  // wall time of the whole report
  ReportOptions options;
  std::vector<DfgSweep> dfg;
  std::vector<FresnelComparison> fresnel;
  std::vector<PrefilterReport> prefilter;
  std::vector<BakeSweep> bake;         // at most one
  std::vector<KernelsReport> kernels;  // at most one
};

// Runs every measurement the options ask for. Throws Error for an unknown kind, material or device.
Report run_report(const ReportOptions& options);
std::string report_json(const Report& report);
std::string report_html(const Report& report);
// Writes the page to `html_path` and the JSON beside it (the same name with .json), atomically.
void write_report(const Report& report, const std::string& html_path);
// The JSON path that goes with an HTML path: "out/report.html" -> "out/report.json".
std::string report_json_path(const std::string& html_path);

}  // namespace brdfbake
