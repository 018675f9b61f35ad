// Dry-run estimates (brdfbake/plan.hpp, estimate_job): each table's wall time and bytes from
// measured speed on the device that would bake it.
//
// Why bakes at reduced size and not a throughput model: a table's time is set by its kernel, its
// sample counts, the refinement its error target asks for and, for the cube chains, the
// environment, and the bytes by the container, the pixel type and what the encoder compresses.
// A model of each would be a second description of every family kept in step with the code; a
// small bake of the same request measures all of it at once, on the device it will run on. Two
// sizes (1/2 and 1/4 of each side, the smaller one baked twice: the first bake of a kind pays its
// programs' loading) separate the fixed part (set-up, launches, headers) from the part that grows
// with the texels: t = a + b * work, bytes = c + d * work, extrapolated to the table's work. What this misses: costs
// not proportional to the texels (a chain's coarse levels, adaptive refinement that converges differently at another
// size, compression ratios).
//
// Every measurement goes through one timer (EstimateOptions::timer: the wall time of each step unless a caller gives
// its own), so the arithmetic (the fit, the extrapolation, a group's outputs, the environment's read once, the sum)
// is tested with known times whatever the machine's speed (tests/host/test_job.cpp, EstimateJob.*GivenClock).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "brdfbake/backend.hpp"
#include "brdfbake/cancel.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/plan.hpp"
#include "brdfbake/runner.hpp"
#include "job/group_tables.hpp"

