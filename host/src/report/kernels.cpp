// `brdfbake report --kinds kernels` (issue 36): where each hot kernel stands against its device.
//
// The device's own peaks first (kernels/device_peak.cl): the best rate of fused multiply-adds on
// wide vectors, fp32 and fp64, and the best streaming triad. Then each hot kernel through the
// library's entries at a realistic size, its device seconds from OpenCL event profiling (the
// median of the runs after a warm-up) and the whole call's wall seconds beside them. Its flops
// and bytes are not guessed: kernel_ops.inc holds what Oclgrind counted when the same rows ran at
// a small size (scripts/count_kernel_ops.sh: `oclgrind --plugins libflop_counter.so brdfbake
// report --kinds kernels --count-ops`, bench/kernel_ops/flop_counter.cpp counting every lane), per
// work unit; the measured launch's units times that is its work.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "brdfbake/brdf.hpp"
#include "brdfbake/dfg_lut.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/report.hpp"
#include "runtime/device_impl.hpp"
#include "runtime/program.hpp"

namespace brdfbake {

namespace {

#include "report/kernel_ops.inc"

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// ---- The device's peaks -------------------------------------------------------------------------

constexpr int kPeakChains = 8, kPeakLanes = 16;

KernelPeak measure_peak(Device& dev, Precision precision) {
  detail::ProgramSpec spec;
  spec.file = "device_peak.cl";
  spec.precision = precision;
  cl::Program program = detail::build_program(dev.impl(), spec);
  const DeviceInfo& info = dev.info();
  const size_t items = size_t(std::max(1u, info.compute_units)) * (info.type == "cpu" ? 64 : 2048);
  cl::Buffer out(dev.impl().context, CL_MEM_WRITE_ONLY, items * (precision == Precision::Fp64 ? 8 : 4));
  cl::Kernel k(program, "peak_fma");
  k.setArg(0, out);
  if (precision == Precision::Fp64)
    k.setArg(2, cl_double(0.999));
  else
    k.setArg(2, cl_float(0.999f));
  auto launch = [&](int iterations) {
    k.setArg(1, cl_int(iterations));
    cl::Event e;
    dev.impl().queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(items), cl::NullRange, nullptr, &e);
    e.wait();
    return detail::event_seconds(e);
  };
  int iterations = 64;
  while (iterations < (1 << 24) && launch(iterations) < 0.02) iterations *= 2;  // until a launch takes 20 ms
  KernelPeak best;
  const double flops = 2.0 * kPeakLanes * kPeakChains * double(iterations) * double(items);
  for (int run = 0; run < 3; ++run) {
    const double s = launch(iterations);
    if (s > 0 && flops / s * 1e-9 > best.gflops) best = {flops / s * 1e-9, s, flops};
  }
  return best;
}

void measure_bandwidth(Device& dev, KernelsReport& r) {
  detail::ProgramSpec spec;
  spec.file = "device_peak.cl";
  cl::Program program = detail::build_program(dev.impl(), spec);
  const DeviceInfo& info = dev.info();
  // Arrays far above any cache: 64 MiB each on a CPU, 256 MiB on a GPU (an H200's L2 is 60 MB),
  // within a quarter of the largest allocation.
  size_t each = size_t(info.type == "cpu" ? 64 : 256) << 20;
  if (info.max_alloc > 0) each = std::min<size_t>(each, size_t(info.max_alloc / 4));
  each -= each % 16;
  const size_t items = each / 16;
  cl::Buffer a(dev.impl().context, CL_MEM_READ_WRITE, each), b(dev.impl().context, CL_MEM_READ_WRITE, each),
      c(dev.impl().context, CL_MEM_READ_WRITE, each);
  const cl_float zero = 0.5f;
  for (cl::Buffer* buf : {&a, &b, &c}) dev.impl().queue.enqueueFillBuffer(*buf, zero, 0, each);
  cl::Kernel k(program, "stream_triad");
  k.setArg(0, a);
  k.setArg(1, b);
  k.setArg(2, c);
  k.setArg(3, cl_float(3.0f));
  for (int run = 0; run < 6; ++run) {  // the first touches the pages
    cl::Event e;
    dev.impl().queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(items), cl::NullRange, nullptr, &e);
    e.wait();
    const double s = detail::event_seconds(e), moved = 3.0 * double(each);
    if (run > 0 && s > 0 && moved / s * 1e-9 > r.bandwidth) {
      r.bandwidth = moved / s * 1e-9;
      r.bandwidth_bytes = moved;
      r.bandwidth_seconds = s;
    }
  }
}

