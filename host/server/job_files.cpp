#include "server/job_files.hpp"

#include <utility>

#include "server/confine.hpp"
#include "server/job_store.hpp"

namespace brdfbake::server {

namespace fs = std::filesystem;

JobFile find_job_file(JobStore& store, const Roots& roots, const fs::path& jobs_dir, const std::string& id,
                      const std::string& name, const std::string& use) {
  JobFile f;
  const auto refuse = [&f](int status, std::string error) {
    f.status = status;
    f.error = std::move(error);
    return f;
  };
  const auto r = store.get(id, false);
  if (!r) return refuse(404, "no job '" + id.substr(0, 40) + "'");
  if (r->state != JobState::Done)
    return refuse(r->state == JobState::Queued || r->state == JobState::Running ? 409 : 404,
                  "job " + id + " is " + job_state_name(r->state) + ": its files are " + use + " once it is done");
  const fs::path given(name);
  bool up = false;
  for (const auto& part : given) up |= part == "..";
  if (given.is_absolute() || up)
    return refuse(400, "file name '" + name.substr(0, 80) + "' must be a path inside the job's folder");
  f.path = roots.data_file(jobs_dir / id, name);
  if (f.path.empty()) {
    f.missing = true;
    return refuse(404, "job " + id + " has no file '" + name.substr(0, 80) + "'");
  }
  return f;
}

}  // namespace brdfbake::server
