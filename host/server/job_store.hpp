// The server's job records in SQLite (DATA/jobs.db): one row a job, written at each change of state
// (submitted, running, finished), so that a restart after a crash or kill -9 finds every job as it
// last was. Live progress stays in memory (the scheduler); only states reach the disk.
// WAL journal, synchronous=NORMAL: a killed process loses no committed change; a power cut may lose
// the last few (docs/SERVICE.md, "Persistence").
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

struct sqlite3;

namespace brdfbake::server {

enum class JobState { Queued, Running, Done, Failed, Cancelled };
const char* job_state_name(JobState s);
std::optional<JobState> job_state_from_name(const std::string& name);
inline bool job_finished(JobState s) {
  return s == JobState::Done || s == JobState::Failed || s == JobState::Cancelled;
}

struct JobRecord {
  std::string id;
  std::int64_t seq = 0;  // submission order
  JobState state = JobState::Queued;
  std::string device;                               // the device queue it runs on (its key)
  std::string source;                               // what it was submitted as, for messages ("job.json", "bake")
  std::string job;                                  // the job document, paths confined (parse_job reads it back)
  double submitted = 0, started = 0, finished = 0;  // seconds since the epoch; 0: not yet
  int attempts = 0;                                 // times it started running
  double timeout = 0;                               // seconds of running allowed
  std::string error;                                // failed, cancelled: one line
  int exit_code = 0;              // what the command line exits with for it: 0, 1 runtime, 2 bad input
  std::string manifest;           // done: manifest.json
  bool cancel_requested = false;  // DELETE while running: never run again, whatever stops it
};

class JobStore {
 public:
  // Opens (creating when absent) the database; throws Error naming the file.
  explicit JobStore(const std::string& path);
  ~JobStore();
  JobStore(const JobStore&) = delete;
  JobStore& operator=(const JobStore&) = delete;

  // Adds a queued job; fills in id and seq. Throws Error (e.g. "database or disk is full").
  void insert(JobRecord& r);
  void mark_running(const std::string& id, double started, int attempts);
  void finish(const std::string& id, JobState state, double finished, const std::string& error, int exit_code,
              const std::string& manifest);
  // A running job was asked to stop (DELETE): recorded, so that a restart does not run it again.
  void request_cancel(const std::string& id);
  // Back to queued (a shutdown interrupted it); cancelled instead when a cancel was recorded.
  // True when it was queued.
  bool requeue(const std::string& id, double now);
  bool remove(const std::string& id);

  std::optional<JobRecord> get(const std::string& id, bool with_documents = true);
  // Newest first; `state` filters when given; without the job and manifest documents.
  std::vector<JobRecord> list(std::optional<JobState> state, int limit);
  std::map<std::string, std::int64_t> count_by_state();

  // After a restart: jobs left running are cancelled when a cancel was recorded for them, else
  // re-queued when they have started fewer than `max_attempts` times, else failed; returns those
  // it failed. Queued jobs are returned by queued() in submission order.
  std::vector<JobRecord> recover(int max_attempts, double now);
  std::vector<JobRecord> queued();

  // "ok", or what SQLite's integrity check found.
  std::string integrity_check();

 private:
  void exec(const char* sql);
  std::string path_;
  sqlite3* db_ = nullptr;
  std::mutex mutex_;
};

}  // namespace brdfbake::server
