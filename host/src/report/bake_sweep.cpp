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
#include <malloc.h>
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
#include "families/preview/bake_files.hpp"
#include "families/preview/ideal.hpp"
#include "families/preview/model.hpp"
#include "families/preview/render.hpp"
#include "families/preview/splitsum.hpp"
#include "io/staging_dir.hpp"

namespace brdfbake {

// What moves the bake's share of the render's error (issue 35): the chain's sizes, its schedule where
// the engine reads it, its refinement and its texels' storage (ASTC where the target takes it). The
// DFG table's size and axis and the SH order moved no target's render by 0.1 % of itself in the
// sweeps of docs/REPORT.md: `--vary lut_size=16,32` and the like measure them on demand. Chains above
// the default 256^2 too (`--vary chain_size=512`): the ideal bake of a 512^2 chain filters its levels
// from a 1024^2 source, ~600 MB more at its peak (babylon's ten levels: 0.95 GB for the sweep), over
// the default sweep's memory budget of 600 MB.
const std::vector<std::pair<std::string, std::vector<std::string>>> kDefaultBakeFactors = {
    {"chain_size", {"64", "128"}},
    {"min_size", {"4", "64"}},
    {"schedule", {"sqrt"}},
    {"chain_max_error", {"0.03", "0.003"}},
    {"pixel", {"f32", "astc4x4", "astc6x6"}},
};

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

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

// The reference render is of the split-sum render's layout (the errors compare them pixel by pixel).
void check_layout(const PreviewResult& reference, const detail::preview::Layout& layout) {
  if (reference.reference.width != layout.width || reference.reference.height != layout.height ||
      reference.spheres.size() != layout.spheres.size())
    throw Error("the bake sweep's reference render has another layout than the split-sum render");
}

// The material groups of the spheres: the first word of each material's name ("gold r0.2": gold), in
// order of first appearance; per group the error's, the shares' and the probe's figures. `stats`: per
// sphere the error against the reference and its shares, as render_preview states them (sphere_errors
// then add_shares).
void fill_errors(BakeSweepPoint& pt, const PreviewResult& split, const std::vector<PreviewSphereStats>& stats,
                 const std::vector<double>& sharp) {
  std::vector<std::string> order;
  std::map<std::string, std::vector<size_t>> by;
  for (size_t s = 0; s < stats.size(); ++s) {
    pt.sphere_rms.push_back(stats[s].linear.rms);
    pt.sphere_p99.push_back(stats[s].linear.p99);
    pt.sphere_max.push_back(stats[s].linear.max);
    pt.sphere_bake.push_back(stats[s].bake_share.rms);
    pt.sphere_engine.push_back(stats[s].engine_share.rms);
    pt.sphere_sharp.push_back(sharp[s]);
    const std::string& name = split.spheres[s].material.name;
    const std::string group = name.substr(0, name.find(' '));
    if (!by.count(group)) order.push_back(group);
    by[group].push_back(s);
  }
  for (const auto& name : order) {
    std::vector<double> total, bake, engine;
    BakeSweepGroup g;
    g.name = name;
    for (size_t s : by[name]) {
      total.push_back(pt.sphere_rms[s]);
      bake.push_back(pt.sphere_bake[s]);
      engine.push_back(pt.sphere_engine[s]);
      g.sharp = std::max(g.sharp, pt.sphere_sharp[s]);
    }
    g.median_rms = median(total);
    g.max_rms = *std::max_element(total.begin(), total.end());
    g.bake_median = median(bake);
    g.bake_worst = *std::max_element(bake.begin(), bake.end());
    g.engine_median = median(engine);
    g.engine_worst = *std::max_element(engine.begin(), engine.end());
    pt.groups.push_back(g);
  }
  pt.error = median(pt.sphere_rms);
  pt.bake_error = median(pt.sphere_bake);
  pt.engine_error = median(pt.sphere_engine);
}

// Bakes `job` into `dir` once more and adds its wall time to pt (the folder is replaced).
void timed_bake(const Job& job, const fs::path& dir, const RunOptions& ro, BakeSweepPoint& pt) {
  fs::remove_all(dir);
  const auto t0 = Clock::now();
  run_job(job, {}, ro);
  pt.wall_seconds.push_back(since(t0));
  pt.seconds = median(pt.wall_seconds);
  const auto [lo, hi] = std::minmax_element(pt.wall_seconds.begin(), pt.wall_seconds.end());
  pt.spread = *hi - *lo;
}

}  // namespace