namespace brdfbake {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// EstimateOptions::timer, or the wall time of the work.
using Timer = std::function<double(const EstimateStep&, const std::function<void()>&)>;
double time_step(const Timer& timer, const EstimateStep& step, const std::function<void()>& work) {
  if (timer) return timer(step, work);
  const auto t0 = Clock::now();
  work();
  return since(t0);
}

// The texels a request bakes, every level and face: the unit its time and bytes grow with.
double work_units(const TableRequest& t) {
  const double size = t.number(table_size_param(t.kind), 0);
  if (size <= 0) return 1;
  if (t.find("min_size")) {  // a cube chain: 6 faces a level, halving down to min_size
    double w = 0;
    const double min_size = std::max(1.0, t.number("min_size", 1));
    for (double s = size; s >= min_size; s = std::floor(s / 2)) {
      w += 6 * s * s;
      if (s <= 1) break;
    }
    return w;
  }
  if (t.kind == TableKind::Fresnel && t.text("table") != "2d") return size;  // 1-D: cells along cos_theta
  return size * t.number("height", size);
}

// The request with each side divided by `d`, or
// nothing when the smaller request does not validate (a target's power-of-two rule, a size floor).
std::optional<TableRequest> scaled(const TableRequest& t, int d) {
  TableRequest s = t;
  const char* size_param = table_size_param(t.kind);
  const double size = std::max(1.0, std::round(t.number(size_param) / d));
  s.set(size_param, size);
  if (t.find("height")) s.set("height", std::max(1.0, std::round(t.number("height") / d)));
  // A chain keeps its levels (each level's roughness and sample pattern as in the full chain): the
  // smallest level is divided too.
  if (t.find("min_size")) s.set("min_size", std::min(std::max(1.0, std::round(t.number("min_size") / d)), size));
  try {
    validate_table(s);
  } catch (const Error&) {
    return std::nullopt;
  }
  return s;
}

// One bake of a group's request and the delivery of each of its outputs.
struct Point {
  double work = 0, seconds = 0;
  std::vector<double> bytes;  // per output
};

// a + b * work through two points (work1 < work2), a >= 0 and b >= 0: a fixed part that comes out
// negative (noise) is dropped and the larger point scaled in proportion.
double extrapolate(double w1, double v1, double w2, double v2, double w) {
  if (w2 <= w1) return v2 * w / std::max(w2, 1.0);
  const double b = (v2 - v1) / (w2 - w1);
  const double a = v1 - b * w1;
  if (b <= 0 || a < 0) return v2 * w / w2;
  return a + b * w;
}

struct Measured {
  double seconds = 0;
  std::vector<std::uint64_t> bytes;
  std::string method;
};

std::mutex cache_mutex;
std::map<std::string, Measured>& group_cache() {
  static std::map<std::string, Measured> cache;
  return cache;
}
std::map<std::string, double>& environment_cache() {
  static std::map<std::string, double> cache;
  return cache;
}

// The key of a group's estimate in the cache: its bake, its device and environment, and each
// output's container, format and texels.
std::string group_key(const Job& job, const std::vector<size_t>& g) {
  const TableRequest& t = job.tables[g.front()];
  std::string key = t.device + "|" + t.environment + "|" + (job.sanitize ? "s" : "") + "|" + table_bake_key(t);
  for (size_t i : g) {
    const TableRequest& o = job.tables[i];
    const size_t dot = o.output.rfind('.');
    key += "|" + (dot == std::string::npos ? std::string() : o.output.substr(dot)) + "," + o.format + "," + o.pixel;
  }
  return key;
}

// A group measured on `backend`: baked at its own size when small, else at 1/4 and 1/2 of its sides
// and extrapolated in its texels.
Measured measure_group(const Job& job, const std::vector<size_t>& g, const BakeInputs& inputs, Backend& backend,
                       const std::function<bool()>& stop_requested, const Timer& timer) {
  const TableRequest& head = job.tables[g.front()];
  Measured m;
  // A bake of `t` (the head's sides divided or not) and the delivery of each output at its sides.
  const auto measure = [&](const TableRequest& t) {
    Point p;
    p.work = work_units(t);
    EstimateStep step;
    step.bake = &t;
    p.seconds = time_step(timer, step, [&] {
      TableRunOptions run;
      run.delivery = TableDelivery::Memory;
      run.backend = &backend;
      run.inputs = inputs;
      run.stop_requested = stop_requested;
      const TableRun tr = run_table(t, run);
      const BakeResult& r = tr.result;
      for (size_t i : g) {
        TableRequest o = job.tables[i];
        o.params = t.params;  // the outputs of a group share the bake's parameters
        const Delivery d = deliver_result(r, o, TableDelivery::Bytes);
        double b = 0;
        for (const auto& f : d.files) b += double(f.bytes.size());
        p.bytes.push_back(b);
      }
    });
    if (p.bytes.size() != g.size()) throw Error("estimate: the timer did not run the measuring bake of " + t.output);
    return p;
  };
  const double work = work_units(head);
  std::optional<TableRequest> half, quarter;
  if (head.find(table_size_param(head.kind)) && work > kEstimateMeasureBelow) {
    half = scaled(head, 2);
    quarter = scaled(head, 4);
  }
  // Each measurement follows a first bake of the same request, untimed: it builds or loads the kind's
  // programs (a size may launch variants another does not) and touches its allocations. The estimate pays that; the
  // bake after it finds the programs built (on a fresh machine, cold builds of ~1 s a program would otherwise count,
  // which the bake then does not pay: 9.4 s estimated for a 1.5 s bake with empty kernel caches).
  if (half && quarter && work_units(*quarter) < work_units(*half)) {
    measure(*quarter);
    measure(*half);  // a larger size may launch other variants of the kind's kernels
    const Point small = measure(*quarter);
    const Point large = measure(*half);
    m.seconds = extrapolate(small.work, small.seconds, large.work, large.seconds, work);
    for (size_t k = 0; k < g.size(); ++k)
      m.bytes.push_back(static_cast<std::uint64_t>(
          std::llround(extrapolate(small.work, small.bytes[k], large.work, large.bytes[k], work))));
    m.method = "scaled";
  } else {
    measure(head);
    const Point p = measure(head);
    m.seconds = p.seconds;
    for (double b : p.bytes) m.bytes.push_back(static_cast<std::uint64_t>(b));
    m.method = "measured";
  }
  return m;
}

}  // namespace

