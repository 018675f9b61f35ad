// brdfbake lut --kind ggx|ggx-multiscatter|charlie --size N [...] -o FILE
#include <cstdio>
#include <iostream>

#include "brdfbake/io.hpp"
#include "brdfbake/lut.hpp"
#include "cli_common.hpp"

namespace brdfbake::cli {

int cmd_lut(int argc, char** argv) {
  cxxopts::Options options("brdfbake lut", "Bake a split-sum DFG lookup table");
  options.add_options()
      ("kind", "ggx | ggx-multiscatter | charlie", cxxopts::value<std::string>()->default_value("ggx"))
      ("size", "cells along n_dot_v (and roughness unless --height)", cxxopts::value<std::string>()->default_value("128"))
      ("height", "cells along roughness", cxxopts::value<std::string>())
      ("samples", "evaluations per texel (default: the calibrated count for a 1e-4 bound)", cxxopts::value<std::string>())
      ("max-error", "choose the sample count that keeps the max abs error below this", cxxopts::value<std::string>())
      ("estimator", "quadrature | vndf | ndf | uniform", cxxopts::value<std::string>()->default_value("quadrature"))
      ("sheen-visibility", "charlie visibility: estevez-kulla | neubelt", cxxopts::value<std::string>()->default_value("estevez-kulla"));
  add_table_output_options(options);
  add_common_options(options);
  const auto r = parse(options, argc, argv);
  if (help_or_stray(options, r)) return 0;

  LutSpec spec;
  spec.kind = lut_kind_from_name(r["kind"].as<std::string>());
  spec.width = integer(r, "size");
  spec.height = r.count("height") ? integer(r, "height") : spec.width;
  if (spec.width < 1 || spec.height < 1) throw UsageError("--size and --height must be at least 1");
  if (r.count("samples")) {
    spec.samples = integer(r, "samples");
    if (spec.samples < 1) throw UsageError("--samples must be a positive integer (got '" + r["samples"].as<std::string>() + "')");
  }
  if (r.count("max-error")) {
    spec.max_error = finite_number(r, "max-error");
    if (spec.max_error <= 0) throw UsageError("--max-error must be positive");
  }
  spec.estimator = estimator_from_name(r["estimator"].as<std::string>());
  spec.sheen_visibility = sheen_visibility_from_name(r["sheen-visibility"].as<std::string>());
  spec.precision = precision_option(r);
  const LutSpec resolved = resolve_lut_spec(spec);  // validates before any slow work
  const TableOutput out = table_output_option(r);
  const bool quiet = quiet_option(r);
  const std::string device_name = device_option(r);

  ProgressLine progress_line(quiet);
  auto progress = [&](double fraction) {
    progress_line.update("baking " + std::string(lut_kind_name(spec.kind)) + " " + std::to_string(resolved.width) +
                             "x" + std::to_string(resolved.height),
                         fraction);
  };
  LutTiming timing;
  Table table;
  if (device_name == "reference") {
    table = bake_lut_reference(spec, &timing, progress);
  } else {
    Device device = Device::open(device_name);
    table = bake_lut(device, spec, &timing, progress);
  }
  progress_line.finish();
  write_table_output(table, out);
  if (!quiet)
    std::fprintf(stderr, "%s: %s %dx%d, %s, %s samples, %s, error bound %s, %.3f s (device %.3f s)\n",
                 out.path == "-" ? "stdout" : out.path.c_str(), lut_kind_name(spec.kind), table.width, table.height,
                 table.meta("estimator").c_str(), table.meta("samples").c_str(), table.meta("precision").c_str(),
                 table.meta("error_bound").c_str(), timing.wall_seconds, timing.device_seconds);
  return 0;
}

}  // namespace brdfbake::cli
