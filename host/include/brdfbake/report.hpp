// `brdfbake report`: the accuracy-against-time sweep for chosen kinds on a chosen device, as a
// self-contained HTML page (inline SVG plots, no network resources) and a JSON of the numbers.
//   DFG kinds (ggx, ggx-multiscatter, charlie): every estimator over its sample counts against the
//     converged reference (brdfbake/accuracy.hpp), device time from event profiling;
//   fresnel: every model against the exact one for a few measured materials, with device rates;
//   prefilter: the error and device time of each level of a small chain against the brute-force
//     reference, for both estimators.
// The page states the machine's load, which the times depend on (docs/BENCHMARKS.md).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "brdfbake/accuracy.hpp"
#include "brdfbake/fresnel.hpp"

namespace brdfbake {

// The sample counts of the report's DFG sweep: the full sweep's without its slowest counts.
inline const std::vector<int> kReportCounts = {16, 32, 64, 128, 256, 384, 512, 768, 1024, 2048, 4096};

struct ReportOptions {
  std::vector<std::string> kinds = {"ggx", "ggx-multiscatter", "charlie"};  // and "fresnel", "prefilter"
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
  std::string command;  // the command line, recorded for reproduction
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