// ---- The hot kernels ----------------------------------------------------------------------------

// One row: its definition and how to run it once (count: at the counting size), giving the work
// units, the device seconds of the row's kernel and the wall seconds of the call.
struct Run {
  double units = 0.0, device = 0.0, wall = 0.0;
};
struct RowDef {
  const char* id;
  const char* kernel;
  const char* file;  // its kernels/ file: the count holds the hash of its source
  const char* unit;
  Precision precision;
  bool walk;
  const char* shape;  // "cpu": measured in the CPU shape only (the GPU shape does not launch the kernel); "": both
  std::string (*launch)(bool count);
  Run (*run)(Device& dev, bool count);
};

Run run_lut(Device& dev, bool count, Precision p) {
  LutSpec s;
  s.kind = LutKind::Ggx;
  s.width = s.height = count ? 16 : 128;
  s.precision = p;
  LutTiming t;
  bake_lut(dev, s, &t);
  return {double(s.width) * s.height, t.device_seconds, t.wall_seconds};
}

Run run_pairs(Device& dev, bool count, Precision p) {
  const size_t n = count ? 512 : 1u << 21;  // measured: 48 MB of pairs in, 24 MB out, above the caches
  std::vector<double> pairs(6 * n), out(3 * n);
  for (size_t i = 0; i < n; ++i) {  // a fixed spread of directions over the upper hemisphere
    const double u = (double(i) + 0.5) / double(n), v = std::fmod(double(i) * 0.618033988749895, 1.0);
    const double ci = 0.05 + 0.95 * u, si = std::sqrt(1 - ci * ci), co = 0.05 + 0.95 * v, so = std::sqrt(1 - co * co);
    const double phi = 6.283185307179586 * std::fmod(double(i) * 0.754877666246693, 1.0);
    double* q = &pairs[6 * i];
    q[0] = si, q[1] = 0, q[2] = ci, q[3] = so * std::cos(phi), q[4] = so * std::sin(phi), q[5] = co;
  }
  Material m;
  m.roughness = 0.4;
  m.metallic = 0.2;
  m.sheen = 0.3;
  m.clearcoat = 0.2;
  EvalOptions o;
  o.precision = p;
  const auto t0 = std::chrono::steady_clock::now();
  BrdfEvaluator e(dev, BrdfModel::Disney, {m}, o);
  EvalTiming t;
  e.eval(pairs.data(), n, out.data(), &t);
  return {double(n), t.device_seconds, seconds_since(t0)};
}

Run run_grid(Device& dev, bool count) {
  TabulateSpec s;
  s.model = BrdfModel::Disney;
  NamedMaterial m;
  m.name = "m";
  m.params.roughness = 0.4;
  m.params.sheen = 0.3;
  m.params.clearcoat = 0.2;
  s.materials = {m};
  s.layout = TableLayout::Grid;
  s.res = count ? std::vector<int>{4, 4, 16} : std::vector<int>{64, 64, 128};
  TabulateTiming t;
  tabulate(dev, s, &t);
  return {double(s.res[0]) * s.res[1] * s.res[2], t.device_seconds, t.wall_seconds};
}

// The environment: builtin:studio as an equirect 4 x the cube's face wide (so that the conversion
// supersamples the same way at both sizes).
Run run_convert(Device& dev, bool count) {
  const int size = count ? 32 : 256;
  const EnvImage env = builtin_environment("studio", 4 * size);
  const auto t0 = std::chrono::steady_clock::now();
  double device = 0.0;
  environment_to_cube(dev, env, size, &device);
  return {6.0 * size * size, device, seconds_since(t0)};
}

