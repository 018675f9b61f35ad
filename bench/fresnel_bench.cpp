// What each Fresnel model costs and what each approximation gets wrong.
//
//   fresnel_bench [--quick] [--cells N] [--out FILE]
//
// 1. Device throughput of every model, fp32 and fp64: a 1-D RGB table of N cells (default 1<<22),
//    kernel time from OpenCL event profiling (the output is made resident before the timed kernel),
//    a warm-up, then rounds that time every model once each (15 to 51, ~1 s of the slowest
//    kernel): the median and the fastest round, and each model's time over Schlick's. Beside it
//    the kernel's own max error against the reference (a 65536-cell table).
// 2. The scalar double reference, one thread, on the same settings: cells per second.
// 3. Every approximation against the exact model (conductor for metals, dielectric for dielectrics)
//    for every preset: max and mean |approx - exact| over 4097 cosines in [0, 1], all channels.
// Prints markdown and writes it to FILE (docs/BENCHMARKS.md's "Fresnel" section comes from it).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "brdfbake/fresnel.hpp"

using namespace brdfbake;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// The setting each model is timed with: gold for the metal models, glass for the real-index ones.
FresnelSpec timed_spec(FresnelModel m, int cells, Precision p) {
  FresnelSpec s;
  s.model = m;
  s.size = cells;
  s.precision = p;
  if (m == FresnelModel::Empirical) {
    s.bias = 0.04;
    s.scale = 0.96;
    s.power = 5.0;
  } else if (m == FresnelModel::SchlickIor || m == FresnelModel::Dielectric) {
    s.material = "glass";
  } else {
    s.material = "gold";
  }
  return s;
}

std::string setting(FresnelModel m) {
  if (m == FresnelModel::Empirical) return "bias 0.04, scale 0.96, power 5";
  return m == FresnelModel::SchlickIor || m == FresnelModel::Dielectric ? "glass" : "gold";
}

// Device times of every model at one precision, measured in rounds: each round times every model
// once, so that a ratio to Schlick compares kernels run seconds apart (the machine may be shared).
// Per model: the median time, and the median over rounds of its time over Schlick's in that round.
struct DeviceRuns {
  std::vector<double> seconds, fastest, ratio;
  int rounds = 0;
};

DeviceRuns time_device(Device& dev, int cells, Precision p) {
  const std::vector<FresnelModel>& models = fresnel_models();
  FresnelTiming t;
  double slowest = 0.0;
  for (FresnelModel m : models) {  // warm-up: program builds, allocator
    bake_fresnel(dev, timed_spec(m, cells, p), &t);
    bake_fresnel(dev, timed_spec(m, cells, p), &t);
    slowest = std::max(slowest, t.device_seconds);
  }
  DeviceRuns d;
  d.rounds = std::clamp(static_cast<int>(std::ceil(1.0 / std::max(slowest, 1e-6))), 15, 51);
  std::vector<std::vector<double>> times(models.size()), ratios(models.size());
  for (int r = 0; r < d.rounds; ++r) {
    double schlick = 0.0;
    for (size_t i = 0; i < models.size(); ++i) {
      bake_fresnel(dev, timed_spec(models[i], cells, p), &t);
      if (models[i] == FresnelModel::Schlick) schlick = t.device_seconds;
      times[i].push_back(t.device_seconds);
      ratios[i].push_back(t.device_seconds / schlick);
    }
  }
  for (size_t i = 0; i < models.size(); ++i) {
    d.seconds.push_back(median(times[i]));
    d.fastest.push_back(*std::min_element(times[i].begin(), times[i].end()));
    d.ratio.push_back(median(ratios[i]));
  }
  return d;
}

std::string load_average() {
  std::ifstream f("/proc/loadavg");
  std::string one;
  return f >> one ? one : "unknown";
}

