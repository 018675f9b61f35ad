// Throughput and accuracy of bulk BRDF evaluation (kernels/brdf_eval.cl) against the scalar double
// reference, for every model: device evaluations per second at fp32, fp64 and fp32 with
// -cl-fast-relaxed-math, each with its max error against the reference; the reference's own
// single-thread rate; the speed-up of lobe specialisation; the lane width; a full MERL table.
//
//   brdf_bench [--quick] [--pairs N] [--model NAME] [--out FILE]
//
// --model runs the first table for that model only (and skips the others).
//
// Device time is kernel time from OpenCL event profiling, the median of the repetitions after one
// warm-up launch; rates count the direction pairs actually launched (one material). The reference
// rate is calibrated to run for about a second on one thread. Writes the markdown tables for
// docs/BENCHMARKS.md to stdout (and FILE when given).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "brdfbake/brdf.hpp"
#include "brdfbake/error.hpp"

using namespace brdfbake;

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

// A material that switches every lobe of its model on.
Material full_material(BrdfModel model) {
  Material m;
  m.base_color = {0.8, 0.45, 0.2};
  m.metallic = 0.3;
  m.roughness = 0.4;
  switch (model) {
    case BrdfModel::Disney:
      m.subsurface = 0.5;
      m.specular_tint = 0.3;
      m.anisotropic = 0.6;
      m.sheen = 0.5;
      m.clearcoat = 0.7;
      m.clearcoat_gloss = 0.8;
      break;
    case BrdfModel::Gltf:
    case BrdfModel::GltfCorrelated:
      m.sheen_color = {0.6, 0.3, 0.2};
      m.sheen_roughness = 0.5;
      m.clearcoat = 0.6;
      m.clearcoat_roughness = 0.2;
      m.specular_factor = 0.8;
      m.specular_color_factor = {1.0, 0.9, 0.8};
      m.ior = 1.6;
      break;
    case BrdfModel::Phong:
    case BrdfModel::BlinnPhong:
      m.shininess = 64.0;
      break;
    case BrdfModel::CookTorrance:
      m.distribution = MicrofacetDistribution::Beckmann;
      break;
    default:
      break;
  }
  return m;
}

// A plain dielectric: the lobes a specialised program can leave out (Disney: subsurface, sheen,
// clearcoat, anisotropy; glTF: sheen, clearcoat, metal, KHR_materials_specular).
Material plain_material() {
  Material m;
  m.base_color = {0.8, 0.45, 0.2};
  m.metallic = 0.0;
  m.roughness = 0.4;
  return m;
}

// Pairs in the upper hemisphere (the work every evaluation does; below-horizon lanes are cheaper).
std::vector<double> upper_pairs(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> v(6 * n);
  for (size_t i = 0; i < 2 * n; ++i) {
    double x = g(rng), y = g(rng), z = std::fabs(g(rng)) + 1e-3;
    const double len = std::sqrt(x * x + y * y + z * z);
    v[3 * i] = double(float(x / len));
    v[3 * i + 1] = double(float(y / len));
    v[3 * i + 2] = double(float(z / len));
  }
  return v;
}

struct DeviceRun {
  double evals_per_second = 0.0;
  double max_error = 0.0;
};

// Median device rate over `reps` launches after one warm-up, and the max error over the first
// `checked` pairs against the reference.
DeviceRun run_device(Device& dev, BrdfModel model, const Material& m, const EvalOptions& o,
                     const std::vector<double>& pairs, int reps, size_t checked) {
  const size_t n = pairs.size() / 6;
  BrdfEvaluator ev(dev, model, {m}, o);
  std::vector<double> out(3 * n);
  EvalTiming t;
  ev.eval(pairs.data(), n, out.data(), &t);  // warm-up
  std::vector<double> times;
  for (int r = 0; r < reps; ++r) {
    ev.eval(pairs.data(), n, out.data(), &t);
    times.push_back(t.device_seconds);
  }
  DeviceRun run;
  run.evals_per_second = static_cast<double>(n) / median(times);
  std::vector<double> want(3 * checked);
  eval_reference(model, m, pairs.data(), checked, want.data());
  for (size_t k = 0; k < 3 * checked; ++k)
    run.max_error = std::max(run.max_error, std::fabs(out[k] - want[k]) / std::max(1.0, std::fabs(want[k])));
  return run;
}

