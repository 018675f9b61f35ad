// brdfbake report [--kinds K,...] [--device SEL] [--size N] [--counts N,...] [...] -o report.html
#include <cstdio>
#include <iostream>
#include <sstream>

#include "brdfbake/environment.hpp"
#include "brdfbake/output_checks.hpp"
#include "brdfbake/report.hpp"
#include "cli_common.hpp"
#include "cli_table.hpp"

namespace brdfbake::cli {

namespace {

std::vector<std::string> list(const std::string& text, const std::string& option) {
  std::vector<std::string> out;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ','))
    if (!item.empty()) out.push_back(item);
  if (out.empty()) throw UsageError("--" + option + " must list at least one value");
  return out;
}

std::vector<int> int_list(const std::string& text, const std::string& option) {
  std::vector<int> out;
  for (const auto& item : list(text, option)) {
    char* end = nullptr;
    const long v = std::strtol(item.c_str(), &end, 10);
    if (*end != '\0' || v < 1 || v > (1 << 20))
      throw UsageError("--" + option + ": '" + item + "' is not a count in 1..1048576");
    out.push_back(static_cast<int>(v));
  }
  return out;
}

}  // namespace

int cmd_report(int argc, char** argv) {
  cxxopts::Options options(
      "brdfbake report",
      "Measure accuracy against time on a device and write a self-contained HTML page with the plots, "
      "and a JSON of the numbers beside it (docs/BENCHMARKS.md)");
  // clang-format off
  options.add_options()
      ("kinds", "what to measure: ggx, ggx-multiscatter, charlie, fresnel, prefilter, bake, kernels (default: ggx,ggx-multiscatter,charlie)", cxxopts::value<std::string>())
      ("lut-size,size", "DFG tables: cells a side (default: 64) (alias: --size)", cxxopts::value<std::string>())
      ("counts", "DFG tables: sample counts (default: 16,32,64,128,256,384,512,768,1024,2048,4096)", cxxopts::value<std::string>())
      ("estimators", "DFG tables: quadrature, vndf, ndf, uniform (default: every estimator of the kind)", cxxopts::value<std::string>())
      ("precisions", "fp32, fp64 (default: fp32)", cxxopts::value<std::string>())
      ("max-seconds", "DFG tables: after a bake slower than this, larger counts of its estimator are skipped (default: 1.5; 0: none)", cxxopts::value<std::string>())
      ("materials", "fresnel: measured materials (default: gold,copper,aluminium,water)", cxxopts::value<std::string>())
      ("targets", "bake: the targets swept (default: generic,filament,gltf,babylon,khronos-viewer)", cxxopts::value<std::string>())
      ("vary", "bake: the settings, one at a time around each target's defaults, as OPTION=V1,V2;OPTION=... (default: chain_size=64,128,512;min_size=4,64;schedule=sqrt;lut_size=16,32,64;n_dot_v_axis=sqrt;pixel=f32;sh_order=5;chain_max_error=0.03,0.003); an alias (cube_size) is taken as its option's name", cxxopts::value<std::string>())
      ("preview-width", "bake: the preview's width, its height half of it (default: 512: the spheres of the default 512x512 preview)", cxxopts::value<std::string>())
      ("runs", "bake: bakes per setting under 1 s, the median reported; kernels: timed runs of each kernel after a warm-up (default: 3)", cxxopts::value<std::string>())
      ("count-ops", "kernels: run each kernel once at its counting size under Oclgrind's flop counter (scripts/count_kernel_ops.sh), no peaks, no figures")
      ("keep-bakes", "bake: keep each setting's bake in DIR/TARGET/SETTING (default: removed)", cxxopts::value<std::string>())
      ("environment,env", "prefilter and bake: the environment (default: builtin:studio) (alias: --env)", cxxopts::value<std::string>())
      ("chain-size,cube-size", "prefilter: face size of the chain's first level (default: 32) (alias: --cube-size)", cxxopts::value<std::string>())
      ("device", "P:D, cpu, gpu or a name substring (default: BRDFBAKE_DEVICE, else the first GPU, else the first CPU)", cxxopts::value<std::string>())
      ("o,output", "the page (.html); the JSON goes beside it with .json (default: report.html)", cxxopts::value<std::string>())
      ("quiet", "no progress lines or summary")
      ("h,help", "this help");
  // clang-format on
  const auto r = parse(options, argc, argv);
  refuse_two_spellings(argc, argv,
                       {ParamDef("lut_size", ParamType::Int, "").alias("size"),
                        ParamDef("chain_size", ParamType::Int, "").alias("cube_size"),
                        ParamDef("environment", ParamType::Path, "").alias("env")});
  if (r.count("help")) {
    std::cout << options.help()
              << "\nexamples:\n  brdfbake report -o report.html\n"
                 "  brdfbake report --kinds ggx,fresnel,prefilter --precisions fp32,fp64 --device gpu -o gpu.html\n"
                 "  brdfbake report --kinds bake --env ../shared/envmaps/venice_sunset_1k.hdr -o bake.html\n"
                 "  brdfbake report --kinds kernels -o kernels.html\n";
    return 0;
  }
  if (!r.unmatched().empty()) throw UsageError("unexpected argument '" + r.unmatched().front() + "'");
  ReportOptions o;
  if (r.count("kinds")) o.kinds = list(r["kinds"].as<std::string>(), "kinds");
  if (r.count("lut-size")) o.dfg.size = integer(r, "lut-size");
  if (o.dfg.size < 1 || o.dfg.size > 4096) throw UsageError("--lut-size must be 1 to 4096");
  if (r.count("counts")) o.dfg.counts = int_list(r["counts"].as<std::string>(), "counts");
  if (r.count("estimators"))
    for (const auto& e : list(r["estimators"].as<std::string>(), "estimators"))
      o.dfg.estimators.push_back(estimator_from_name(e));
  if (r.count("precisions")) {
    o.dfg.precisions.clear();
    for (const auto& p : list(r["precisions"].as<std::string>(), "precisions"))
      o.dfg.precisions.push_back(precision_from_name(p));
  }
  if (r.count("max-seconds")) {
    o.dfg.max_seconds_per_bake = finite_number(r, "max-seconds");
    if (o.dfg.max_seconds_per_bake < 0) throw UsageError("--max-seconds must be >= 0");
  }
  if (r.count("materials")) o.materials = list(r["materials"].as<std::string>(), "materials");
  if (r.count("environment")) o.environment = r["environment"].as<std::string>();
  if (r.count("chain-size")) o.prefilter_size = integer(r, "chain-size");
  if (o.prefilter_size < 4 || o.prefilter_size > 256) throw UsageError("--chain-size must be 4 to 256");
  if (r.count("targets")) o.bake.targets = list(r["targets"].as<std::string>(), "targets");
  if (r.count("vary")) {
    std::stringstream f(r["vary"].as<std::string>());
    std::string item;
    while (std::getline(f, item, ';')) {
      if (item.empty()) continue;
      const size_t eq = item.find('=');
      if (eq == std::string::npos || eq == 0)
        throw UsageError("--vary: '" + item + "' is not OPTION=VALUE,VALUE (e.g. chain_size=64,128)");
      o.bake.factors.push_back({item.substr(0, eq), list(item.substr(eq + 1), "vary")});
    }
    if (o.bake.factors.empty()) throw UsageError("--vary must list at least one OPTION=VALUES");
  }
  if (r.count("preview-width")) o.bake.preview_width = integer(r, "preview-width");
  if (o.bake.preview_width < 96 || o.bake.preview_width > 4096)
    throw UsageError("--preview-width must be 96 to 4096 (12 columns of spheres at least 8 pixels wide)");
  if (r.count("runs")) o.bake.runs = o.kernels.runs = integer(r, "runs");
  if (o.bake.runs < 1 || o.bake.runs > 9) throw UsageError("--runs must be 1 to 9");
  o.kernels.count = r.count("count-ops") > 0;
  if (r.count("keep-bakes")) o.bake.keep_bakes = r["keep-bakes"].as<std::string>();
  if (r.count("device")) o.device = r["device"].as<std::string>();
  const std::string out = r.count("output") ? r["output"].as<std::string>() : std::string("report.html");
  if (out.size() < 6 || out.substr(out.size() - 5) != ".html")
    throw UsageError("-o must name an .html file (got '" + out + "')");
  const bool quiet = r.count("quiet") > 0;
  for (int k = 0; k < argc; ++k) o.command += (k ? " " : "brdfbake ") + std::string(argv[k]);
  check_output_path(out);
  check_output_path(report_json_path(out));
  {  // the page and its JSON are not the environment it reads, nor a folder
    std::vector<RequestFile> inputs;
    if (!o.environment.empty())
      for (const auto& f : environment_files(o.environment)) inputs.push_back({"--env", f, false, ""});
    check_outputs_not_inputs({{"-o", out, false, ""}, {"-o", report_json_path(out), false, "JSON"}}, inputs);
  }
  if (!quiet) o.log = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  const Report report = run_report(o);
  write_report(report, out);
  if (!quiet) {
    size_t n = 0;
    for (const auto& s : report.dfg) n += s.points.size();
    for (const auto& f : report.fresnel) n += f.rows.size();
    for (const auto& p : report.prefilter) n += p.levels.size();
    for (const auto& b : report.bake)
      for (const auto& t : b.targets) n += t.points.size();
    for (const auto& k : report.kernels) n += k.rows.size();
    std::fprintf(
        stderr,
        "%s and %s: %zu measurements on %s in %.1f s (load average %.2f at the start, %.2f at the end, %d cores)\n",
        out.c_str(), report_json_path(out).c_str(), n, report.device.c_str(), report.seconds, report.load_before[0],
        report.load_after[0], report.cores);
  }
  return 0;
}

}  // namespace brdfbake::cli