double reference_cells_per_second(const FresnelSpec& s) {
  bake_fresnel_reference(s);
  int reps = 0;
  double total = 0.0;
  while (total < 0.3 || reps < 3) {
    const auto t0 = std::chrono::steady_clock::now();
    bake_fresnel_reference(s);
    total += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ++reps;
  }
  return static_cast<double>(s.size) * reps / total;
}

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  int cells = 1 << 22;
  std::string out_file;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick")) {
      quick = true;
    } else if (!std::strcmp(argv[i], "--cells") && i + 1 < argc) {
      cells = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--out") && i + 1 < argc) {
      out_file = argv[++i];
    } else {
      std::fprintf(stderr, "usage: fresnel_bench [--quick] [--cells N] [--out FILE]\n");
      return 2;
    }
  }
  if (quick) cells = std::min(cells, 1 << 18);
  if (cells < 1 || cells > kFresnelMaxCells) {
    std::fprintf(stderr, "fresnel_bench: --cells must be between 1 and %lld\n", kFresnelMaxCells);
    return 2;
  }
  std::ostringstream md;
  try {
    Device dev = Device::open();
    const DeviceInfo& info = dev.info();
    md << "Device: " << info.name << " (" << info.platform_name << " " << info.driver_version << ", "
       << info.compute_units << " compute units). Tables: 1-D, r g b; an evaluation is one cell "
       << "(three channels).\n\n";

    // ---- 1. Device throughput --------------------------------------------------------------------
    md << "### Device throughput\n\n"
       << "Kernel time by OpenCL event profiling (the output is made resident before the timed "
          "kernel), over rounds that time every model once each, after a warm-up: the median and "
          "the fastest round. On a shared machine the fastest round is the kernel's own cost, the "
          "median includes what other processes took; a kernel of a few ms rarely runs "
          "undisturbed there, so the table is timed at two sizes: the large one asked for, and a "
          "cache-resident one whose sub-millisecond kernels give a stable fastest round. "
          "`vs schlick`: the model's time over Schlick's for the same table and precision, as the "
          "median over rounds of the ratio within a round, and as the ratio of the fastest times. "
          "Mcells/s from the fastest time. `max error`: the kernel against the scalar double "
          "reference over a 65536-cell table.\n";
    std::vector<Precision> precisions = {Precision::Fp32};
    if (info.fp64) precisions.push_back(Precision::Fp64);
    std::vector<int> sizes = {cells};
    if (cells > (1 << 18)) sizes.push_back(1 << 18);
    std::vector<std::vector<double>> max_errors(precisions.size());
    for (size_t k = 0; k < precisions.size(); ++k)
      for (FresnelModel m : fresnel_models()) {
        FresnelSpec small = timed_spec(m, 1 << 16, precisions[k]);
        small.endpoints = true;
        max_errors[k].push_back(fresnel_error(bake_fresnel(dev, small), bake_fresnel_reference(small)).max_abs);
      }
    for (int size : sizes) {
      md << "\n"
         << size << " cells:\n\n"
         << "| model | setting | precision | median (ms) | fastest (ms) | Mcells/s | vs schlick (median) "
            "| vs schlick (fastest) | max error |\n"
         << "|---|---|---|---:|---:|---:|---:|---:|---:|\n";
      std::string loads;
      for (size_t k = 0; k < precisions.size(); ++k) {
        const Precision p = precisions[k];
        loads += std::string(loads.empty() ? "" : ", ") + precision_name(p) + " " + load_average();
        const DeviceRuns d = time_device(dev, size, p);
        for (size_t i = 0; i < fresnel_models().size(); ++i) {
          const FresnelModel m = fresnel_models()[i];  // [0] is schlick
          md << "| " << fresnel_model_name(m) << " | " << setting(m) << " | " << precision_name(p) << " | "
             << fmt("%.3f", d.seconds[i] * 1e3) << " | " << fmt("%.3f", d.fastest[i] * 1e3) << " | "
             << fmt("%.1f", size / d.fastest[i] * 1e-6) << " | " << fmt("%.2f", d.ratio[i]) << " | "
             << fmt("%.2f", d.fastest[i] / d.fastest[0]) << " | " << fmt("%.1e", max_errors[k][i]) << " |\n";
          std::fprintf(stderr,
                       "%d cells %s %-17s median %9.3f ms fastest %9.3f ms  x%.2f / x%.2f of schlick (%d rounds)\n",
                       size, precision_name(p), fresnel_model_name(m), d.seconds[i] * 1e3, d.fastest[i] * 1e3,
                       d.ratio[i], d.fastest[i] / d.fastest[0], d.rounds);
        }
      }
      const char* threads = std::getenv("POCL_MAX_PTHREAD_COUNT");
      md << "\nRounds per precision: 15 to 51 (about 1 s of the slowest kernel). Load average (1 min) "
            "at the start: "
         << loads << " on " << info.compute_units << " compute units"
         << (threads ? std::string(", POCL_MAX_PTHREAD_COUNT=") + threads : std::string()) << ".\n";
    }

    // ---- 2. Reference throughput -------------------------------------------------------------------
    const int ref_cells = quick ? 1 << 14 : 1 << 18;
    md << "\n### Scalar double reference (one thread)\n\n"
       << "`bake_fresnel_reference` over a " << ref_cells << "-cell table, wall time.\n\n"
       << "| model | setting | Mcells/s |\n|---|---|---:|\n";
    for (FresnelModel m : fresnel_models()) {
      const double rate = reference_cells_per_second(timed_spec(m, ref_cells, Precision::Fp64));
      md << "| " << fresnel_model_name(m) << " | " << setting(m) << " | " << fmt("%.2f", rate * 1e-6) << " |\n";
      std::fprintf(stderr, "reference %-17s %8.2f Mcells/s\n", fresnel_model_name(m), rate * 1e-6);
    }

    // ---- 3. What each approximation gets wrong ---------------------------------------------------
    md << "\n### Approximation error against the exact model, every preset\n\n"
       << "max / mean of |model - exact| over 4097 cosines in [0, 1] (both ends) and the three "
          "channels; the exact model is the conductor for metals and the dielectric for dielectrics. "
          "Settings: `schlick` F0 = the exact F0; `schlick-metallic` metals base colour = exact F0 "
          "and metallic 1, dielectrics metallic 0 (F0 = 0.04); `schlick-ior` the preset's index; "
          "`f82-tint` exact F0 with the tint fitted at cos = 1/7; `empirical` bias = mean F0, "
          "scale = 1 - bias, power 5 (a grey Schlick). `schlick, hard-coded F0`: Schlick from the "
          "F0 shaders commonly hard-code for the material (the first of `brdfbake fresnel "
          "--list-materials`), against the same exact model.\n\n"
       << "| material | schlick | schlick-metallic | schlick-ior | f82-tint | empirical | schlick, hard-coded F0 |\n"
       << "|---|---|---|---|---|---|---|\n";
    FresnelCompareOptions o;
    o.rate_cells = 0;
    for (const MaterialPreset& preset : material_presets()) {
      const FresnelComparison c = compare_fresnel_models(preset.name, nullptr, o);
      md << "| " << preset.name;
      for (FresnelModel m : {FresnelModel::Schlick, FresnelModel::SchlickMetallic, FresnelModel::SchlickIor,
                             FresnelModel::F82Tint, FresnelModel::Empirical}) {
        std::string cell = "-";
        for (const FresnelModelReport& r : c.rows)
          if (r.model == m)
            cell = fmt("%.4f", r.worst) + " / " + fmt("%.4f", (r.mean_abs.r + r.mean_abs.g + r.mean_abs.b) / 3.0);
        md << " | " << cell;
      }
      const std::vector<HardCodedF0> hard = hard_coded_f0(preset);
      if (hard.empty()) {
        md << " | - |\n";
        continue;
      }
      FresnelSpec approx, exact;
      approx.model = FresnelModel::Schlick;
      approx.f0 = hard.front().f0;
      exact.model = c.exact_model;
      exact.material = preset.name;
      approx.size = exact.size = o.grid;
      approx.endpoints = exact.endpoints = true;
      const FresnelError e = fresnel_error(bake_fresnel_reference(approx), bake_fresnel_reference(exact));
      md << " | " << fmt("%.4f", e.max_abs) << " / " << fmt("%.4f", e.mean_abs) << " |\n";
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fresnel_bench: %s\n", e.what());
    return 1;
  }
  std::printf("%s", md.str().c_str());
  if (!out_file.empty()) {
    std::ofstream f(out_file);
    f << md.str();
    if (!f) {
      std::fprintf(stderr, "fresnel_bench: cannot write %s\n", out_file.c_str());
      return 1;
    }
  }
  return 0;
}
