// brdfbake prefilter --env FILE|builtin:NAME [--size 256] [--min-size 16] [...] -o FILE.ktx2|.ktx|.dds|DIR
#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "brdfbake/environment.hpp"
#include "cli_common.hpp"

namespace brdfbake::cli {

namespace {

// A path whose writability stands for a folder output: a file inside it when it exists, else the
// folder itself (created later beside its siblings).
std::string directory_probe(const std::string& dir) {
  std::error_code ec;
  if (std::filesystem::is_directory(dir, ec)) return (std::filesystem::path(dir) / "probe").string();
  std::string d = dir;
  while (d.size() > 1 && d.back() == '/') d.pop_back();
  return d;
}

CubeImageLayout layout_from_name(const std::string& n) {
  if (n == "faces") return CubeImageLayout::Faces;
  if (n == "cross") return CubeImageLayout::HorizontalCross;
  if (n == "vcross") return CubeImageLayout::VerticalCross;
  if (n == "equirect") return CubeImageLayout::Equirect;
  throw UsageError("--layout must be faces, cross, vcross or equirect (got '" + n + "')");
}

}  // namespace

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
      ("sanitize", "replace NaN, infinite and negative pixels instead of refusing the input")
      ("pixel", "f16 | f32", cxxopts::value<std::string>()->default_value("f16"))
      ("layout", "folder output: faces | cross | vcross | equirect", cxxopts::value<std::string>()->default_value("faces"))
      ("image-format", "folder output: exr | hdr", cxxopts::value<std::string>()->default_value("exr"))
      ("dds-legacy", ".dds output: the legacy header (D3DFMT 113/116) instead of DX10")
      ("o,output", "FILE.ktx2, FILE.ktx, FILE.dds, or a folder", cxxopts::value<std::string>());
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
  const CubeFormat format = cube_format_from_path(out);
  CubeWriteOptions wo;
  const std::string pixel = r["pixel"].as<std::string>();
  if (pixel == "f16") wo.pixel = PixelType::F16;
  else if (pixel == "f32") wo.pixel = PixelType::F32;
  else throw UsageError("--pixel must be f16 or f32 (got '" + pixel + "')");
  wo.layout = layout_from_name(r["layout"].as<std::string>());
  const std::string image_format = r["image-format"].as<std::string>();
  if (image_format == "exr") wo.image_format = CubeImageFormat::Exr;
  else if (image_format == "hdr") wo.image_format = CubeImageFormat::Hdr;
  else throw UsageError("--image-format must be exr or hdr (got '" + image_format + "')");
  const CubeFormat container = format == CubeFormat::Dds && r.count("dds-legacy") ? CubeFormat::DdsLegacy : format;

  const bool quiet = quiet_option(r);
  const std::string device_name = device_option(r);
  if (device_name == "reference")
    throw UsageError("--device reference is not available for prefilter (the brute-force reference is in "
                     "bench/prefilter_bench); choose an OpenCL device");
  const PrefilterSpec resolved = resolve_prefilter_spec(spec);  // validates before any slow work
  check_output_path(format == CubeFormat::Directory ? directory_probe(out) : out);
  EnvLoadOptions lo;
  lo.sanitize = r.count("sanitize") > 0;
  const EnvImage env = load_environment(r["env"].as<std::string>(), lo);
  if (!quiet && env.sanitize.replaced)
    std::fprintf(stderr, "sanitized '%s': replaced %zu NaN, %zu infinite and %zu negative values\n",
                 env.source.c_str(), env.sanitize.nan, env.sanitize.infinite, env.sanitize.negative);
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
