// Device queues: one worker thread per served device (each OpenCL device, and the reference), with
// its Backend opened once at start and kept warm (context, queue and built programs reused by every
// job). A device runs one thing at a time (its queue is in order and not shared), devices run
// concurrently. Fast-path tables go before queued jobs on their device. Jobs are stopped between
// bakes when cancelled, past their timeout, or at shutdown (then re-queued for the next start).
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "brdfbake/backend.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/tables.hpp"
#include "server/job_store.hpp"
#include "server/metrics.hpp"

namespace brdfbake::server {

struct SchedulerOptions {
  std::vector<std::string> devices;  // selectors to serve; "" = the default device; reference always
  std::filesystem::path jobs_dir;    // DATA/jobs: each job's folder
  int max_queue = 64;                // queued jobs (all devices) before submissions get 503
  int max_attempts = 2;              // a job the server stopped under this many times is failed
  bool warm_up = true;               // build the DFG and Fresnel programs at start
  // What a job's error says to clients: the server's own paths taken out (Roots::public_text).
  std::function<std::string(const std::string&)> public_text;
};

// The queue is full: the caller answers 503 with Retry-After.
class QueueFull : public Error {
 public:
  QueueFull(const std::string& m, int seconds) : Error(m), retry_after(seconds) {}
  int retry_after;
};

struct JobProgressInfo {
  int bake = 0, bakes = 0;
  std::string what;
  double fraction = 0.0;  // of this bake
};

struct DeviceStatus {
  std::string key;  // "0:0", "reference"
  std::string name;
  std::string type;                 // cpu, gpu, accelerator, other, reference
  std::uint64_t global_memory = 0;  // 0 for the reference
  bool warm = false;                // programs built
  std::string running;              // the job id it runs, "" when idle
  double rate = 0;                  // work units a second (job_work_units), measured; 0: not yet
  std::string table;                // the POST /v1/tables request it bakes ("ggx 1024"), "" when none
  bool busy = false;                // running a job or a table
  int queued = 0;                   // jobs waiting for it
  double busy_seconds = 0;
  // The fraction of the last minute it worked on jobs and tables (0..1), from its worker's busy
  // intervals (a job that also uses another device counts on its own device).
  double load = 0;
};

enum class CancelResult { Cancelled, Stopping, Finished, Unknown };

// A served device as the choice of a job's device sees it (Scheduler::fastest_device).
struct DeviceCandidate {
  std::string key, name;
  double rate = 0;     // work units a second it measured; 0: not measured yet
  double backlog = 0;  // work units of the jobs queued on it and of the one it runs
};
// The candidate that finishes `units` of work first: backlog / rate + units / rate, the smallest
// (the first of equal ones); candidates with no rate yet are left out. Returns its index, or -1
// when fewer than two candidates have a rate (then there is nothing to choose); `why` gets each
// one's estimate ("0:0 'NVIDIA H200': 0.12 s (backlog 0.05 s) ...").
int fastest_device(const std::vector<DeviceCandidate>& candidates, double units, std::string* why);
// A job's work in the units above: the bytes its tables' outputs hold (estimate_table_bytes), the
// one measure every kind has; a device's rate is measured in the same units.
double job_work_units(const std::vector<TableRequest>& tables);

class Scheduler {
 public:
  // Opens every device (throws Error naming the selector when one cannot be opened) and starts
  // the workers.
  Scheduler(JobStore& store, Metrics& metrics, SchedulerOptions options);
  ~Scheduler();
  Scheduler(const Scheduler&) = delete;
  Scheduler& operator=(const Scheduler&) = delete;

  // The key of the device a selector names ("" = the server's default, "reference"), or throws
  // Error "'<selector>' is not served here (serving ...)".
  std::string device_key(const std::string& selector);
  // Global memory of a device (0: the reference, host memory only).
  std::uint64_t device_memory(const std::string& key) const;

  // Stores a queued job (fills id and seq) and queues it on record.device. Throws QueueFull when
  // max_queue jobs are waiting, Error when the store fails. `units`: its work (job_work_units), for
  // the backlog the choice of a device reads; `choice`: why its device was chosen (choose_device),
  // kept for its status while the server runs.
  void submit(JobRecord& record, double units = 0, const std::string& choice = {});
  // For a job that names no device, where several OpenCL devices are served: the one that finishes
  // it first (fastest_device over the served OpenCL devices, their backlogs and measured rates).
  // Empty when there is no choice to make (one device, or rates not measured yet).
  std::string choose_device(double units, std::string* why) const;
  // Why a job's device was chosen ("" when it was named or there was no choice); in memory only.
  std::string device_choice(const std::string& id) const;
  // After a restart: queues a stored job again, whatever the limit.
  void resume(const JobRecord& record);

  // Runs `work` on a device before its queued jobs; the future carries its exceptions. `label`
  // says what it bakes while it runs (DeviceStatus::table).
  std::future<void> run_now(const std::string& key, const std::string& label, std::function<void(Backend&)> work);

  CancelResult cancel(const std::string& id);
  std::optional<JobProgressInfo> progress(const std::string& id) const;
  // Waits until the job is not queued or running (in memory), at most `seconds`.
  void wait_finished(const std::string& id, double seconds);

  std::vector<DeviceStatus> devices() const;
  int queued_total() const;
  int running_total() const;
  // POST /v1/tables requests being baked, all devices.
  int tables_running() const;

  // Stops taking work; lets running jobs finish for `grace` seconds, then stops them at their next
  // checkpoint (re-queued for the next start) and waits `hard` more seconds. True when every worker
  // has stopped (then joined); false when one is still inside a long bake.
  bool shutdown(double grace, double hard);

 private:
  struct Slot;
  struct Control;
  void worker(Slot& slot);
  void end_busy(Slot& slot);
  void run_job(Slot& slot, const std::string& id);
  void warm_up(Slot& slot);
  Slot* slot(const std::string& key) const;
  int retry_after_locked() const;

  JobStore& store_;
  Metrics& metrics_;
  SchedulerOptions options_;
  std::vector<std::unique_ptr<Slot>> slots_;  // the default device first
  mutable std::mutex queue_mutex_;            // every slot's queues, running and stopping_
  std::condition_variable work_cv_;           // work queued, or stopping
  std::condition_variable finished_cv_;       // a job left its queue or finished
  bool stopping_ = false;
  std::map<std::string, std::shared_ptr<Control>> running_;  // by job id
  double mean_job_seconds_ = 1.0;
  std::map<std::string, double> job_units_;     // queued and running jobs' work units, by id
  std::map<std::string, std::string> choices_;  // by id: why its device was chosen (bounded)
  mutable std::mutex selector_mutex_;
  std::map<std::string, std::string> selector_keys_;
};

}  // namespace brdfbake::server
