// brdfbake run JOB.json [-o DIR] [--dry-run] [--quiet]
#include <iostream>

#include "brdfbake/job.hpp"
#include "cli_common.hpp"
#include "cli_remote.hpp"

namespace brdfbake::cli {

// cmd_bake.cpp
void print_manifest_summary(const Manifest& m, std::ostream& out);

int cmd_run(int argc, char** argv) {
  cxxopts::Options options("brdfbake run", "Run a job: bake every table it lists (docs/SCENES.md, \"Jobs\")");
  options.add_options()("job", "the job file (JSON)", cxxopts::value<std::string>())(
      "o,output", "output folder (overrides the job's output_dir)", cxxopts::value<std::string>())(
      "dry-run", "check the job and print it with every default filled in; bake nothing")(
      "sanitize", "replace NaN, infinite and negative environment pixels instead of refusing the input")(
      "memory-budget", memory_budget_help(), cxxopts::value<std::string>())(
      "wait", "when another run is writing the output folder, wait for it (default: fail at once)")(
      "quiet", "no progress or summary")("h,help", "this help");
  add_remote_options(options);
  options.parse_positional({"job"});
  options.positional_help("JOB.json");
  const auto r = parse(options, argc, argv);
  if (r.count("help")) {
    std::cout << options.help() << "\nexample:\n  brdfbake run examples/job.json -o out\n";
    return 0;
  }
  if (!r.unmatched().empty()) throw UsageError("unexpected argument '" + r.unmatched().front() + "'");
  if (!r.count("job")) throw UsageError("missing the job file (brdfbake run JOB.json)");
  const bool quiet = r.count("quiet") > 0;
  if (remote_requested(r) && !r.count("dry-run"))
    return run_remote("run", r, r["job"].as<std::string>(), "", r.count("output") ? r["output"].as<std::string>() : "",
                      r.count("sanitize") > 0, quiet);

  Job job = read_job(r["job"].as<std::string>());
  if (r.count("output")) job.output_dir = r["output"].as<std::string>();
  if (r.count("sanitize")) job.sanitize = true;
  if (r.count("dry-run")) {
    std::cout << job_to_json(job);
    return 0;
  }
  if (job.output_dir.empty()) throw UsageError("the job has no output_dir: give -o DIR");

  ProgressLine line(quiet);
  auto progress = [&](const JobEvent& e) {
    std::string what = "[" + std::to_string(e.bake + 1) + "/" + std::to_string(e.bakes) + "] " + e.what;
    what.resize(std::max<size_t>(what.size(), 56), ' ');
    line.update(what, e.fraction);
  };
  Manifest manifest;
  try {
    RunOptions run = run_options(r.count("wait") > 0, quiet);
    run.memory_budget = memory_budget_option(r);
    manifest = run_job(job, progress, run);
  } catch (...) {
    line.finish();
    throw;
  }
  line.finish();
  if (!quiet) print_manifest_summary(manifest, std::cout);
  return 0;
}

}  // namespace brdfbake::cli
