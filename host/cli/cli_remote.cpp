#include "cli_remote.hpp"

#include <iostream>

#include "cli_common.hpp"
#include "server/client.hpp"

namespace brdfbake::cli {

// cmd_bake.cpp
void print_manifest_summary(const Manifest& m, std::ostream& out);

void add_remote_options(cxxopts::Options& options) {
  options.add_options()("server",
                        "run on a brdfbake server (http://HOST:PORT; docs/SERVICE.md) and download the files here",
                        cxxopts::value<std::string>())(
      "token-file", "with --server: the file holding the server's bearer token (default: $BRDFBAKE_TOKEN)",
      cxxopts::value<std::string>());
}

bool remote_requested(const cxxopts::ParseResult& r) {
  if (r.count("token-file") && !r.count("server")) throw UsageError("--token-file goes with --server");
  return r.count("server") > 0;
}

int run_remote(const std::string& command, const cxxopts::ParseResult& r, const std::string& job_path,
               const std::string& job_json, const std::string& output_dir, bool sanitize, bool quiet) {
  server::RemoteOptions o;
  o.url = r["server"].as<std::string>();
  if (r.count("token-file")) o.token_file = r["token-file"].as<std::string>();
  ProgressLine line(quiet);
  auto progress = [&](const JobEvent& e) {
    std::string what = "[" + std::to_string(e.bake + 1) + "/" + std::to_string(e.bakes) + "] " + e.what;
    what.resize(std::max<size_t>(what.size(), 56), ' ');
    line.update(what, e.fraction);
  };
  Manifest manifest;
  try {
    manifest = job_json.empty() ? server::remote_run_file(job_path, output_dir, sanitize, o, progress)
                                : server::remote_run(job_json, job_path, output_dir, o, progress);
  } catch (const server::RemoteError& e) {
    line.finish();
    std::cerr << "brdfbake " << command << ": " << e.what() << "\n";
    return e.exit_code;
  }
  line.finish();
  if (!quiet) print_manifest_summary(manifest, std::cout);
  return 0;
}

}  // namespace brdfbake::cli