void mark_bake_sweep(BakeSweepTarget& t) {
  auto dominated = [&](size_t i, auto cost) {
    for (size_t j = 0; j < t.points.size(); ++j) {
      if (j == i) continue;
      const double ci = cost(t.points[i]), cj = cost(t.points[j]);
      const double ei = t.points[i].bake_error, ej = t.points[j].bake_error;
      if (cj <= ci && ej <= ei && (cj < ci || ej < ei)) return true;
    }
    return false;
  };
  for (size_t i = 0; i < t.points.size(); ++i) {
    t.points[i].pareto_time = !dominated(i, [](const BakeSweepPoint& p) { return p.seconds; });
    t.points[i].pareto_bytes = !dominated(i, [](const BakeSweepPoint& p) { return double(p.bytes); });
  }
  t.recommended = -1;
  t.ties.clear();
  t.why.clear();
  if (t.points.empty()) return;
  // The settings no blurrier than the default (their probe within kBakeSharpWithin of the default's on
  // every group); per group, the best bake share any of them reached on its worst sphere. A setting
  // that blurs the mirrors does not set the bar: ASTC 6x6 reads 16 % lower on venice's gold mirror
  // (its blocks smooth what the 20-pixel sphere's pixels sample) with a 16 % blurrier probe.
  const BakeSweepPoint& def = t.points.front();
  std::map<std::string, double> default_sharp;
  for (const auto& g : def.groups)
    if (g.sharp >= 0.0) default_sharp[g.name] = g.sharp;
  // ... and whose engine share is no larger than the default's on any group (its median, within the
  // same 2 %): a setting that changes the chain's level count changes how the engine reads it (the
  // LOD from roughness), which the bake's share does not see (generic's min_size=64 under venice: the
  // same bake share, the engine's 12.0 % -> 14.4 %).
  std::map<std::string, double> default_engine;
  for (const auto& g : def.groups) default_engine[g.name] = g.engine_median;
  const auto sharp_ok = [&](const BakeSweepPoint& p) {
    for (const auto& g : p.groups) {
      const auto ds = default_sharp.find(g.name);
      if (ds != default_sharp.end() && g.sharp >= 0.0 && g.sharp > kBakeSharpWithin * ds->second) return false;
      const auto de = default_engine.find(g.name);
      if (de != default_engine.end() && g.engine_median > kBakeSharpWithin * de->second) return false;
    }
    return true;
  };
  std::map<std::string, double> best;
  for (const auto& p : t.points)
    if (sharp_ok(p))
      for (const auto& g : p.groups) {
        auto it = best.find(g.name);
        if (it == best.end() || g.bake_worst < it->second) best[g.name] = g.bake_worst;
      }
  // How far a setting is from the best on its worst group (1: the best on every group).
  const auto ratio = [&](const BakeSweepPoint& p) {
    double r = 1.0;
    for (const auto& g : p.groups)
      if (best[g.name] > 0.0) r = std::max(r, g.bake_worst / best[g.name]);
    return r;
  };
  for (auto& p : t.points) p.eligible = sharp_ok(p) && ratio(p) <= kBakeRecommendWithin;
  int fastest = -1;
  for (size_t i = 0; i < t.points.size(); ++i)
    if (t.points[i].eligible && (fastest < 0 || t.points[i].seconds < t.points[size_t(fastest)].seconds))
      fastest = int(i);
  if (fastest < 0) {
    // The settings trade one group against another: the one closest to the best on its worst group.
    int closest = 0;
    for (size_t i = 0; i < t.points.size(); ++i)
      if (sharp_ok(t.points[i]) && ratio(t.points[i]) < ratio(t.points[size_t(closest)])) closest = int(i);
    t.recommended = closest;
    char text[200];
    std::snprintf(text, sizeof text,
                  "no setting is within the tolerance on every group (they trade one group against another): %s is "
                  "the closest, %.0f %% above the best on its worst group",
                  t.points[size_t(closest)].label.c_str(), 100.0 * (ratio(t.points[size_t(closest)]) - 1.0));
    t.why = text;
    return;
  }
  // The ties: eligible settings whose median differs from the fastest's by less than either spread.
  const BakeSweepPoint& f = t.points[size_t(fastest)];
  std::vector<int> tied;
  for (size_t i = 0; i < t.points.size(); ++i) {
    const BakeSweepPoint& p = t.points[i];
    if (p.eligible && std::abs(p.seconds - f.seconds) <= std::max(p.spread, f.spread)) tied.push_back(int(i));
  }
  // of the tied, the fewest bytes; on equal bytes the first in the sweep's order (the default, when it
  // ties: no change to make)
  int pick = tied.front();
  for (int i : tied)
    if (t.points[size_t(i)].bytes < t.points[size_t(pick)].bytes) pick = i;
  t.recommended = pick;
  for (int i : tied)
    if (i != pick) t.ties.push_back(t.points[size_t(i)].label);
  int eligible = 0;
  for (const auto& p : t.points) eligible += p.eligible ? 1 : 0;
  const BakeSweepPoint& r = t.points[size_t(pick)];
  char text[160];
  std::snprintf(text, sizeof text, "%d of %zu settings within the tolerances; ", eligible, t.points.size());
  t.why = text;
  if (eligible == 1) {
    t.why += r.label;
  } else if (t.ties.empty()) {
    t.why += r.label + " is the fastest of them";
  } else {
    std::string list;
    for (const auto& l : t.ties) list += (list.empty() ? "" : ", ") + l;
    bool as_few = false;
    for (const auto& l : t.ties)
      for (const auto& p : t.points) as_few = as_few || (p.label == l && p.bytes == r.bytes);
    t.why += r.label + " ties in time with " + list + " (their medians differ by less than their spread): of them it " +
             (as_few ? "writes the fewest bytes and comes first in the sweep of those that write as few"
                     : "writes the fewest bytes");
  }
  if (eligible == 1)
    t.why += " (the only one: not timed again)";
  else if (r.wall_seconds.size() < 2)
    t.why += "; timed once (no spread)";
}