// A chain of 4 levels (128^2 -> 16^2 measured, 64^2 -> 8^2 counted: the same roughness per level,
// the same mix of level sizes, every level a multiple of 8 so that the strips kernel runs on each):
// units are the texels of levels 1..3, the device seconds their filtering
// (PrefilterTiming::level_device_seconds).
Run run_chain(Device& dev, bool count, EnvEstimator estimator, bool strips) {
  const int size = count ? 64 : 128;
  const EnvImage env = builtin_environment("studio", 4 * size);
  const CubeLevels source = environment_to_cube(dev, env, size);
  PrefilterSpec s;
  s.size = size;
  s.min_size = size / 8;
  s.estimator = estimator;
  s.strips = strips;
  PrefilterTiming t;
  const auto t0 = std::chrono::steady_clock::now();
  const CubeLevels c = prefilter_cube(dev, source, s, &t);
  Run r;
  r.wall = seconds_since(t0);
  for (int l = 1; l < c.level_count(); ++l) {
    r.units += 6.0 * c.level_size(l) * c.level_size(l);
    if (size_t(l) < t.level_device_seconds.size()) r.device += t.level_device_seconds[size_t(l)];
  }
  return r;
}

const RowDef kRows[] = {
    {"dfg_lut ggx fp32", "dfg_lut", "dfg_lut.cl", "texel", Precision::Fp32, false, "",
     [](bool c) {
       return std::string(c ? "GGX DFG table 16x16" : "GGX DFG table 128x128") + ", 384 evaluations a texel";
     },
     [](Device& d, bool c) { return run_lut(d, c, Precision::Fp32); }},
    {"dfg_lut ggx fp64", "dfg_lut", "dfg_lut.cl", "texel", Precision::Fp64, false, "",
     [](bool c) {
       return std::string(c ? "GGX DFG table 16x16" : "GGX DFG table 128x128") + ", 384 evaluations a texel";
     },
     [](Device& d, bool c) { return run_lut(d, c, Precision::Fp64); }},
    {"brdf_pairs disney fp32", "brdf_pairs", "brdf_eval.cl", "pair", Precision::Fp32, false, "",
     [](bool c) { return std::string(c ? "512" : "2,097,152") + " direction pairs, Disney, one material (eval)"; },
     [](Device& d, bool c) { return run_pairs(d, c, Precision::Fp32); }},
    {"brdf_pairs disney fp64", "brdf_pairs", "brdf_eval.cl", "pair", Precision::Fp64, false, "",
     [](bool c) { return std::string(c ? "512" : "2,097,152") + " direction pairs, Disney, one material (eval)"; },
     [](Device& d, bool c) { return run_pairs(d, c, Precision::Fp64); }},
    {"brdf_grid disney fp32", "brdf_grid", "brdf_eval.cl", "cell", Precision::Fp32, false, "",
     [](bool c) { return std::string(c ? "4x4x16" : "64x64x128") + " grid, Disney (tabulate)"; },
     [](Device& d, bool c) { return run_grid(d, c); }},
    {"equirect_to_cube fp32", "equirect_to_cube", "cubemap.cl", "texel", Precision::Fp32, false, "",
     [](bool c) { return std::string(c ? "128x64 equirect to a 32^2 cube" : "1024x512 equirect to a 256^2 cube"); },
     [](Device& d, bool c) { return run_convert(d, c); }},
    {"prefilter_pyramid_strips fp32", "prefilter_pyramid_strips", "prefilter.cl", "texel", Precision::Fp32, true, "cpu",
     [](bool c) {
       return std::string(c ? "levels 1-3 of a 64^2 GGX chain" : "levels 1-3 of a 128^2 GGX chain") +
              ", quadrature, blocks of 8x8 texels (the CPU shape's default)";
     },
     [](Device& d, bool c) { return run_chain(d, c, EnvEstimator::Quadrature, true); }},
    {"prefilter_pyramid fp32", "prefilter_pyramid", "prefilter.cl", "texel", Precision::Fp32, true, "",
     [](bool c) {
       return std::string(c ? "levels 1-3 of a 64^2 GGX chain" : "levels 1-3 of a 128^2 GGX chain") +
              ", quadrature, a walk per texel (the GPU shape's default)";
     },
     [](Device& d, bool c) { return run_chain(d, c, EnvEstimator::Quadrature, false); }},
    {"prefilter_level fp32", "prefilter_level", "prefilter.cl", "texel", Precision::Fp32, false, "",
     [](bool c) {
       return std::string(c ? "levels 1-3 of a 64^2 GGX chain" : "levels 1-3 of a 128^2 GGX chain") +
              ", sampling (1024 lobe samples a texel)";
     },
     [](Device& d, bool c) { return run_chain(d, c, EnvEstimator::Sampling, false); }},
};

