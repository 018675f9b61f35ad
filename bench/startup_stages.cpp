// Where the time of a short job goes, stage by stage, in one cold process (issue 11, start-up):
//
//   startup_stages lut [SIZE]            the DFG LUT (ggx-multiscatter) as `brdfbake lut` runs it
//   startup_stages irradiance ENV        3-band SH only, as `brdfbake irradiance --sh 3 -o x.json`
//   startup_stages prefilter ENV [SIZE [charlie]]   the chain SIZE^2 -> 16^2 (issue 11, prefilter),
//                                        with the library's stages, the error bound the chain
//                                        records and the peak resident memory
//
// Each stage is timed with a steady clock (wall time, milliseconds): opening the OpenCL platform
// and device, loading the environment, the bake (program from the binary cache, kernels, read
// back), the same bake again (programs already built: the difference is the program build), and
// writing the output. Run it cold (a new process each time) several times; the first stage also
// pays for loading the OpenCL implementation (PoCL: LLVM and clang, ~100 MiB of libraries).
// Prints one line per stage; the whole-process time and peak memory come from bench/cmgen_compare.sh.
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "brdfbake/backend.hpp"
#include "brdfbake/dfg_lut.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/io.hpp"
#include "families/prefilter/bound_kernel.hpp"

using namespace brdfbake;

namespace {

using Clock = std::chrono::steady_clock;

class Stages {
 public:
  void mark(const char* what) {
    const auto now = Clock::now();
    rusage usage{};
    ::getrusage(RUSAGE_SELF, &usage);
    std::printf("%-44s %8.2f ms  (peak so far %.0f MiB)\n", what,
                std::chrono::duration<double, std::milli>(now - last_).count(), double(usage.ru_maxrss) / 1024.0);
    last_ = now;
  }
  void total() const {
    std::printf("%-44s %8.2f ms\n", "total (after process start)",
                std::chrono::duration<double, std::milli>(Clock::now() - first_).count());
  }

 private:
  Clock::time_point first_ = Clock::now(), last_ = first_;
};

std::string temp_output(const char* name) {
  return (std::filesystem::temp_directory_path() / ("startup_stages_" + std::to_string(::getpid()) + name)).string();
}

int lut(int size) {
  Stages t;
  Device device = Device::open();
  t.mark("open the OpenCL platform and device");
  LutSpec spec;
  spec.kind = LutKind::GgxMultiscatter;
  spec.width = spec.height = size;
  Table table = bake_lut(device, spec);
  t.mark("bake (program from the cache, kernel, read)");
  LutTiming timing;
  table = bake_lut(device, spec, &timing);
  t.mark("bake again (program already built)");
  std::printf("%-44s %8.2f ms\n", "  of which device time (event profiling)", 1e3 * timing.device_seconds);
  const std::string out = temp_output(".exr");
  write_table(table, out, TableFormat::Exr);
  t.mark("write .exr");
  t.total();
  std::filesystem::remove(out);
  return 0;
}

int irradiance(const std::string& env_spec) {
  Stages t;
  const EnvImage env = load_environment(env_spec);
  t.mark("load the environment");
  Device device = Device::open();
  t.mark("open the OpenCL platform and device");
  IrradianceSpec spec;
  spec.sh_order = 3;
  spec.cube_size = 0;
  IrradianceResult r = compute_irradiance(device, env, spec);
  t.mark("SH (programs from the cache, conversion, SH)");
  r = compute_irradiance(device, env, spec);
  t.mark("SH again (programs already built)");
  std::printf("%-44s %8.2f ms\n", "  of which device time (event profiling)", 1e3 * r.device_seconds);
  const std::string out = temp_output(".json");
  write_sh_json(r.sh, {{"source", env.source}}, out);
  t.mark("write .json");
  t.total();
  std::filesystem::remove(out);
  return 0;
}

// The prefiltered chain as `brdfbake prefilter` runs it, with the library's own stages
// (PrefilterTiming::stage_seconds: conversion, bright texels, program, pyramid, each level).
int prefilter(const std::string& env_spec, int size, bool charlie) {
  Stages t;
  const EnvImage env = load_environment(env_spec);
  t.mark("load the environment");
  Device device = Device::open();
  t.mark("open the OpenCL platform and device");
  PrefilterSpec spec;
  spec.size = size;
  spec.min_size = 16;
  if (charlie) spec.distribution = EnvDistribution::Charlie;
  // for experiments: BRDFBAKE_BENCH_TILE=1 runs the per-texel quadrature, BRDFBAKE_BENCH_BRIGHT=0
  // turns environment sampling off
  if (const char* tile = std::getenv("BRDFBAKE_BENCH_TILE")) spec.strips = std::atoi(tile) != 1;
  if (const char* bright = std::getenv("BRDFBAKE_BENCH_BRIGHT")) spec.bright_texels = std::atoi(bright);
  PrefilterTiming timing;
  const CubeLevels cube = prefilter_environment(device, env, spec, &timing);
  t.mark("prefilter (stages below)");
  for (const auto& [name, seconds] : timing.stage_seconds)
    std::printf("  %-42s %8.2f ms\n", name.c_str(), 1e3 * seconds);
  std::printf("%-44s %8.2f ms\n", "  of which device time (event profiling)", 1e3 * timing.device_seconds);
  for (size_t l = 0; l < timing.level_device_seconds.size(); ++l)
    std::printf("    %-40s %8.2f ms\n", (l == 0 ? std::string("conversion") : "level " + std::to_string(l)).c_str(),
                1e3 * timing.level_device_seconds[l]);
  // the bound every chain records (families/prefilter/bound.cpp), as the family's bake measures it:
  // its reference on this device in fp64 where it has it
  const std::shared_ptr<Backend> backend = Backend::open(device);
  std::vector<double> roughness;
  for (int l = 0; l < cube.level_count(); ++l)
    roughness.push_back(schedule_roughness(spec.schedule, l, cube.level_count()));
  const detail::ChainBound bound = detail::chain_error_bound(*backend, cube, spec.distribution, roughness);
  t.mark(bound.on_device ? "error bound (reference on the device, fp64)" : "error bound (reference on the host)");
  std::printf("%-44s %8.2f ms\n", "  of which device time (event profiling)", 1e3 * bound.device_seconds);
  const std::string out = temp_output(".ktx2");
  write_cubemap(cube, out, CubeFormat::Ktx2);
  t.mark("write .ktx2");
  t.total();
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  std::printf("%-44s %8.1f MiB\n", "peak resident memory (ru_maxrss)", double(usage.ru_maxrss) / 1024.0);
  std::filesystem::remove(out);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc >= 2 && std::strcmp(argv[1], "lut") == 0) return lut(argc >= 3 ? std::atoi(argv[2]) : 128);
    if (argc >= 3 && std::strcmp(argv[1], "irradiance") == 0) return irradiance(argv[2]);
    if (argc >= 3 && std::strcmp(argv[1], "prefilter") == 0)
      return prefilter(argv[2], argc >= 4 ? std::atoi(argv[3]) : 256,
                       argc >= 5 && std::strcmp(argv[4], "charlie") == 0);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "startup_stages: %s\n", e.what());
    return 1;
  }
  std::fprintf(stderr,
               "usage: startup_stages lut [SIZE] | startup_stages irradiance ENV | startup_stages prefilter ENV [SIZE "
               "[charlie]]\n");
  return 2;
}