PlanEstimate estimate_job(const Job& given, const EstimateOptions& options) {
  const auto t_start = Clock::now();
  Job job = given;
  validate_job(job);
  // The groups of run_job (its defaults filled in): identical bakes, one bake for all their outputs.
  const std::vector<std::vector<size_t>> groups = detail::group_tables(job);

  PlanEstimate out;
  out.tables.resize(job.tables.size());
  for (size_t i = 0; i < job.tables.size(); ++i) {
    out.tables[i].output = job.tables[i].output;
    out.tables[i].kind = job.tables[i].kind;
  }

  std::map<std::string, EnvImage> environments;  // loaded only when a group must be measured
  std::map<std::string, double> read_seconds;    // the seconds of each read here
  EnvLoadOptions load;
  load.sanitize = job.sanitize;
  if (options.memory_budget) load.memory_budget = options.memory_budget;
  const auto environment = [&](const std::string& spec) -> EnvImage& {
    auto it = environments.find(spec);
    if (it == environments.end()) {
      EstimateStep step;
      step.environment = spec;
      const double seconds =
          time_step(options.timer, step, [&] { it = environments.emplace(spec, load_environment(spec, load)).first; });
      if (it == environments.end()) throw Error("estimate: the timer did not run the read of " + spec);
      read_seconds[spec] = seconds;
      if (!options.timer) {
        std::lock_guard<std::mutex> lock(cache_mutex);
        environment_cache()[spec + (job.sanitize ? "|s" : "")] = seconds;
      }
    }
    return it->second;
  };

  std::map<std::string, std::shared_ptr<Backend>> backends;
  const auto on_device = [&](const std::string& selector, const std::function<void(Backend&)>& work) {
    if (options.on_device) return options.on_device(selector, work);
    auto it = backends.find(selector);
    if (it == backends.end()) it = backends.emplace(selector, Backend::open(selector)).first;
    work(*it->second);
  };

  bool measured_any = false;
  for (size_t b = 0; b < groups.size(); ++b) {
    const std::vector<size_t>& g = groups[b];
    const std::string key = group_key(job, g);
    Measured m;
    bool cached = false;
    if (!options.timer) {
      std::lock_guard<std::mutex> lock(cache_mutex);
      auto it = group_cache().find(key);
      if (it != group_cache().end()) m = it->second, cached = true;
    }
    if (!cached) {
      measured_any = true;
      const TableRequest& head = job.tables[g.front()];
      BakeInputs inputs;
      if (table_kind_uses_environment(head.kind)) inputs.environment = &environment(head.environment);
      if (options.stop_requested && options.stop_requested()) throw Cancelled("cancelled: the estimate was stopped", 0);
      on_device(head.device, [&](Backend& backend) {
        m = measure_group(job, g, inputs, backend, options.stop_requested, options.timer);
      });
      if (!options.timer) {
        std::lock_guard<std::mutex> lock(cache_mutex);
        group_cache()[key] = m;
      }
    }
    for (size_t k = 0; k < g.size(); ++k) {
      TableEstimate& e = out.tables[g[k]];
      e.seconds = k == 0 ? m.seconds : 0.0;
      e.bake = static_cast<int>(b);
      e.bytes = m.bytes[k];
      e.method = m.method;
    }
  }

  // Each environment read once, as run_job reads them.
  std::vector<std::string> specs;
  for (const auto& t : job.tables)
    if (table_kind_uses_environment(t.kind) && std::find(specs.begin(), specs.end(), t.environment) == specs.end())
      specs.push_back(t.environment);
  for (const auto& spec : specs) {
    double seconds = -1;
    if (read_seconds.count(spec)) {
      seconds = read_seconds[spec];
    } else if (!options.timer) {
      std::lock_guard<std::mutex> lock(cache_mutex);
      auto it = environment_cache().find(spec + (job.sanitize ? "|s" : ""));
      if (it != environment_cache().end()) seconds = it->second;
    }
    if (seconds < 0) {
      environment(spec);
      measured_any = true;
      seconds = read_seconds[spec];
    }
    out.environment_seconds += seconds;
  }
  out.seconds = out.environment_seconds;
  for (const auto& e : out.tables) {
    out.seconds += e.seconds;
    out.bytes += e.bytes;
  }
  out.calibration_seconds = measured_any ? since(t_start) : 0.0;
  return out;
}

}  // namespace brdfbake
