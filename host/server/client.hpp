// The server's client in the command line: `brdfbake run JOB.json --server URL` and
// `brdfbake bake --server URL` submit the job, follow its progress and download its files into the
// output folder all or nothing, as a local run writes them (docs/SERVICE.md, "From the command
// line").
#pragma once

#include <functional>
#include <string>

#include "brdfbake/job.hpp"
#include "brdfbake/manifest.hpp"

namespace brdfbake::server {

// A remote run that failed: the job's own error (with the exit code the command line would have
// used for it locally) or the server's answer.
class RemoteError : public Error {
 public:
  RemoteError(const std::string& m, int code) : Error(m), exit_code(code) {}
  int exit_code;  // 1 runtime, 2 bad input
};

struct RemoteOptions {
  std::string url;         // http://host:port
  std::string token_file;  // "" = $BRDFBAKE_TOKEN, else no token
  double poll_seconds = 0.2;
};

// Submits `job_json` (a job document; `source` names it in messages, e.g. "job.json"), follows it
// and downloads every file and manifest.json into `output_dir` (written in a temporary folder
// beside it and moved in at the end). Returns the manifest as the server recorded it.
Manifest remote_run(const std::string& job_json, const std::string& source, const std::string& output_dir,
                    const RemoteOptions& options, const JobProgress& progress = {});

// `brdfbake run JOB.json --server URL`: reads the job file (malformed JSON is refused here, in the
// words a local run uses), applies the command line's overrides, submits it as it is (the server
// checks it and finds its input files under its input root) and downloads into `output_dir`
// ("" = the job's output_dir).
Manifest remote_run_file(const std::string& job_path, const std::string& output_dir, bool sanitize,
                         const RemoteOptions& options, const JobProgress& progress = {});

// A manifest.json read back (the fields the command line's summary shows).
Manifest manifest_from_json(const std::string& text, const std::string& output_dir);

}  // namespace brdfbake::server