void check_bake_sweep(const BakeSweepOptions& o) {
  if (o.preview_width < 96 || o.preview_width > kPreviewMaxSize)
    throw Error("the bake sweep's preview width must be 96 to " + std::to_string(kPreviewMaxSize) +
                " (12 columns of spheres at least 8 pixels wide)");
  if (o.runs < 1 || o.runs > 9) throw Error("the bake sweep's runs must be 1 to 9");
  for (const auto& t : o.targets) engine_target_from_name(t);  // throws, listing the targets
  // The sweep replaces KEEP/TARGET/SETTING folders: only a new or an empty folder is taken, before
  // anything runs (issue 34, class 1).
  if (!o.keep_bakes.empty() && !io::is_new_or_empty_folder(o.keep_bakes)) {
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
  using namespace detail::preview;
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
    // The ideal bake's parts (ideal.hpp), shared by settings of the same key: the default's, kept for
    // the whole target (most settings change the storage or the refinement, not the chain's shape),
    // and the last other one. At most these two are held (the memory of the sweep).
    std::shared_ptr<IdealParts> default_parts, other_parts;
    std::string default_job;
    std::vector<Job> jobs;  // the job of each point, for the timing runs that follow
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
        timed_bake(job, dir, ro, pt);
      } catch (const Cancelled&) {
        throw;  // SIGINT, SIGTERM: the whole report stops
      } catch (const Error& e) {
        bt.skipped.push_back(label + ": " + e.what());
        say("  bake " + target + " " + label + ": failed (" + e.what() + ")");
        continue;
      }
      folder_size(dir, &pt.bytes, &pt.files);
      if (!o.keep_bakes.empty()) pt.folder = dir.string();

      PreviewSpec spec;
      spec.target = engine_target_from_name(target);
      spec.bake = dir.string();
      spec.width = o.preview_width;
      spec.height = o.preview_width / 2;
      spec.reference = false;
      spec.shares = false;  // the shares below, the ideal bake shared between settings
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
      // The ideal bake of these files (its parts shared where the key is the same) and its split-sum
      // render; the shares against the reference as render_preview computes them; the probe.
      t0 = Clock::now();
      BakeFiles files = read_bake_files(dir.string(), spec.target, env.source);
      const std::string key = ideal_parts_key(files);
      std::shared_ptr<IdealParts> parts = default_parts && default_parts->key == key ? default_parts
                                          : other_parts && other_parts->key == key   ? other_parts
                                                                                     : nullptr;
      if (!parts) {
        other_parts.reset();  // its memory first
        parts = std::make_shared<IdealParts>(ideal_parts(*backend, env, files));
        (option.empty() ? default_parts : other_parts) = parts;
      }
      SplitSumOptions split_options;
      split_options.babylon_mix_ibl_radiance_with_irradiance = split.spec.mix_ibl_radiance_with_irradiance;
      const SplitSum ideal_split(apply_ideal_parts(*parts, files).files, split_options);
      const SplitSum files_split(std::move(files), split_options);
      const Layout layout = make_layout(split.spec);
      const std::vector<SpherePixel> pixels = sphere_pixels(layout);
      PreviewResult shares = split;  // its split-sum image and spheres, with the reference and the ideal
      shares.reference = ref->reference;
      render_split_sum(layout, pixels, ideal_split, view_vector(layout.camera), shares, shares.ideal);
      check_layout(*ref, layout);
      shares.stats = sphere_errors(layout, pixels, shares.splitsum, shares.reference, shares.exposure);
      add_shares(layout, pixels, shares);
      const std::vector<double> sharp = sharp_probe(layout, files_split, ideal_split);
      pt.ideal_seconds = since(t0);
      fill_errors(pt, split, shares.stats, sharp);
      char line[260];
      std::snprintf(line, sizeof line,
                    "  bake %s %s: %.2f s, %.3g MB, error %.3g (median sphere RMS), bake share %.3g, engine share %.3g",
                    target.c_str(), label.c_str(), pt.seconds, double(pt.bytes) / 1e6, pt.error, pt.bake_error,
                    pt.engine_error);
      say(line);
      if (o.keep_bakes.empty()) fs::remove_all(dir);
      bt.points.push_back(std::move(pt));
      ::malloc_trim(0);  // the freed chains back to the system, not kept in the heap for the next
      jobs.push_back(std::move(job));
    }
    if (bt.points.empty() || bt.points.front().label != "default")
      throw Error("the bake sweep could not bake the default of target " + target +
                  (bt.skipped.empty() ? std::string() : " (" + bt.skipped.front() + ")"));
    // The settings the recommendation may take are timed again, up to `runs` runs each: the median
    // and the spread that decide it (the others keep their one run). One bake's files at a time.
    // With one setting eligible, no time decides: it is not timed again.
    mark_bake_sweep(bt);
    const auto eligible = std::count_if(bt.points.begin(), bt.points.end(), [](const auto& p) { return p.eligible; });
    for (size_t i = 0; i < bt.points.size() && eligible > 1; ++i) {
      BakeSweepPoint& pt = bt.points[i];
      if (!pt.eligible) continue;
      const fs::path dir = root / target / ("timing-" + pt.label);
      Job job = jobs[i];
      job.output_dir = dir.string();
      while (int(pt.wall_seconds.size()) < o.runs) timed_bake(job, dir, ro, pt);
      fs::remove_all(dir);
    }
    mark_bake_sweep(bt);
    say("  " + target + ": recommended " +
        (bt.recommended >= 0 ? bt.points[size_t(bt.recommended)].label : std::string("none")) + " (" + bt.why + ")");
    sweep.targets.push_back(std::move(bt));
  }
  sweep.seconds = since(t_start);
  return sweep;
}

}  // namespace brdfbake
