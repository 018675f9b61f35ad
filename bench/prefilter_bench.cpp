// Prefiltered environment maps: device time and error against the brute-force reference.
//
//   prefilter_bench [--quick] [--timing-only] [--default-only] [--charlie] [--per-texel] [--out DIR] [--shared DIR]
//   [--env SPEC]...
//
// --default-only: the default chain's time and per-level errors, no sweep (the accuracy check of a
// change to the default path); --charlie: the same chain with the Charlie lobe; --per-texel: the
// quadrature's former walk per texel (PrefilterSpec::strips off), the accuracy reference of the strips.
//
// For every environment (builtin:studio, builtin:sun, and the real maps of ../shared/envmaps when
// present), at 1024x512 input, the default chain (--size 256 --min-size 16, GGX, linear schedule):
//   * device time of the whole chain, conversion included (median of 3 runs after a warm-up;
//     OpenCL event profiling);
//   * error per level against the scalar double reference (host/reference/src/envmap.cpp) filtering
//     the same 256^2 source cube, on 16 x 16 texels of every face of every level (all of them at
//     16^2): RMS and max relative error per channel, |P - P_ref| / max(P_ref, 1e-3 mean);
//   * a sweep: the quadrature's refinement, and the sampling estimator's sample counts with and
//     without filtered importance sampling, each with and without environment sampling (the exact
//     bright-texel sum); device time of the filtering and the worst level's errors;
//   * the reference's time per texel and its extrapolation to the whole chain, the baseline.
// Writes DIR/prefilter_bench.md (tables for docs/BENCHMARKS.md) and DIR/prefilter_bench.csv
// (one row a run, for bench/plot_prefilter.gp).
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/reference/envmap.hpp"

using namespace brdfbake;
namespace fs = std::filesystem;

namespace {

struct Errors {
  double rms = 0, max = 0;
};

// CPU seconds this process has used (user + system): under load, the event-timed device time
// stretches while the CPU time of the work stays put; CPU / cores estimates an idle machine's time.
double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec) + double(u.ru_stime.tv_sec) +
         1e-6 * double(u.ru_stime.tv_usec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

reference::EnvCube to_env_cube(const CubeLevels& c) {
  reference::EnvCube e;
  e.size = c.size;
  e.rgb.resize(18u * size_t(c.size) * size_t(c.size));
  for (size_t t = 0; t < 6u * size_t(c.size) * size_t(c.size); ++t)
    for (size_t k = 0; k < 3; ++k) e.rgb[3 * t + k] = c.levels[0][4 * t + k];
  return e;
}

// The texels of a level compared against the reference: a 16 x 16 grid per face (all at <= 16).
struct Probe {
  int face, i, j;
};
std::vector<Probe> probes(int size) {
  const int n = std::min(size, 16), stride = size / n;
  std::vector<Probe> p;
  for (int f = 0; f < 6; ++f)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) p.push_back({f, i * stride + stride / 2, j * stride + stride / 2});
  return p;
}

struct RefLevel {
  std::vector<Probe> probes;
  std::vector<double> values;  // 3 per probe
  double mean = 0;
  double seconds = 0;
};

RefLevel reference_level(const reference::EnvCube& src, EnvDistribution d, double roughness, int size) {
  RefLevel r;
  r.probes = probes(size);
  std::vector<Vec3> dirs;
  for (const auto& p : r.probes) dirs.push_back(math::cube_texel_direction(p.face, size, p.i, p.j));
  const auto t0 = std::chrono::steady_clock::now();
  r.values = reference::prefilter_directions(
      src, d == EnvDistribution::Ggx ? reference::EnvLobe::Ggx : reference::EnvLobe::Charlie, roughness, dirs);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  double sum = 0;
  for (double v : r.values) sum += v;
  r.mean = sum / double(r.values.size());
  return r;
}

Errors level_errors(const CubeLevels& got, int level, const RefLevel& ref) {
  Errors e;
  double sum = 0;
  size_t n = 0;
  for (size_t k = 0; k < ref.probes.size(); ++k) {
    const auto& p = ref.probes[k];
    const float* t = got.texel(level, p.face, p.i, p.j);
    for (size_t c = 0; c < 3; ++c) {
      const double want = ref.values[3 * k + c];
      const double d = std::fabs(double(t[c]) - want) / std::max(want, 1e-3 * ref.mean);
      sum += d * d;
      e.max = std::max(e.max, d);
      ++n;
    }
  }
  e.rms = std::sqrt(sum / double(n));
  return e;
}

