// The report's kind "bake" (brdfbake/report.hpp): what each bake setting costs at the level of the
// render. For each target, its default bake and one setting changed at a time (a one-factor sweep,
// not the cross product): each bake is run as `brdfbake bake --target T --OPTION VALUE` runs it (the
// planner, run_job into a folder of its own, the backend and its programs warm: the wall time a user
// waits for, the median of a few runs where a run is cheap), the bytes of every file it wrote, and
// the preview's split-sum render of its files (families/preview) against one reference render. The
// reference does not depend on the bake, only on the environment, the spheres and the target's BRDF:
// it is rendered once per target (again only for a setting that changes the BRDF, as
// energy_compensation would) and every setting's split-sum render is compared with it, pixel by
// pixel, exactly as render_preview compares them (a direct `brdfbake preview --bake` of the same
// folder gives the same numbers: tests/host/test_report.cpp).
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>

#include "brdfbake/backend.hpp"
#include "brdfbake/cancel.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/job.hpp"
#include "brdfbake/plan.hpp"
#include "brdfbake/preview.hpp"
#include "brdfbake/report.hpp"
#include "families/preview/model.hpp"
#include "families/preview/render.hpp"

namespace brdfbake {

const std::vector<std::pair<std::string, std::vector<std::string>>> kDefaultBakeFactors = {
    {"chain_size", {"64", "128", "512"}},
    {"min_size", {"4", "64"}},
    {"schedule", {"sqrt"}},
    {"lut_size", {"16", "32", "64"}},
    {"n_dot_v_axis", {"sqrt"}},
    {"pixel", {"f32"}},
    {"sh_order", {"5"}},
    {"chain_max_error", {"0.03", "0.003"}},
};

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// A bake cheaper than this is run `runs` times and the median reported; a slower one once (its
// scatter from run to run is small against its time).
constexpr double kRepeatBelowSeconds = 1.0;

// A folder removed with everything in it on destruction (unless kept).
class Folder {
 public:
  Folder(fs::path p, bool keep) : path_(std::move(p)), keep_(keep) {}
  ~Folder() {
    std::error_code ec;
    if (!keep_) fs::remove_all(path_, ec);
  }
  Folder(const Folder&) = delete;
  Folder& operator=(const Folder&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
  bool keep_;
};

// The job `brdfbake bake --env ENV --target T [--OPTION VALUE]` runs; n_dot_v_axis, a parameter of
// the DFG table that the planner does not expose, is set on the job's DFG tables.
Job plan_setting(const std::string& environment, const std::string& target, const std::string& option,
                 const std::string& value, const std::string& device) {
  const std::vector<ParamDef>& schema = bake_option_schema();
  Params given;
  auto add = [&](const std::string& name, const std::string& text) {
    const ParamDef* d = find_param_def(schema, name);
    if (!d) throw Error("unknown bake option '" + name + "'");
    given.push_back({name, parse_param_text(*d, text, "--" + name)});
  };
  add("environment", environment);
  add("target", target);
  if (!device.empty()) add("device", device);
  if (!option.empty() && option != "n_dot_v_axis") add(option, value);
  OptionNaming naming;
  naming.cli = true;
  Plan plan = plan_bake(parse_bake_options(given, naming));
  if (option == "n_dot_v_axis") {
    bool any = false;
    for (TableRequest& t : plan.job.tables)
      if (t.kind == TableKind::Ggx || t.kind == TableKind::GgxMultiscatter) {
        t.set("n_dot_v_axis", value);
        t.output.clear();  // named again from the parameters (the axis is in the name)
        any = true;
      }
    if (!any) throw Error("the plan has no GGX DFG table");
    validate_job(plan.job);
  }
  return plan.job;
}

void folder_size(const fs::path& dir, std::uint64_t* bytes, int* files) {
  *bytes = 0;
  *files = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) {
      *bytes += e.file_size();
      ++*files;
    }
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The label of a setting, safe as a folder name.
std::string label_of(const std::string& option, const std::string& value) {
  if (option.empty()) return "default";
  std::string l = option + "=" + value;
  for (char& c : l)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '=' || c == '.' || c == '-')) c = '_';
  return l;
}

// The per-sphere relative error of a split-sum render against a reference render of the same
// layout, as render_preview computes it (detail::preview::sphere_errors): per pixel |s - r| / |r|
// (Euclidean norms of the linear RGB triples, in double from the float images), per sphere its RMS,
// 99th percentile and max.
std::vector<PreviewErrorStats> compare(const PreviewResult& split, const PreviewResult& reference) {
  using namespace detail::preview;
  const Layout layout = make_layout(split.spec);
  if (reference.reference.width != layout.width || reference.reference.height != layout.height ||
      reference.spheres.size() != layout.spheres.size())
    throw Error("the bake sweep's reference render has another layout than the split-sum render");
  std::vector<PreviewErrorStats> out;
  for (const PreviewSphereStats& s :
       sphere_errors(layout, sphere_pixels(layout), split.splitsum, reference.reference, split.exposure))
    out.push_back(s.linear);
  return out;
}

