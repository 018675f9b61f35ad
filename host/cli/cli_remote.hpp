// `--server URL` for run and bake: the job goes to a brdfbake server (host/server/client.hpp) and
// its files come back into the output folder; progress and summary as a local run prints them.
#pragma once

#include <cxxopts.hpp>
#include <string>

namespace brdfbake::cli {

// The options run and bake add: --server, --token-file.
void add_remote_options(cxxopts::Options& options);
bool remote_requested(const cxxopts::ParseResult& r);

// Runs a job file (run) or a job document (bake, job_json non-empty) on the server named by
// --server; returns the exit code.
int run_remote(const std::string& command, const cxxopts::ParseResult& r, const std::string& job_path,
               const std::string& job_json, const std::string& output_dir, bool sanitize, bool quiet);

}  // namespace brdfbake::cli
