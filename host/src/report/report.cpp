// `brdfbake report`: the measurements (brdfbake/report.hpp) and their JSON. The page is drawn by
// report/report_html.cpp from the same Report.
#include "brdfbake/report.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/material_presets.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/version.hpp"
#include "families/prefilter/model.hpp"
#include "io/atomic_file.hpp"

namespace brdfbake {

namespace {

using json = nlohmann::ordered_json;

void read_load(double out[3]) {
  out[0] = out[1] = out[2] = -1.0;
  std::ifstream in("/proc/loadavg");
  if (in) in >> out[0] >> out[1] >> out[2];
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char b[32];
  std::strftime(b, sizeof b, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return b;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// ---- Prefiltered levels against the brute-force reference --------------------------------------

struct Probe {
  int face, i, j;
};

// The texels compared: a grid of up to 8 x 8 per face (every texel at 8^2 and below).
std::vector<Probe> probes(int size) {
  const int n = std::min(size, 8), stride = size / n;
  std::vector<Probe> p;
  for (int f = 0; f < 6; ++f)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) p.push_back({f, i * stride + stride / 2, j * stride + stride / 2});
  return p;
}

PrefilterReport prefilter_report(Device& dev, const EnvImage& env, const std::string& name, EnvEstimator estimator,
                                 int size, const std::function<void(const std::string&)>& log) {
  PrefilterSpec spec;
  spec.size = size;
  spec.min_size = std::max(1, size / 8);
  spec.estimator = estimator;
  const CubeLevels source = environment_to_cube(dev, env, size);
  PrefilterTiming timing;
  prefilter_cube(dev, source, spec, &timing);  // warm-up: program builds
  const CubeLevels cube = prefilter_cube(dev, source, spec, &timing);
  PrefilterReport r;
  r.environment = name;
  r.distribution = env_distribution_name(spec.distribution);
  r.estimator = env_estimator_name(estimator);
  r.size = size;
  r.device_seconds = timing.device_seconds;
  const std::vector<std::string> rough = [&] {
    std::vector<std::string> v;
    std::string s = cube.meta("roughness_per_level"), cur;
    for (char ch : s + ",") {
      if (ch == ',') {
        v.push_back(cur);
        cur.clear();
      } else {
        cur += ch;
      }
    }
    return v;
  }();
  std::vector<std::string> samples;
  {
    std::string s = cube.meta("samples_per_level"), cur;
    for (char ch : s + ",") {
      if (ch == ',') {
        samples.push_back(cur);
        cur.clear();
      } else {
        cur += ch;
      }
    }
  }
  for (int l = 1; l < cube.level_count(); ++l) {
    PrefilterLevelReport lr;
    lr.level = l;
    lr.size = cube.level_size(l);
    lr.roughness = size_t(l) < rough.size() ? std::atof(rough[size_t(l)].c_str()) : 0.0;
    lr.device_seconds = size_t(l) < timing.level_device_seconds.size() ? timing.level_device_seconds[size_t(l)] : 0.0;
    lr.samples = size_t(l) < samples.size() ? std::atoi(samples[size_t(l)].c_str()) : 0;
    const std::vector<Probe> ps = probes(lr.size);
    std::vector<Vec3> dirs;
    for (const auto& p : ps) dirs.push_back(math::cube_texel_direction(p.face, lr.size, p.i, p.j));
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<double> want =
        detail::prefilter_reference_directions(cube, EnvDistribution::Ggx, lr.roughness, dirs);
    r.reference_seconds += seconds_since(t0);
    double mean = 0;
    for (double v : want) mean += v;
    mean /= double(std::max<size_t>(1, want.size()));
    double sum = 0;
    size_t n = 0;
    for (size_t k = 0; k < ps.size(); ++k) {
      const float* t = cube.texel(l, ps[k].face, ps[k].i, ps[k].j);
      for (size_t c = 0; c < 3; ++c) {
        const double w = want[3 * k + c];
        const double d = std::fabs(double(t[c]) - w) / std::max(w, 1e-3 * mean);
        sum += d * d;
        lr.max_error = std::max(lr.max_error, d);
        ++n;
      }
    }
    lr.rms_error = std::sqrt(sum / double(std::max<size_t>(1, n)));
    lr.probes = static_cast<int>(ps.size());
    r.levels.push_back(lr);
    if (log) {
      char b[160];
      std::snprintf(b, sizeof b, "  prefilter %s level %d (roughness %.3f): rms %.2e, max %.2e, %.1f ms",
                    r.estimator.c_str(), l, lr.roughness, lr.rms_error, lr.max_error, lr.device_seconds * 1e3);
      log(b);
    }
  }
  return r;
}

json errors_json(const TableErrors& e) { return json{{"max", e.max}, {"rms", e.rms}}; }

json bake_json(const BakeSweep& s) {
  json b;
  b["environment"] = s.environment;
  b["preview"] = {{"width", s.preview_width}, {"height", s.preview_width / 2}, {"material", "the default grid"}};
  b["seconds"] = s.seconds;
  b["time_definition"] =
      "wall seconds of the whole bake as `brdfbake bake --target T` runs it (planner, environment load, every table, "
      "the engine's files, manifest; programs cached, the backend warm): every setting once, the settings the "
      "recommendation may take again up to --runs "
      "runs (default 3); 'seconds' the median of 'wall_seconds', 'spread' their largest minus their smallest";
  b["bytes_definition"] = "every file the bake wrote, manifest.json included";
  b["error_definition"] =
      "per sphere, the relative RMS over its pixels of |split-sum - reference| / |reference| (linear RGB norms), the "
      "split-sum render from the setting's files, the reference rendered once per target (brdfbake preview); "
      "'error' is the median over the spheres, groups the median and max over each row of the default grid";
  b["shares_definition"] =
      "per sphere, the bake's share: the relative RMS of |split-sum(files) - split-sum(ideal bake)| / |reference|, "
      "what "
      "the setting's files add (resolution, refinement, storage); the engine's share: of |split-sum(ideal bake) - "
      "reference| / |reference|, the target's split-sum approximation that no file changes (docs/PREVIEW.md, 'Engine "
      "share and bake share'); the ideal bake made for the files' chain shape (level count and sizes), shared by the "
      "settings of the same shape";
  b["sharp_definition"] =
      "per sphere below roughness 0.1 (sphere_sharp, -1 for the others; a group's 'sharp' the worst of its spheres): "
      "the bake's share drawn at a radius of 2 x the files' level-0 face size in pixels (one texel of level 0 spans "
      ">= 2 pixels at the sphere's centre), the RMS over 16384 of its pixels of |files - ideal| / |ideal|";
  b["pareto_definition"] =
      "a point is on the front when no other point of its target is at most as slow (or as large) and at most as "
      "wrong, one of them strictly";
  b["recommended_rule"] =
      "of the settings whose sharp-reflection probe on every group is within " +
      std::to_string(int(std::lround((kBakeSharpWithin - 1) * 100))) +
      "% of the default's (no blurrier) and whose engine share (each group's median) is within as much of the "
      "default's, those whose bake share on every group's worst sphere is within " +
      std::to_string(int(std::lround((kBakeRecommendWithin - 1) * 100))) +
      "% of the best of them for that group ('eligible'); the fastest by its median time; settings whose medians "
      "differ by less than either's spread tie ('ties'), and of them the one with the fewest bytes is taken; with "
      "none eligible, the one closest to the best on its worst group";
  json targets = json::array();
  for (const auto& t : s.targets) {
    json tj;
    tj["target"] = t.target;
    tj["reference_seconds"] = t.reference_seconds;
    tj["reference_bound"] = t.reference_bound;
    json pts = json::array();
    for (const auto& p : t.points) {
      json groups = json::object();
      for (const auto& g : p.groups)
        groups[g.name] = {{"median_rms", g.median_rms},
                          {"max_rms", g.max_rms},
                          {"bake_median", g.bake_median},
                          {"bake_worst", g.bake_worst},
                          {"engine_median", g.engine_median},
                          {"engine_worst", g.engine_worst},
                          {"sharp", g.sharp >= 0.0 ? json(g.sharp) : json(nullptr)}};
      json pj = {{"label", p.label},
                 {"option", p.option},
                 {"value", p.value},
                 {"seconds", p.seconds},
                 {"spread", p.spread},
                 {"wall_seconds", p.wall_seconds},
                 {"bytes", p.bytes},
                 {"files", p.files},
                 {"splitsum_seconds", p.splitsum_seconds},
                 {"ideal_seconds", p.ideal_seconds},
                 {"error", p.error},
                 {"bake_error", p.bake_error},
                 {"engine_error", p.engine_error},
                 {"groups", groups},
                 {"sphere_rms", p.sphere_rms},
                 {"sphere_p99", p.sphere_p99},
                 {"sphere_max", p.sphere_max},
                 {"sphere_bake", p.sphere_bake},
                 {"sphere_engine", p.sphere_engine},
                 {"sphere_sharp", p.sphere_sharp},
                 {"pareto_time", p.pareto_time},
                 {"pareto_bytes", p.pareto_bytes},
                 {"eligible", p.eligible}};
      if (!p.folder.empty()) pj["folder"] = p.folder;
      pts.push_back(pj);
    }
    tj["points"] = pts;
    tj["recommended"] = t.recommended >= 0 ? json(t.points[size_t(t.recommended)].label) : json(nullptr);
    tj["ties"] = t.ties;
    tj["why"] = t.why;
    tj["skipped"] = t.skipped;
    targets.push_back(tj);
  }
  b["targets"] = targets;
  return b;
}

json kernels_json(const KernelsReport& k) {
  json j;
  j["kernel_shape"] = k.shape;
  j["peaks"] = {{"fp32_gflops", k.fp32.gflops},
                {"fp32_seconds", k.fp32.seconds},
                {"fp64_gflops", k.fp64.gflops},
                {"fp64_seconds", k.fp64.seconds},
                {"bandwidth_gbs", k.bandwidth},
                {"bandwidth_bytes", k.bandwidth_bytes},
                {"bandwidth_seconds", k.bandwidth_seconds}};
  j["peak_definition"] =
      "peak_fma (kernels/device_peak.cl): 8 independent chains of fma on float16 (double16 for fp64) per work-item, "
      "flops = 2 x 16 lanes x 8 chains x iterations x work-items, the best of 3 launches of >= 20 ms; bandwidth: "
      "STREAM's triad on float4 over three arrays of 64 MiB (CPU) or 256 MiB (GPU), bytes = 3 x the array, the best of "
      "5 launches after one that touches the pages";
  j["count_source"] = kernel_op_count_source();
  j["count_definition"] =
      "flops and bytes per work unit counted by Oclgrind (bench/kernel_ops/flop_counter.cpp, every lane of a vector "
      "instruction): fadd, fsub, fmul, fdiv 1, fma and fmuladd 2, sqrt, rsqrt and each transcendental builtin 1; "
      "bytes: every global and constant load and store the kernel executed (caches serve re-reads, so above the "
      "DRAM traffic); the row ran at the counting size (scripts/count_kernel_ops.sh) and its counts per unit scale "
      "to the measured launch's units";
  j["fraction_definition"] =
      "'fraction', of the roof: compute-bound rows (flops per byte at or above the ridge, peak GFLOP/s / triad GB/s): "
      "GFLOP/s over the peak of the row's precision; memory-bound rows: GB/s over the triad's (above 1: the caches "
      "serve the loads); 'flops_fraction': GFLOP/s over the peak, whichever the side";
  json rows = json::array();
  for (const auto& r : k.rows) {
    json row = {{"id", r.id},
                {"kernel", r.kernel},
                {"launch", r.launch},
                {"unit", r.unit},
                {"precision", r.precision},
                {"units", r.units},
                {"device_seconds", r.device_seconds},
                {"wall_seconds", r.wall_seconds},
                {"units_per_second", r.units_per_second},
                {"counted", r.counted},
                {"stale_count", r.stale}};
    if (r.counted) {
      row["flops_per_unit"] = r.flops_per_unit;
      row["bytes_per_unit"] = r.bytes_per_unit;
      row["special_share"] = r.special_share;
      row["gflops"] = r.gflops;
      row["gbytes_per_second"] = r.gbytes_per_second;
      row["intensity"] = std::isfinite(r.intensity) ? json(r.intensity) : json(nullptr);
      row["bound"] = r.bound;
      row["fraction"] = r.fraction;
      row["flops_fraction"] = r.flops_fraction;
      row["limit"] = r.limit;
    }
    rows.push_back(row);
  }
  j["rows"] = rows;
  return j;
}

json rgb_json(const Rgb& v) { return json::array({v.r, v.g, v.b}); }

}  // namespace

const std::vector<std::string>& report_kinds() {
  static const std::vector<std::string> k = {"ggx",  "ggx-multiscatter", "charlie", "fresnel", "prefilter",
                                             "bake", "kernels"};
  return k;
}

std::string report_json_path(const std::string& html_path) {
  std::filesystem::path p(html_path);
  p.replace_extension(".json");
  return p.string();
}

Report run_report(const ReportOptions& o) {
  for (const auto& k : o.kinds)
    if (std::find(report_kinds().begin(), report_kinds().end(), k) == report_kinds().end())
      throw Error("unknown report kind '" + k +
                  "' (expected ggx, ggx-multiscatter, charlie, fresnel, prefilter, bake or kernels)");
  if (o.kinds.empty()) throw Error("the report needs at least one kind");
  if (o.device == "reference")
    throw Error(
        "the report measures a device's estimators against the scalar reference, which is its baseline: "
        "choose an OpenCL device");
  for (const auto& m : o.materials)
    if (!find_material_preset(m)) throw Error("unknown material '" + m + "' (brdfbake fresnel --list-materials)");
  if (std::find(o.kinds.begin(), o.kinds.end(), "bake") != o.kinds.end()) check_bake_sweep(o.bake);
  const auto t0 = std::chrono::steady_clock::now();
  Report r;
  r.generator = std::string("brdfbake ") + kVersion;
  r.date = utc_now();
  r.options = o;
  r.cores = static_cast<int>(std::thread::hardware_concurrency());
  read_load(r.load_before);
  Device dev = Device::open(o.device);
  const DeviceInfo& info = dev.info();
  r.device = info.name;
  r.device_details = info.platform_name + ", driver " + info.driver_version + ", " +
                     std::to_string(info.compute_units) + " compute units, " + info.type +
                     (info.fp64 ? ", fp64" : ", no fp64") + ", kernel shape " + info.kernel_shape;
  auto log = [&](const std::string& s) {
    if (o.log) o.log(s);
  };
  for (const auto& k : o.kinds) {
    if (k == "ggx" || k == "ggx-multiscatter" || k == "charlie") {
      DfgSweepOptions d = o.dfg;
      d.log = o.log;
      r.dfg.push_back(sweep_dfg(dev, lut_kind_from_name(k), d));
    } else if (k == "fresnel") {
      FresnelCompareOptions f;
      f.rate_cells = o.fresnel_rate_cells;
      f.rate_runs = 3;
      for (const auto& m : o.materials) {
        log("fresnel: " + m);
        r.fresnel.push_back(compare_fresnel_models(m, &dev, f));
      }
    } else if (k == "prefilter") {
      log("prefilter: " + o.environment + " at " + std::to_string(o.prefilter_size) + "^2");
      EnvLoadOptions lo;
      const EnvImage env = load_environment(o.environment, lo);
      for (EnvEstimator e : {EnvEstimator::Quadrature, EnvEstimator::Sampling})
        r.prefilter.push_back(prefilter_report(dev, env, o.environment, e, o.prefilter_size, o.log));
    } else if (k == "bake") {
      log("bake: " + o.environment + ", targets and settings one at a time, preview " +
          std::to_string(o.bake.preview_width) + "x" + std::to_string(o.bake.preview_width / 2));
      r.bake.push_back(sweep_bake(o.environment, o.device, o.bake, o.log));
    } else if (k == "kernels") {
      r.kernels.push_back(measure_kernels(dev, o.kernels, o.log));
    }
  }
  read_load(r.load_after);
  r.seconds = seconds_since(t0);
  return r;
}

std::string report_json(const Report& r) {
  json j;
  j["generator"] = r.generator;
  j["date"] = r.date;
  j["command"] = r.options.command;
  j["device"] = r.device;
  j["device_details"] = r.device_details;
  j["cores"] = r.cores;
  j["load_average_before"] = json::array({r.load_before[0], r.load_before[1], r.load_before[2]});
  j["load_average_after"] = json::array({r.load_after[0], r.load_after[1], r.load_after[2]});
  j["seconds"] = r.seconds;
  j["kinds"] = r.options.kinds;
  j["error_definition"] =
      "DFG: max and RMS over every channel and cell of |table - reference| / max(1, |reference|) (absolute below 1, "
      "relative above), against the converged scalar double reference at the same cells; fresnel: max and mean "
      "|model - exact| per channel over cos_theta in [0, 1]; prefilter: per channel |P - P_ref| / max(P_ref, 1e-3 "
      "mean(P_ref)) at probe texels, P_ref the brute-force reference filtering the same source cube";
  j["time_definition"] = "device seconds from OpenCL event profiling (median of up to 3 runs after a warm-up)";
  json dfg = json::array();
  for (const auto& s : r.dfg) {
    json k;
    k["kind"] = lut_kind_name(s.kind);
    k["size"] = s.size;
    k["device"] = s.device;
    k["reference"] = {
        {"seconds", s.reference_seconds}, {"threads", s.reference_threads}, {"error", errors_json(s.reference_error)}};
    json pts = json::array();
    for (const auto& p : s.points)
      pts.push_back({{"estimator", estimator_name(p.estimator)},
                     {"precision", precision_name(p.precision)},
                     {"samples", p.samples},
                     {"evaluations_per_texel", p.evaluations_per_texel},
                     {"device_seconds", p.device_seconds},
                     {"error", errors_json(p.error)}});
    k["points"] = pts;
    k["skipped"] = s.skipped;
    dfg.push_back(k);
  }
  j["dfg"] = dfg;
  json fres = json::array();
  for (const auto& c : r.fresnel) {
    json m;
    m["material"] = c.material;
    m["exact_model"] = fresnel_model_name(c.exact_model);
    m["grid"] = c.grid;
    m["rate_cells"] = c.rate_cells;
    json rows = json::array();
    for (const auto& row : c.rows)
      rows.push_back({{"model", fresnel_model_name(row.model)},
                      {"setting", row.setting},
                      {"max_abs", rgb_json(row.max_abs)},
                      {"mean_abs", rgb_json(row.mean_abs)},
                      {"worst", row.worst},
                      {"cos_at_worst", row.cos_at_worst},
                      {"cells_per_second", row.cells_per_second},
                      {"device_seconds", row.device_seconds}});
    m["models"] = rows;
    fres.push_back(m);
  }
  j["fresnel"] = fres;
  json pre = json::array();
  for (const auto& p : r.prefilter) {
    json e;
    e["environment"] = p.environment;
    e["distribution"] = p.distribution;
    e["estimator"] = p.estimator;
    e["chain_size"] = p.size;  // the chain's level 0 (report --chain-size)
    e["device_seconds"] = p.device_seconds;
    e["reference_seconds"] = p.reference_seconds;
    json lv = json::array();
    for (const auto& l : p.levels)
      lv.push_back({{"level", l.level},
                    {"size", l.size},
                    {"roughness", l.roughness},
                    {"samples", l.samples},
                    {"device_seconds", l.device_seconds},
                    {"rms_error", l.rms_error},
                    {"max_error", l.max_error},
                    {"probes", l.probes}});
    e["levels"] = lv;
    pre.push_back(e);
  }
  j["prefilter"] = pre;
  if (!r.bake.empty()) j["bake"] = bake_json(r.bake.front());
  if (!r.kernels.empty()) j["kernels"] = kernels_json(r.kernels.front());
  return j.dump(2) + "\n";
}

void write_report(const Report& r, const std::string& html_path) {
  const std::string json_path = report_json_path(html_path);
  io::ParentFolders folders(html_path);  // made if missing, as every output's
  io::TempFile html(html_path), js(json_path);
  io::write_bytes(html, report_html(r));
  io::write_bytes(js, report_json(r));
  // the numbers first, the page that shows them last: a page on disk always has its JSON
  std::error_code ec;
  for (const std::string& p : {json_path, html_path})
    if (std::filesystem::is_directory(p, ec))
      throw Error("cannot write '" + p + "': a folder of that name is in the way (nothing was written)");
  js.commit();
  html.commit();
  folders.keep();
}

}  // namespace brdfbake