// The material groups of the spheres: the first word of each material's name ("gold r0.2": gold), in
// order of first appearance.
void fill_errors(BakeSweepPoint& pt, const PreviewResult& split, const std::vector<PreviewErrorStats>& stats) {
  std::vector<std::string> order;
  std::map<std::string, std::vector<double>> by;
  for (size_t s = 0; s < stats.size(); ++s) {
    pt.sphere_rms.push_back(stats[s].rms);
    pt.sphere_p99.push_back(stats[s].p99);
    pt.sphere_max.push_back(stats[s].max);
    const std::string& name = split.spheres[s].material.name;
    const std::string group = name.substr(0, name.find(' '));
    if (!by.count(group)) order.push_back(group);
    by[group].push_back(stats[s].rms);
  }
  for (const auto& g : order) {
    const std::vector<double>& v = by[g];
    pt.groups.push_back({g, median(v), *std::max_element(v.begin(), v.end())});
  }
  pt.error = median(pt.sphere_rms);
}

}  // namespace

void mark_bake_sweep(BakeSweepTarget& t) {
  auto dominated = [&](size_t i, auto cost) {
    for (size_t j = 0; j < t.points.size(); ++j) {
      if (j == i) continue;
      const double ci = cost(t.points[i]), cj = cost(t.points[j]);
      const double ei = t.points[i].error, ej = t.points[j].error;
      if (cj <= ci && ej <= ei && (cj < ci || ej < ei)) return true;
    }
    return false;
  };
  for (size_t i = 0; i < t.points.size(); ++i) {
    t.points[i].pareto_time = !dominated(i, [](const BakeSweepPoint& p) { return p.seconds; });
    t.points[i].pareto_bytes = !dominated(i, [](const BakeSweepPoint& p) { return double(p.bytes); });
  }
  t.recommended = -1;
  if (t.points.empty()) return;
  double best = HUGE_VAL;
  for (const auto& p : t.points) best = std::min(best, p.error);
  for (size_t i = 0; i < t.points.size(); ++i)
    if (t.points[i].error <= kBakeRecommendWithin * best &&
        (t.recommended < 0 || t.points[i].seconds < t.points[size_t(t.recommended)].seconds))
      t.recommended = int(i);
}

void check_bake_sweep(const BakeSweepOptions& o) {
  if (o.preview_width < 96 || o.preview_width > kPreviewMaxSize)
    throw Error("the bake sweep's preview width must be 96 to " + std::to_string(kPreviewMaxSize) +
                " (12 columns of spheres at least 8 pixels wide)");
  if (o.runs < 1 || o.runs > 9) throw Error("the bake sweep's runs must be 1 to 9");
  for (const auto& t : o.targets) engine_target_from_name(t);  // throws, listing the targets
  // The sweep replaces KEEP/TARGET/SETTING folders: only a new or an empty folder is taken, before
  // anything runs (issue 34, class 1).
  if (!o.keep_bakes.empty()) {
    std::error_code ec;
    const auto type = fs::symlink_status(o.keep_bakes, ec).type();
    if (type != fs::file_type::not_found && (type != fs::file_type::directory || !fs::is_empty(o.keep_bakes, ec)))
      throw Error("keep_bakes: '" + o.keep_bakes +
                  "' exists and is not an empty folder: give a new folder (the sweep replaces its TARGET/SETTING "
                  "folders)");
  }
  for (const auto& f : o.factors)
    if (f.first != "n_dot_v_axis" && !find_param_def_or_alias(bake_option_schema(), f.first))
      throw Error("the bake sweep cannot vary '" + f.first +
                  "' (a bake option: chain_size, min_size, schedule, lut_size, sh_order, pixel, chain_max_error, "
                  "..., or n_dot_v_axis)");
  Params named;  // an option varied under two of its names (chain_size and its alias cube_size)
  for (const auto& f : o.factors)
    if (f.first != "n_dot_v_axis") named.push_back({f.first, false});
  canonicalize_params(named, bake_option_schema(), "the bake sweep's factors: ", false);
}

namespace {

// The factors under the options' canonical names (cube_size=64 is chain_size=64): the labels, the
// report's JSON and the folders of kept bakes name only those.
std::vector<std::pair<std::string, std::vector<std::string>>> canonical_factors(
    const std::vector<std::pair<std::string, std::vector<std::string>>>& factors) {
  auto out = factors;
  for (auto& f : out)
    if (const ParamDef* d = find_param_def_or_alias(bake_option_schema(), f.first)) f.first = d->name;
  return out;
}

}  // namespace

