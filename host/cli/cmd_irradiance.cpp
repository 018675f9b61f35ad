// brdfbake irradiance --env FILE|builtin:NAME [--sh 3|5] [--cube 32] [...] -o FILE.json|.ktx2|.ktx|.dds|DIR
#include <cstdio>
#include <filesystem>

#include "brdfbake/environment.hpp"
#include "cli_env.hpp"

namespace brdfbake::cli {

int cmd_irradiance(int argc, char** argv) {
  cxxopts::Options options("brdfbake irradiance",
                           "Diffuse irradiance of an environment: spherical harmonics and an irradiance cube");
  options.add_options()
      ("env", "FILE, six face files, a path with {face}, or builtin:studio / builtin:sun", cxxopts::value<std::string>())
      ("sh", "SH bands: 3 (9 coefficients) or 5 (25)", cxxopts::value<std::string>()->default_value("3"))
      ("sh-window", "none | hanning | lanczos (against ringing)", cxxopts::value<std::string>()->default_value("none"))
      ("cube", "face size of the irradiance cube", cxxopts::value<std::string>()->default_value("32"))
      ("source-size", "face size the environment is converted to for the cube (the SH uses the input itself)", cxxopts::value<std::string>()->default_value("256"))
      ("sh-json", "also write the SH coefficients to this JSON file", cxxopts::value<std::string>())
      ("o,output", "FILE.json (SH only), or the cube: FILE.ktx2, FILE.ktx, FILE.dds or a folder", cxxopts::value<std::string>());
  add_cube_output_options(options);
  add_common_options(options);
  const auto r = parse(options, argc, argv);
  if (help_or_stray(options, r)) return 0;
  if (!r.count("env")) throw UsageError("missing --env FILE or --env builtin:studio|sun");
  if (!r.count("output")) throw UsageError("missing -o FILE.json|.ktx2|.ktx|.dds|DIR");

  IrradianceSpec spec;
  spec.sh_order = integer(r, "sh");
  if (spec.sh_order != 3 && spec.sh_order != 5)
    throw UsageError("--sh must be 3 or 5 (got '" + r["sh"].as<std::string>() + "')");
  spec.window = sh_window_from_name(r["sh-window"].as<std::string>());
  spec.cube_size = integer(r, "cube");
  if (spec.cube_size < 1) throw UsageError("--cube must be at least 1 (got " + std::to_string(spec.cube_size) + ")");
  spec.source_size = integer(r, "source-size");
  if (spec.source_size < 1) throw UsageError("--source-size must be at least 1");
  spec.precision = precision_option(r);

  const std::string out = r["output"].as<std::string>();
  std::string ext = std::filesystem::path(out).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const bool json_only = ext == ".json";
  if (json_only) spec.cube_size = 0;
  CubeFormat format = CubeFormat::Ktx2;
  CubeWriteOptions wo;
  if (!json_only) {
    format = cube_container_option(r, out);
    wo = cube_write_options(r);
    wo.stem = "irradiance";
  }

  // a bad output path fails before any slow work
  check_output_path(json_only ? out : output_probe(out, format));
  if (r.count("sh-json")) check_output_path(r["sh-json"].as<std::string>());
  const bool quiet = quiet_option(r);
  const std::string device_name = device_option(r);
  if (device_name == "reference")
    throw UsageError("--device reference is not available for irradiance; choose an OpenCL device");
  const EnvImage env = load_environment_option(r, quiet);
  ProgressLine line(quiet);
  auto progress = [&](double fraction, const std::string& what) { line.update("irradiance, " + what, fraction); };
  IrradianceResult result;
  if (json_only) {
    result.sh = project_sh(env, spec.sh_order, spec.window);  // on the host: no OpenCL device to open
  } else {
    Device device = Device::open(device_name);
    result = compute_irradiance(device, env, spec, progress);
  }
  line.finish();
  Metadata meta = {{"source", env.source}};
  if (!json_only) meta.emplace_back("source_size", std::to_string(spec.source_size));
  if (json_only) {
    write_sh_json(result.sh, meta, out);
  } else {
    // the JSON first: if the cube cannot be written, the JSON goes again, so nothing is left half done
    const std::string sh_json = r.count("sh-json") ? r["sh-json"].as<std::string>() : std::string();
    if (!sh_json.empty()) write_sh_json(result.sh, meta, sh_json);
    try {
      write_cubemap(result.cube, out, format, wo);
    } catch (...) {
      if (!sh_json.empty()) std::remove(sh_json.c_str());
      throw;
    }
  }
  if (!quiet) {
    char cube_part[96] = "";
    if (!json_only)
      std::snprintf(cube_part, sizeof cube_part, ", irradiance cube %d^2 (E / pi), device %.3f s", spec.cube_size,
                    result.device_seconds);
    std::fprintf(stderr, "%s: SH order %d (%d coefficients, window %s, on the host)%s\n", out.c_str(),
                 result.sh.order, result.sh.order * result.sh.order, sh_window_name(result.sh.window), cube_part);
  }
  return 0;
}

}  // namespace brdfbake::cli