// FNV-1a of a kernel file's source with its includes expanded: a count made on other sources
// (a kernel changed since) is not used.
std::string source_hash(const char* file) {
  std::uint64_t h = 1469598103934665603ull;
  for (char ch : detail::kernel_source(file)) h = (h ^ static_cast<unsigned char>(ch)) * 1099511628211ull;
  char b[24];
  std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(h));
  return b;
}

void append_marker(const std::string& row, double units, const std::string& hash) {
  const char* path = std::getenv("BRDFBAKE_FLOP_COUNTS");
  if (!path || !*path) throw Error("report --count-ops: BRDFBAKE_FLOP_COUNTS must name the counter's file");
  FILE* f = std::fopen(path, "a");
  if (!f) throw Error(std::string("cannot append to ") + path);
  std::fprintf(f, "{\"row\": \"%s\", \"units\": %.0f, \"source_hash\": \"%s\"}\n", row.c_str(), units, hash.c_str());
  std::fclose(f);
}

}  // namespace

const KernelOpCount* find_kernel_op_count(const std::string& row, const std::string& shape) {
  for (const KernelOpCount& c : kKernelOpCounts)
    if (row == c.row && shape == c.shape) return &c;
  return nullptr;
}

const char* kernel_op_count_source() { return kKernelOpCountSource; }

// Above this share of its flops, divisions, square roots and transcendentals are named as a cause: on
// a CPU a vector division or square root takes the time of 10-40 FMAs, so 5 % of them can double the
// time the flops alone would take.
constexpr double kSpecialShare = 0.05;

void place_kernel_row(KernelRow& r, double peak_gflops, double bandwidth_gbs, unsigned compute_units) {
  r.units_per_second = r.device_seconds > 0 ? r.units / r.device_seconds : 0.0;
  if (!r.counted) return;
  r.gflops = r.units_per_second * r.flops_per_unit * 1e-9;
  r.gbytes_per_second = r.units_per_second * r.bytes_per_unit * 1e-9;
  r.intensity = r.bytes_per_unit > 0 ? r.flops_per_unit / r.bytes_per_unit : HUGE_VAL;
  const double ridge = bandwidth_gbs > 0 ? peak_gflops / bandwidth_gbs : 0.0;
  r.bound = r.intensity >= ridge ? "compute" : "memory";
  r.flops_fraction = peak_gflops > 0 ? r.gflops / peak_gflops : 0.0;
  r.fraction =
      r.bound == "compute" ? r.flops_fraction : (bandwidth_gbs > 0 ? r.gbytes_per_second / bandwidth_gbs : 0.0);
  r.limit.clear();
  const bool cached = r.bound == "memory" && r.fraction > 1.0;
  if (r.fraction >= kKernelLowFraction && !cached) return;
  std::vector<std::string> why;
  char b[240];
  if (cached) {
    std::snprintf(b, sizeof b,
                  "its loads and stores (%.3g bytes a %s, counted) run above the triad's DRAM bandwidth: the caches "
                  "serve them (re-reads), so it is bound by loads, at %.1f%% of the flops peak",
                  r.bytes_per_unit, r.unit.c_str(), 100.0 * r.flops_fraction);
    why.push_back(b);
  } else if (r.bound == "memory") {
    std::snprintf(b, sizeof b,
                  "below the ridge (%.2g flops a byte against %.2g) yet at %.0f%% of the triad's GB/s: bandwidth does "
                  "not bound it",
                  r.intensity, ridge, 100.0 * r.fraction);
    why.push_back(b);
  }
  if (r.device_seconds > 0 && r.device_seconds < 2e-3) {
    std::snprintf(b, sizeof b, "launch overhead: %.2f ms of device time in all", r.device_seconds * 1e3);
    why.push_back(b);
  }
  if (compute_units > 0 && r.units < 4.0 * compute_units) why.push_back("too few work units to fill the compute units");
  if (r.special_share > kSpecialShare) {
    std::snprintf(b, sizeof b,
                  "divisions, square roots and transcendentals: %.1f%% of its flops, each the time of many FMAs",
                  100.0 * r.special_share);
    why.push_back(b);
  }
  if (r.walk)
    why.push_back(
        "a serial, data-dependent walk per work-item: branches and gathers differ by lane, so vector lanes idle "
        "and the loads are scattered");
  if (why.size() == (r.bound == "memory" && !cached ? 1u : 0u))  // nothing named but the ridge's side
    why.push_back("none of the causes checked here (launches, work units, special functions, a walk)");
  for (size_t k = 0; k < why.size(); ++k) r.limit += (k ? "; " : "") + why[k];
}