BakeSweep sweep_bake(const std::string& environment, const std::string& device, const BakeSweepOptions& o,
                     const std::function<void(const std::string&)>& log) {
  const auto t_start = Clock::now();
  auto say = [&](const std::string& s) {
    if (log) log(s);
  };
  check_bake_sweep(o);
  const auto factors = canonical_factors(o.factors.empty() ? kDefaultBakeFactors : o.factors);
  BakeSweep sweep;
  sweep.environment = environment;
  sweep.preview_width = o.preview_width;
  std::shared_ptr<Backend> backend = Backend::open(device);
  const EnvImage env = load_environment(environment, EnvLoadOptions{});
  RunOptions ro;
  ro.backend = [backend](const std::string&) { return backend; };
  const fs::path root = o.keep_bakes.empty()
                            ? fs::temp_directory_path() / ("brdfbake-sweep-" + std::to_string(::getpid()))
                            : fs::path(o.keep_bakes);
  Folder root_folder(root, !o.keep_bakes.empty());

  for (const std::string& target : o.targets) {
    BakeSweepTarget bt;
    bt.target = target;
    std::map<std::string, std::shared_ptr<PreviewResult>> references;  // by BRDF
    std::string default_job;
    std::vector<std::pair<std::string, std::string>> settings = {{"", ""}};
    for (const auto& f : factors)
      for (const auto& v : f.second) settings.push_back({f.first, v});
    for (const auto& [option, value] : settings) {
      const std::string label = label_of(option, value);
      BakeSweepPoint pt;
      pt.label = label;
      pt.option = option;
      pt.value = value;
      Job job;
      try {
        job = plan_setting(environment, target, option, value, device);
      } catch (const Error& e) {
        bt.skipped.push_back(label + ": " + e.what());
        say("  bake " + target + " " + label + ": skipped (" + e.what() + ")");
        continue;
      }
      job.output_dir.clear();
      const std::string plan_text = job_to_json(job);
      if (option.empty())
        default_job = plan_text;
      else if (plan_text == default_job) {
        bt.skipped.push_back(label + ": the same bake as the default for this target");
        continue;
      }
      const fs::path dir = root / target / label;
      job.output_dir = dir.string();
      try {
        for (int run = 0; run < o.runs; ++run) {
          fs::remove_all(dir);
          const auto t0 = Clock::now();
          run_job(job, {}, ro);
          pt.wall_seconds.push_back(since(t0));
          if (pt.wall_seconds.back() >= kRepeatBelowSeconds) break;
        }
      } catch (const Cancelled&) {
        throw;  // SIGINT, SIGTERM: the whole report stops
      } catch (const Error& e) {
        bt.skipped.push_back(label + ": " + e.what());
        say("  bake " + target + " " + label + ": failed (" + e.what() + ")");
        continue;
      }
      pt.seconds = median(pt.wall_seconds);
      folder_size(dir, &pt.bytes, &pt.files);
      if (!o.keep_bakes.empty()) pt.folder = dir.string();

      PreviewSpec spec;
      spec.target = engine_target_from_name(target);
      spec.bake = dir.string();
      spec.width = o.preview_width;
      spec.height = o.preview_width / 2;
      spec.reference = false;
      spec.shares = false;  // the sweep compares bakes against one reference (the shares: issue 35's next part)
      auto t0 = Clock::now();
      PreviewResult split = render_preview(*backend, env, spec);
      pt.splitsum_seconds = since(t0);
      std::shared_ptr<PreviewResult>& ref = references[split.brdf];
      if (!ref) {
        spec.reference = true;
        t0 = Clock::now();
        ref = std::make_shared<PreviewResult>(render_preview(*backend, env, spec));
        bt.reference_seconds += since(t0);
        for (const auto& s : ref->stats) bt.reference_bound = std::max(bt.reference_bound, s.reference_rms_bound);
      }
      fill_errors(pt, split, compare(split, *ref));
      char line[200];
      std::snprintf(line, sizeof line, "  bake %s %s: %.2f s (%zu run%s), %.3g MB, error %.3g (median sphere RMS)",
                    target.c_str(), label.c_str(), pt.seconds, pt.wall_seconds.size(),
                    pt.wall_seconds.size() == 1 ? "" : "s", double(pt.bytes) / 1e6, pt.error);
      say(line);
      if (o.keep_bakes.empty()) fs::remove_all(dir);
      bt.points.push_back(std::move(pt));
    }
    if (bt.points.empty() || bt.points.front().label != "default")
      throw Error("the bake sweep could not bake the default of target " + target +
                  (bt.skipped.empty() ? std::string() : " (" + bt.skipped.front() + ")"));
    mark_bake_sweep(bt);
    sweep.targets.push_back(std::move(bt));
  }
  sweep.seconds = since(t_start);
  return sweep;
}

}  // namespace brdfbake