// Single-thread reference rate, calibrated to ~`seconds`.
double run_reference(BrdfModel model, const Material& m, const std::vector<double>& pairs, double seconds) {
  const size_t n = std::min<size_t>(pairs.size() / 6, 1 << 16);
  std::vector<double> out(3 * n);
  size_t done = 0;
  const auto t0 = Clock::now();
  double elapsed = 0.0;
  do {
    eval_reference(model, m, pairs.data(), n, out.data());
    done += n;
    elapsed = seconds_since(t0);
  } while (elapsed < seconds);
  return static_cast<double>(done) / elapsed;
}

std::string rate(double r) { return fmt("%.1f", r / 1e6); }
std::string err(double e) { return fmt("%.1e", e); }

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  size_t n_pairs = 1u << 16;  // the eval command's chunk
  std::string out_path, only;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick")) {
      quick = true;
    } else if (!std::strcmp(argv[i], "--pairs") && i + 1 < argc) {
      n_pairs = static_cast<size_t>(std::strtoul(argv[++i], nullptr, 10));
    } else if (!std::strcmp(argv[i], "--model") && i + 1 < argc) {
      only = argv[++i];
    } else if (!std::strcmp(argv[i], "--out") && i + 1 < argc) {
      out_path = argv[++i];
    } else {
      std::fprintf(stderr, "usage: brdf_bench [--quick] [--pairs N] [--model NAME] [--out FILE]\n");
      return 2;
    }
  }
  try {
    Device dev = Device::open();
    const int reps = quick ? 3 : 7;
    const size_t checked = quick ? 4096 : 65536;
    const double ref_seconds = quick ? 0.2 : 1.0;
    const std::vector<double> pairs = upper_pairs(n_pairs, 7u);
    std::ostringstream md;
    md << "Device: " << dev.info().name << " (" << dev.info().platform_name << ", " << dev.info().driver_version << ", "
       << dev.info().compute_units << " compute units). " << n_pairs
       << " direction pairs a launch (the eval command's chunk) in the upper hemisphere, one material with "
          "every lobe of its model on; device time is the median of "
       << reps
       << " profiled launches after a warm-up. Rates in millions of evaluations per second; errors are "
          "the max of |f - f_ref| / max(1, |f_ref|) over "
       << checked << " pairs.\n\n";
    md << "| model | reference (1 thread) | fp32 | fp32 error | fp64 | fp64 error | fp32 fast-math | fast-math error | "
          "fp32 / reference |\n";
    md << "|---|---|---|---|---|---|---|---|---|\n";
    for (BrdfModel model : brdf_models()) {
      if (!only.empty() && only != brdf_model_name(model)) continue;
      const Material m = full_material(model);
      run_reference(model, m, pairs, 0.0);  // warm-up: builds the sheen albedo series once
      const double ref = run_reference(model, m, pairs, ref_seconds);
      EvalOptions o32;
      const DeviceRun f32 = run_device(dev, model, m, o32, pairs, reps, checked);
      DeviceRun f64;
      if (dev.info().fp64) {
        EvalOptions o64;
        o64.precision = Precision::Fp64;
        f64 = run_device(dev, model, m, o64, pairs, reps, checked);
      }
      EvalOptions fast;
      fast.fast_math = true;
      const DeviceRun ff = run_device(dev, model, m, fast, pairs, reps, checked);
      md << "| " << brdf_model_name(model) << " | " << rate(ref) << " | " << rate(f32.evals_per_second) << " | "
         << err(f32.max_error) << " | " << (dev.info().fp64 ? rate(f64.evals_per_second) : "-") << " | "
         << (dev.info().fp64 ? err(f64.max_error) : "-") << " | " << rate(ff.evals_per_second) << " | "
         << err(ff.max_error) << " | " << fmt("%.0fx", f32.evals_per_second / ref) << " |\n";
      std::fprintf(stderr, "%s done\n", brdf_model_name(model));
    }

    if (!only.empty()) {
      std::fputs(md.str().c_str(), stdout);
      return 0;
    }
    md << "\nLobe specialisation (fp32): a plain dielectric (no subsurface, sheen, clearcoat, anisotropy, "
          "metal or KHR_materials_specular) in the program compiled for its own lobes against the one "
          "compiled with every lobe of the model.\n\n";
    md << "| model | specialised | every lobe | speed-up |\n|---|---|---|---|\n";
    for (BrdfModel model : {BrdfModel::Disney, BrdfModel::Gltf, BrdfModel::GltfCorrelated}) {
      EvalOptions spec, all;
      all.specialize = false;
      const DeviceRun a = run_device(dev, model, plain_material(), spec, pairs, reps, 256);
      const DeviceRun b = run_device(dev, model, plain_material(), all, pairs, reps, 256);
      md << "| " << brdf_model_name(model) << " | " << rate(a.evals_per_second) << " | " << rate(b.evals_per_second)
         << " | " << fmt("%.2fx", a.evals_per_second / b.evals_per_second) << " |\n";
    }

    md << "\nBatch size (disney with every lobe, fp32): pairs a launch. Each pair reads 36 bytes (wi, wo and the half "
          "vector the host forms in double) and writes 12; "
          "large batches leave the caches and run at memory bandwidth.\n\n| pairs | fp32 |\n|---|---|\n";
    for (size_t n : {size_t(1) << 14, size_t(1) << 16, size_t(1) << 18, size_t(1) << 21}) {
      const std::vector<double> batch = upper_pairs(n, 11u);
      const DeviceRun a =
          run_device(dev, BrdfModel::Disney, full_material(BrdfModel::Disney), EvalOptions{}, batch, reps, 256);
      md << "| " << n << " | " << rate(a.evals_per_second) << " |\n";
    }

    md << "\nLane width (fp32, disney with every lobe): directions per work-item.\n\n| lanes | fp32 | fp64 "
          "|\n|---|---|---|\n";
    for (int lanes : {8, 16}) {
      EvalOptions o;
      o.lanes = lanes;
      const DeviceRun a = run_device(dev, BrdfModel::Disney, full_material(BrdfModel::Disney), o, pairs, reps, 256);
      std::string b = "-";
      if (dev.info().fp64) {
        o.precision = Precision::Fp64;
        b = rate(
            run_device(dev, BrdfModel::Disney, full_material(BrdfModel::Disney), o, pairs, reps, 256).evals_per_second);
      }
      md << "| " << lanes << " | " << rate(a.evals_per_second) << " | " << b << " |\n";
    }

    md << "\nA full MERL table (90 x 90 x 180 = 1,458,000 bins, directions generated on the device), one "
          "material with every lobe on; device time median of "
       << reps
       << ", wall time of the whole call (program from the cache, read-back included) and the reference "
          "on every core.\n\n| model | precision | device s | wall s | reference s |\n|---|---|---|---|---|\n";
    for (BrdfModel model : {BrdfModel::Disney, BrdfModel::Gltf}) {
      TabulateSpec s;
      s.model = model;
      s.layout = TableLayout::Merl;
      s.materials = {NamedMaterial{"bench", model, full_material(model), {}, {}, {}}};
      TabulateTiming ref_t;
      const MerlTable ref = tabulate_merl_reference(s, &ref_t);
      for (Precision p : {Precision::Fp32, Precision::Fp64}) {
        if (p == Precision::Fp64 && !dev.info().fp64) continue;
        s.options.precision = p;
        TabulateTiming t;
        tabulate_merl(dev, s, &t);  // warm-up (and program build)
        std::vector<double> dt, wt;
        for (int r = 0; r < reps; ++r) {
          tabulate_merl(dev, s, &t);
          dt.push_back(t.device_seconds);
          wt.push_back(t.wall_seconds);
        }
        md << "| " << brdf_model_name(model) << " | " << precision_name(p) << " | " << fmt("%.3f", median(dt)) << " | "
           << fmt("%.3f", median(wt)) << " | " << fmt("%.2f", ref_t.wall_seconds) << " |\n";
      }
    }
    std::fputs(md.str().c_str(), stdout);
    if (!out_path.empty()) {
      std::ofstream f(out_path);
      f << md.str();
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "brdf_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