KernelsReport measure_device_peaks(Device& dev) {
  KernelsReport r;
  r.shape = dev.info().kernel_shape;
  r.fp32 = measure_peak(dev, Precision::Fp32);
  if (dev.info().fp64) r.fp64 = measure_peak(dev, Precision::Fp64);
  measure_bandwidth(dev, r);
  return r;
}

KernelsReport measure_kernels(Device& dev, const KernelsOptions& o,
                              const std::function<void(const std::string&)>& log) {
  KernelsReport r;
  r.shape = dev.info().kernel_shape;
  auto say = [&](const std::string& s) {
    if (log) log(s);
  };
  if (!o.count) {
    say("kernels: the device's peaks (" + r.shape + " shape)");
    r = measure_device_peaks(dev);
    char b[200];
    std::snprintf(b, sizeof b, "  peak fp32 %.1f GFLOP/s, fp64 %.1f GFLOP/s, triad %.1f GB/s", r.fp32.gflops,
                  r.fp64.gflops, r.bandwidth);
    say(b);
  }
  for (const RowDef& d : kRows) {
    if (d.precision == Precision::Fp64 && !dev.info().fp64) continue;
    if (*d.shape && r.shape != d.shape) continue;  // the strips: the CPU shape's quadrature only
    KernelRow row;
    row.id = d.id;
    row.kernel = d.kernel;
    row.unit = d.unit;
    row.precision = precision_name(d.precision);
    row.walk = d.walk;
    row.launch = d.launch(o.count);
    if (o.count) {
      // the marker first: the counter appends the row's launches after it
      append_marker(d.id, 0.0, source_hash(d.file));
      const Run run = d.run(dev, true);
      append_marker(std::string(d.id) + " end", run.units, source_hash(d.file));
      row.units = run.units;
      r.rows.push_back(row);
      continue;
    }
    d.run(dev, false);  // warm-up: program builds, first touches
    std::vector<double> device, wall;
    for (int k = 0; k < std::max(1, o.runs); ++k) {
      const Run run = d.run(dev, false);
      row.units = run.units;
      device.push_back(run.device);
      wall.push_back(run.wall);
    }
    row.device_seconds = median(device);
    row.wall_seconds = median(wall);
    const KernelOpCount* c = find_kernel_op_count(d.id, r.shape);
    if (c && source_hash(d.file) != c->source_hash) {
      row.stale = true;  // counted on other sources of the kernel: not used
      c = nullptr;
    }
    if (c) {
      row.counted = true;
      row.flops_per_unit = c->flops / c->units;
      row.bytes_per_unit = (c->load_bytes + c->store_bytes) / c->units;
      row.special_share = c->flops > 0 ? (c->div + c->sqrt + c->transcendental) / c->flops : 0.0;
    }
    const double peak = d.precision == Precision::Fp64 ? r.fp64.gflops : r.fp32.gflops;
    place_kernel_row(row, peak, r.bandwidth, dev.info().compute_units);
    char b[240];
    std::snprintf(b, sizeof b, "  %s: %.3g %ss/s, device %.2f ms, wall %.2f ms, %.1f GFLOP/s, %.1f%% of the roof", d.id,
                  row.units_per_second, d.unit, row.device_seconds * 1e3, row.wall_seconds * 1e3, row.gflops,
                  100.0 * row.fraction);
    say(b);
    r.rows.push_back(row);
  }
  return r;
}

}  // namespace brdfbake
