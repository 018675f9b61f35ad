// Scene-driven baking against baking everything: for each scene, the wall time of `bake` (the
// planner's job, run_job) and of a bake of every table for the same environment, and the saving.
//
//   bake_bench [--scenes DIR] [--env SPEC] [--reps N] [--lut-size N] [--chain-size N] [--out FILE]
//
// "Every table" is what a pipeline without the planner bakes so that any material works: the three
// DFG tables (ggx, ggx-multiscatter, charlie), the GGX and Charlie prefiltered chains and the
// irradiance, plus the scene's own Fresnel and thin-film tables (a superset of the plan, so the
// difference is exactly what the planner leaves out). Both are run_job() calls, with the same
// sizes, device and environment, program binaries cached (one warm-up bake of everything first);
// each is run --reps times, alternating, and the fastest run is kept, in wall time and in CPU time
// (user + system of all the process's threads). Tables a kind of this build
// cannot bake (thin film when absent) are dropped from both sides, and said so.
// Writes a Markdown table (stdout, and --out FILE).
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "brdfbake/job.hpp"
#include "brdfbake/plan.hpp"

using namespace brdfbake;
namespace fs = std::filesystem;

namespace {

struct Options {
  std::string scenes;
  std::string env = "builtin:studio";
  int reps = 2;
  int lut_size = 128;
  int cube_size = 256;
  std::string out;
};

// Removes the tables this build cannot bake; returns how many.
int drop_unavailable(Job& job) {
  const size_t before = job.tables.size();
  job.tables.erase(std::remove_if(job.tables.begin(), job.tables.end(),
                                  [](const TableRequest& t) { return !table_kind_available(t.kind); }),
                   job.tables.end());
  return int(before - job.tables.size());
}

// Every table for the environment, plus the scene plan's scene-specific tables.
Job everything(const Plan& plan, const PlanOptions& o) {
  PlanOptions all = o;
  Job job = plan_default(all).job;  // ggx-multiscatter, GGX chain, irradiance
  const Plan with_sheen = plan_scene(
      parse_scene_json(R"({"asset":{"version":"2.0"},"materials":[{"pbrMetallicRoughness":{"metallicFactor":0},
                        "extensions":{"KHR_materials_sheen":{"sheenColorFactor":[1,1,1]}}}]})",
                       "every-table", ""),
      all);
  PlanOptions plain = all;
  plain.energy_compensation = false;
  const Plan single = plan_scene(parse_scene_json(R"({"asset":{"version":"2.0"},"materials":[{}]})", "ggx", ""), plain);
  auto add = [&](const TableRequest& t) {
    for (const auto& have : job.tables)
      if (have.output == t.output) return;
    job.tables.push_back(t);
  };
  for (const auto& t : with_sheen.job.tables) add(t);
  for (const auto& t : single.job.tables) add(t);
  for (const auto& t : plan.job.tables) add(t);
  job.source = "every table";
  validate_job(job);
  return job;
}

// Wall seconds and CPU seconds (user + system of every thread of the process: PoCL's workers
// included). On a machine shared with other work the CPU time is the steadier measure of the work
// done; on a GPU it would miss the device's share, and the wall time is the one to read.
struct Timing {
  double wall = 1e300, cpu = 1e300;
};

double cpu_seconds() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  auto s = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return s(u.ru_utime) + s(u.ru_stime);
}

void timed_run(Job job, const fs::path& dir, Timing& best) {
  fs::remove_all(dir);
  job.output_dir = dir.string();
  const double c0 = cpu_seconds();
  const auto t0 = std::chrono::steady_clock::now();
  run_job(job);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double cpu = cpu_seconds() - c0;
  fs::remove_all(dir);
  best.wall = std::min(best.wall, wall);
  best.cpu = std::min(best.cpu, cpu);
}

