// brdfbake prefilter --env FILE|builtin:NAME [--size 256] [--min-size 16] [...] -o FILE.ktx2|.ktx|.dds|DIR
#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "brdfbake/environment.hpp"
#include "cli_env.hpp"

namespace brdfbake::cli {

int cmd_prefilter(int argc, char** argv) {
  cxxopts::Options options("brdfbake prefilter",
                           "Prefilter an environment into a GGX or Charlie radiance mip chain");
  options.add_options()
      ("env", "FILE (.hdr .exr equirect or cross, .ktx2 cube), six comma-separated face files, a path with {face}, or builtin:studio / builtin:sun", cxxopts::value<std::string>())
      ("size", "face size of level 0", cxxopts::value<std::string>()->default_value("256"))
      ("min-size", "face size of the smallest level", cxxopts::value<std::string>()->default_value("16"))
      ("distribution", "ggx | charlie", cxxopts::value<std::string>()->default_value("ggx"))
      ("schedule", "roughness of level l: linear | filament | sqrt", cxxopts::value<std::string>()->default_value("linear"))
      ("estimator", "quadrature (deterministic) | sampling (importance sampling with filtered importance sampling)", cxxopts::value<std::string>()->default_value("quadrature"))
      ("samples", "sampling: lobe samples per texel of every level", cxxopts::value<std::string>())
      ("max-error", "choose samples (sampling) or refinement (quadrature) per level from measurement", cxxopts::value<std::string>())
      ("refinement", "quadrature: refine pyramid texels within this many texel sizes of R", cxxopts::value<std::string>())
      ("no-env-sampling", "do not sum the bright texels explicitly")
      ("no-fis", "sampling: no filtered importance sampling (every sample reads level 0)")
      ("clamp", "BIASED, opt-in: compress source luminance above this value", cxxopts::value<std::string>())
      ("o,output", "FILE.ktx2, FILE.ktx, FILE.dds, or a folder", cxxopts::value<std::string>());
  add_cube_output_options(options);
  add_common_options(options);
  const auto r = parse(options, argc, argv);
  if (help_or_stray(options, r)) return 0;
  if (!r.count("env")) throw UsageError("missing --env FILE or --env builtin:studio|sun");
  if (!r.count("output")) throw UsageError("missing -o FILE.ktx2|.ktx|.dds|DIR");

  PrefilterSpec spec;
  spec.size = integer(r, "size");
  spec.min_size = integer(r, "min-size");
  if (spec.size < 1) throw UsageError("--size must be at least 1 (got " + std::to_string(spec.size) + ")");
  if (spec.min_size < 1 || spec.min_size > spec.size)
    throw UsageError("--min-size must be in 1..--size (got " + std::to_string(spec.min_size) + ")");
  spec.distribution = env_distribution_from_name(r["distribution"].as<std::string>());
  spec.schedule = roughness_schedule_from_name(r["schedule"].as<std::string>());
  spec.estimator = env_estimator_from_name(r["estimator"].as<std::string>());
  if (r.count("samples")) {
    if (spec.estimator != EnvEstimator::Sampling)
      throw UsageError("--samples needs --estimator sampling (the quadrature takes --refinement or --max-error)");
    spec.samples = integer(r, "samples");
    if (spec.samples < 1) throw UsageError("--samples must be a positive integer (got '" + r["samples"].as<std::string>() + "')");
  }
  if (r.count("max-error")) {
    if (r.count("samples") || r.count("refinement")) throw UsageError("give --max-error or --samples/--refinement, not both");
    spec.max_error = finite_number(r, "max-error");
    if (spec.max_error <= 0) throw UsageError("--max-error must be positive");
  }
  if (r.count("refinement")) spec.refinement = finite_number(r, "refinement");
  if (r.count("no-env-sampling")) spec.bright_texels = 0;
  if (r.count("no-fis")) spec.filtered_importance_sampling = false;
  if (r.count("clamp")) {
    spec.clamp_luminance = finite_number(r, "clamp");
    if (spec.clamp_luminance <= 0) throw UsageError("--clamp must be positive");
  }
  spec.precision = precision_option(r);

  const std::string out = r["output"].as<std::string>();
  const CubeFormat container = cube_container_option(r, out);
  const CubeWriteOptions wo = cube_write_options(r);

  const bool quiet = quiet_option(r);
  const std::string device_name = device_option(r);
  if (device_name == "reference")
    throw UsageError("--device reference is not available for prefilter (the brute-force reference is in "
                     "bench/prefilter_bench); choose an OpenCL device");
  const PrefilterSpec resolved = resolve_prefilter_spec(spec);  // validates before any slow work
  check_output_path(output_probe(out, container));
  const EnvImage env = load_environment_option(r, quiet);
  Device device = Device::open(device_name);
  const int levels = prefilter_level_count(resolved);
  // a progress line while the chain is filtered (on a terminal, for runs longer than half a second)
  ProgressLine line(quiet);
  const std::string title = std::string("prefiltering ") + env_distribution_name(spec.distribution) + " " +
                            std::to_string(resolved.size) + "^2 -> " +
                            std::to_string(std::max(1, resolved.size >> (levels - 1))) + "^2";
  auto progress = [&](double fraction, const std::string& what) { line.update(title + ", " + what, fraction); };
  PrefilterTiming timing;
  const CubeLevels cube = prefilter_environment(device, env, spec, &timing, progress);
  line.finish();
  write_cubemap(cube, out, container, wo);
  if (!quiet)
    std::fprintf(stderr, "%s: %s, %d levels %d^2 -> %d^2, %s schedule (%s), %s, %.3f s (device %.3f s)\n",
                 out.c_str(), env_distribution_name(spec.distribution), cube.level_count(), cube.size,
                 cube.level_size(cube.level_count() - 1), roughness_schedule_name(spec.schedule),
                 cube.meta("lod_from_roughness").c_str(), env_estimator_name(spec.estimator), timing.wall_seconds,
                 timing.device_seconds);
  return 0;
}

}  // namespace brdfbake::cli