struct Run {
  CubeLevels cube;
  double seconds = 0;
  std::vector<double> level_seconds;
};

Run timed(Device& dev, const CubeLevels& source, const PrefilterSpec& spec, int runs) {
  Run r;
  PrefilterTiming t;
  r.cube = prefilter_cube(dev, source, spec, &t);  // warm-up: program builds
  std::vector<double> times;
  std::vector<std::vector<double>> levels;
  for (int k = 0; k < runs; ++k) {
    PrefilterTiming tk;
    prefilter_cube(dev, source, spec, &tk);
    times.push_back(tk.device_seconds);
    levels.push_back(tk.level_device_seconds);
  }
  r.seconds = median(times);
  r.level_seconds = levels[0];
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false, timing_only = false, default_only = false, charlie = false, per_texel = false;
  std::string out_dir = "bench-out", shared = "";
  std::vector<std::string> envs;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick"))
      quick = true;
    else if (!std::strcmp(argv[i], "--timing-only"))
      timing_only = true;
    else if (!std::strcmp(argv[i], "--default-only"))
      default_only = true;
    else if (!std::strcmp(argv[i], "--charlie"))
      charlie = true;
    else if (!std::strcmp(argv[i], "--per-texel"))
      per_texel = true;
    else if (!std::strcmp(argv[i], "--out") && i + 1 < argc)
      out_dir = argv[++i];
    else if (!std::strcmp(argv[i], "--shared") && i + 1 < argc)
      shared = argv[++i];
    else if (!std::strcmp(argv[i], "--env") && i + 1 < argc)
      envs.push_back(argv[++i]);
    else {
      std::fprintf(stderr,
                   "usage: prefilter_bench [--quick] [--timing-only] [--default-only] [--charlie] [--per-texel] [--out "
                   "DIR] [--shared DIR] [--env SPEC]...\n");
      return 2;
    }
  }
  if (envs.empty()) {
    envs = {"builtin:studio", "builtin:sun"};
    if (shared.empty()) shared = "../shared";
    for (const char* f :
         {"rooitou_park_1k.hdr", "venice_sunset_1k.hdr", "studio_small_03_1k.hdr", "potsdamer_platz_1k.hdr"}) {
      const fs::path p = fs::path(shared) / "envmaps" / f;
      if (fs::exists(p)) envs.push_back(p.string());
    }
  }
  fs::create_directories(out_dir);
  Device dev = Device::open();
  std::printf("device: %s (%s)\n", dev.info().name.c_str(), dev.info().driver_version.c_str());
  auto load_average = [] {
    std::ifstream in("/proc/loadavg");
    std::string one;
    in >> one;
    return one.empty() ? std::string("?") : one;
  };
  std::ofstream md(out_dir + "/prefilter_bench.md"), csv(out_dir + "/prefilter_bench.csv");
  csv << "env,estimator,variant,parameter,device_seconds,worst_level_rms,worst_level_max\n";

  PrefilterSpec base;  // the defaults: 256 -> 16, GGX, linear
  if (charlie) base.distribution = EnvDistribution::Charlie;
  if (per_texel) base.strips = false;
  const int levels = prefilter_level_count(base);

  for (const std::string& name : envs) {
    const EnvImage env = load_environment(name);
    const std::string label = fs::path(name).filename().string();
    std::printf("== %s (%s)\n", label.c_str(), env.description.c_str());
    double convert = 0;
    const CubeLevels source = environment_to_cube(dev, env, base.size, &convert);
    // the default chain from the 1024x512 input: conversion + filtering
    std::vector<double> chain_times, chain_cpu, chain_wall;
    for (int k = 0; k < 4; ++k) {
      PrefilterTiming t;
      const double c0 = cpu_seconds();
      prefilter_environment(dev, env, base, &t);
      if (k > 0) {
        chain_times.push_back(t.device_seconds);
        chain_cpu.push_back(cpu_seconds() - c0);
        chain_wall.push_back(t.wall_seconds);
      }
    }
    const double chain = median(chain_times), cpu = median(chain_cpu), wall = median(chain_wall);
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    std::printf("default chain: %.3f s device, %.3f s wall, %.3f CPU s (%.3f s on %u idle cores)\n", chain, wall, cpu,
                cpu / cores, cores);
    md << "\n### " << label << "\n\nDefault chain (256^2 -> 16^2, " << levels << " levels, GGX) from " << env.width
       << "x" << env.height << ": **" << chain << " s** device time (load average " << load_average() << "), " << wall
       << " s wall; the process used " << cpu << " CPU s, **" << cpu / cores << " s** on " << cores << " idle cores.\n";
    csv << label << ",default,chain,0," << chain << ",0,0\n";
    if (timing_only) continue;

    const reference::EnvCube src = to_env_cube(source);
    std::vector<RefLevel> refs(static_cast<size_t>(levels));
    double ref_seconds = 0, ref_texels = 0, chain_texels = 0;
    for (int l = 1; l < levels; ++l) {
      const int size = base.size >> l;
      refs[size_t(l)] = reference_level(src, base.distribution, schedule_roughness(base.schedule, l, levels), size);
      ref_seconds += refs[size_t(l)].seconds;
      ref_texels += double(refs[size_t(l)].probes.size());
      chain_texels += 6.0 * size * size;
      std::printf("  reference level %d: %zu texels, %.2f s\n", l, refs[size_t(l)].probes.size(),
                  refs[size_t(l)].seconds);
    }
    md << "\nReference (scalar double, brute force over all " << 6 * base.size * base.size
       << " source texels, 2 threads): " << ref_seconds / ref_texels * 1e3 << " ms per texel, "
       << ref_seconds / ref_texels * chain_texels << " s for the whole chain (extrapolated).\n\n";

    // Per-level errors of the default.
    {
      const Run r = timed(dev, source, base, quick ? 1 : 3);
      md << "| level | size | roughness | refinement | device ms | RMS rel. error | max rel. error "
            "|\n|---:|---:|---:|---:|---:|---:|---:|\n";
      for (int l = 1; l < levels; ++l) {
        const Errors e = level_errors(r.cube, l, refs[size_t(l)]);
        md << "| " << l << " | " << (base.size >> l) << " | " << schedule_roughness(base.schedule, l, levels) << " | "
           << base.refinement << " | " << r.level_seconds[size_t(l)] * 1e3 << " | " << e.rms << " | " << e.max
           << " |\n";
        std::printf("  level %d: rms %.4f max %.4f (%.1f ms)\n", l, e.rms, e.max, r.level_seconds[size_t(l)] * 1e3);
      }
    }

    if (default_only) continue;
    // The sweep.
    struct Variant {
      const char* estimator;  // quadrature | sampling
      const char* name;
      bool fis;
      int bright;
    };
    const Variant variants[] = {{"quadrature", "quadrature+env", true, -1}, {"quadrature", "quadrature", true, 0},
                                {"sampling", "FIS+env", true, -1},          {"sampling", "FIS", true, 0},
                                {"sampling", "plain+env", false, -1},       {"sampling", "plain", false, 0}};
    const std::vector<double> refinements = quick ? std::vector<double>{2, 4} : std::vector<double>{2, 3, 4, 6};
    const std::vector<int> counts = quick ? std::vector<int>{32, 256} : std::vector<int>{16, 64, 256, 1024};
    md << "\n| estimator | variant | refinement / samples | device s (filtering) | worst level RMS | worst level max "
          "|\n"
          "|---|---|---:|---:|---:|---:|\n";
    for (const Variant& v : variants) {
      const bool quadrature = std::string(v.estimator) == "quadrature";
      const size_t n = quadrature ? refinements.size() : counts.size();
      for (size_t k = 0; k < n; ++k) {
        PrefilterSpec s = base;
        s.estimator = quadrature ? EnvEstimator::Quadrature : EnvEstimator::Sampling;
        if (quadrature)
          s.refinement = refinements[k];
        else
          s.samples = counts[k];
        s.filtered_importance_sampling = v.fis;
        s.bright_texels = v.bright;
        const Run r = timed(dev, source, s, quick ? 1 : 2);
        double worst_rms = 0, worst_max = 0;
        for (int l = 1; l < levels; ++l) {
          const Errors e = level_errors(r.cube, l, refs[size_t(l)]);
          worst_rms = std::max(worst_rms, e.rms);
          worst_max = std::max(worst_max, e.max);
        }
        const double param = quadrature ? refinements[k] : double(counts[k]);
        md << "| " << v.estimator << " | " << v.name << " | " << param << " | " << r.seconds << " | " << worst_rms
           << " | " << worst_max << " |\n";
        csv << label << "," << v.estimator << "," << v.name << "," << param << "," << r.seconds << "," << worst_rms
            << "," << worst_max << "\n";
        std::printf("  %-10s %-15s %6g: %.3f s  rms %.4f  max %.4f\n", v.estimator, v.name, param, r.seconds, worst_rms,
                    worst_max);
        std::fflush(stdout);
      }
    }
  }
  return 0;
}