std::string kinds_of(const Job& job) {
  std::map<std::string, int> count;
  for (const auto& t : job.tables) {
    std::string k = table_kind_name(t.kind);
    if (t.kind == TableKind::Prefilter) k += "-" + t.text("distribution");
    ++count[k];
  }
  std::string s;
  for (const auto& [k, n] : count) s += (s.empty() ? "" : ", ") + (n > 1 ? std::to_string(n) + " " : "") + k;
  return s.empty() ? "nothing" : s;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
#ifdef BRDFBAKE_SHARED_DIR
  o.scenes = std::string(BRDFBAKE_SHARED_DIR) + "/scenes";
#endif
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "bake_bench: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--scenes")
      o.scenes = next();
    else if (a == "--env")
      o.env = next();
    else if (a == "--reps")
      o.reps = std::max(1, std::atoi(next().c_str()));
    else if (a == "--lut-size")
      o.lut_size = std::atoi(next().c_str());
    else if (a == "--chain-size" || a == "--cube-size")  // --cube-size: its old name
      o.cube_size = std::atoi(next().c_str());
    else if (a == "--out")
      o.out = next();
    else {
      std::fprintf(
          stderr,
          "usage: bake_bench [--scenes DIR] [--env SPEC] [--reps N] [--lut-size N] [--chain-size N] [--out FILE]\n");
      return 2;
    }
  }
  if (o.scenes.empty() || !fs::exists(o.scenes)) {
    std::fprintf(stderr, "bake_bench: no scenes folder ('%s'); give --scenes DIR\n", o.scenes.c_str());
    return 2;
  }
  std::vector<fs::path> scenes;
  for (const auto& e : fs::directory_iterator(o.scenes))
    if (e.path().extension() == ".gltf" || e.path().extension() == ".glb") scenes.push_back(e.path());
  std::sort(scenes.begin(), scenes.end());

  PlanOptions po;
  po.environment = o.env;
  po.lut_size = o.lut_size;
  po.chain_size = o.cube_size;
  const fs::path work = fs::temp_directory_path() / ("brdfbake-bake-bench-" + std::to_string(::getpid()));

  std::ostringstream md;
  char line[512];
  std::string device;
  try {
    device = Device::open().info().name;
  } catch (const Error&) {
  }
  md << "Environment `" << o.env << "`, DFG tables " << o.lut_size << "², chains " << o.cube_size
     << "² (chain_max_error " << po.chain_max_error << "), device " << device << ", fastest of " << o.reps
     << " runs.\n\n";
  md << "| scene | planned tables | every table | bake wall (s) | every table wall (s) | saving (wall) | bake CPU (s) "
        "| "
        "every table CPU (s) | saving (CPU) |\n";
  md << "|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  std::printf("%s", md.str().c_str());
  std::fflush(stdout);

  // Warm-up: builds (or loads) every program once.
  {
    const Plan p = plan_default(po);
    Job all = everything(p, po);
    drop_unavailable(all);
    Timing ignored;
    timed_run(all, work / "warmup", ignored);
  }
  double sum_plan = 0, sum_all = 0, cpu_plan = 0, cpu_all = 0;
  int dropped_total = 0;
  for (const auto& scene : scenes) {
    const Plan plan = plan_scene(read_scene(scene.string()), po);
    Job job = plan.job;
    Job all = everything(plan, po);
    dropped_total += drop_unavailable(job);
    drop_unavailable(all);
    Timing t_plan, t_all;
    for (int r = 0; r < o.reps; ++r) {
      timed_run(job, work / "plan", t_plan);
      timed_run(all, work / "all", t_all);
    }
    sum_plan += t_plan.wall;
    sum_all += t_all.wall;
    cpu_plan += t_plan.cpu;
    cpu_all += t_all.cpu;
    std::snprintf(line, sizeof line, "| %s | %zu: %s | %zu | %.2f | %.2f | %.0f%% | %.2f | %.2f | %.0f%% |\n",
                  scene.stem().string().c_str(), job.tables.size(), kinds_of(job).c_str(), all.tables.size(),
                  t_plan.wall, t_all.wall, 100.0 * (1.0 - t_plan.wall / t_all.wall), t_plan.cpu, t_all.cpu,
                  100.0 * (1.0 - t_plan.cpu / t_all.cpu));
    md << line;
    std::printf("%s", line);
    std::fflush(stdout);
  }
  std::snprintf(line, sizeof line, "| **all %zu scenes** | | | %.1f | %.1f | %.0f%% | %.1f | %.1f | %.0f%% |\n",
                scenes.size(), sum_plan, sum_all, 100.0 * (1.0 - sum_plan / sum_all), cpu_plan, cpu_all,
                100.0 * (1.0 - cpu_plan / cpu_all));
  md << line;
  std::printf("%s", line);
  if (dropped_total > 0) {
    std::snprintf(line, sizeof line,
                  "\n%d planned tables of kinds this build cannot bake were left out of both sides.\n", dropped_total);
    md << line;
    std::printf("%s", line);
  }
  fs::remove_all(work);
  if (!o.out.empty()) std::ofstream(o.out) << md.str();
  return 0;
}
