// The one lookup of a file a finished job wrote, by the job's id and the file's name inside its
// folder, for GET /v1/jobs/ID/files/NAME (server.cpp) and GET /v1/jobs/ID/view/NAME
// (web_routes.cpp): the job known and done, the name a relative path without '..', and the file
// found by Roots::data_file (no symbolic link on the way, a regular file).
#pragma once

#include <filesystem>
#include <string>

namespace brdfbake::server {

class JobStore;
class Roots;

struct JobFile {
  std::string path;      // the file on disk; empty when the request is refused
  int status = 0;        // when refused: 404 (no such job or file), 409 (not done yet), 400 (a hostile name)
  std::string error;     // when refused: the one line of the reply
  bool missing = false;  // refused only because no file has the name (the caller may say more)
};

// The file `name` of job `id` under `jobs_dir` (DATA/jobs). `use` completes "its files are USE once
// it is done" for a job not done yet ("served", "shown").
JobFile find_job_file(JobStore& store, const Roots& roots, const std::filesystem::path& jobs_dir, const std::string& id,
                      const std::string& name, const std::string& use);

}  // namespace brdfbake::server
