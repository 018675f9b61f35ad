#include "server/scheduler.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "brdfbake/cancel.hpp"
#include "brdfbake/job.hpp"
#include "brdfbake/manifest.hpp"

namespace brdfbake::server {

namespace fs = std::filesystem;

namespace {

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

double steady_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// The window of DeviceStatus::load.
constexpr double kLoadWindowSeconds = 60.0;

// Thrown by a job's checkpoint: why the job stops before its next bake.
struct Stopped {
  enum Why { Cancel, Shutdown, Timeout } why;
};

void log_line(const std::string& s) {
  std::fprintf(stderr, "brdfbake serve: %s\n", s.c_str());
  std::fflush(stderr);
}

// The calibration bake of a device's warm-up: its time gives the device's first rate (work units a
// second) before any job measured one; a 16 x 16 GGX table of 256 evaluations a texel, long enough
// to be more than a launch's overhead on a CPU, a few milliseconds on a GPU.
TableRequest calibration_table() {
  TableRequest t;
  t.kind = TableKind::Ggx;
  t.params = {{"size", 16.0}, {"samples", 256.0}};
  return t;
}

}  // namespace

int fastest_device(const std::vector<DeviceCandidate>& candidates, double units, std::string* why) {
  int best = -1, measured = 0;
  double best_seconds = 0;
  std::string text;
  for (size_t i = 0; i < candidates.size(); ++i) {
    const DeviceCandidate& c = candidates[i];
    if (!(c.rate > 0)) {
      text += (text.empty() ? "" : "; ") + c.key + " '" + c.name + "': rate not measured yet";
      continue;
    }
    ++measured;
    const double backlog = c.backlog / c.rate, seconds = backlog + units / c.rate;
    char buf[160];
    std::snprintf(buf, sizeof buf, ": done in %.3g s (%.3g s of queued work first)", seconds, backlog);
    text += (text.empty() ? "" : "; ") + c.key + " '" + c.name + "'" + buf;
    if (best < 0 || seconds < best_seconds) best = static_cast<int>(i), best_seconds = seconds;
  }
  if (measured < 2) return -1;
  if (why) *why = "the first to finish it of " + std::to_string(measured) + " devices (" + text + ")";
  return best;
}

double job_work_units(const std::vector<TableRequest>& tables) {
  double units = 0;
  for (const TableRequest& t : tables) units += double(estimate_table_bytes(t));
  return units;
}

struct Scheduler::Slot {
  std::string key, name, type;
  std::uint64_t global_memory = 0;
  std::shared_ptr<Backend> backend;
  std::mutex use;  // held while the device works (its queue is in order and shared by nobody else)
  // Guarded by queue_mutex_:
  std::deque<std::packaged_task<void()>> tasks;  // fast path, first
  std::deque<std::string> jobs;
  std::string running;
  std::string table;  // the fast-path table being baked
  bool warm = false;
  double busy_seconds = 0;
  double rate = 0;  // work units a second (job_work_units): the warm-up's calibration, then each job's
  // The device load of the last minute (DeviceStatus::load): when the worker's current task or job
  // began (steady seconds, -1 when idle), and the busy intervals that ended within the last minute.
  double busy_since = -1;
  std::deque<std::pair<double, double>> recent;
  std::thread thread;
};

struct Scheduler::Control {
  std::atomic<int> stop{-1};  // -1: run on; else a Stopped::Why
  double deadline = 0;        // steady seconds; 0: none
  mutable std::mutex mutex;
  JobProgressInfo progress;
};

Scheduler::Scheduler(JobStore& store, Metrics& metrics, SchedulerOptions options)
    : store_(store), metrics_(metrics), options_(std::move(options)) {
  std::vector<std::string> selectors = options_.devices;
  if (selectors.empty()) selectors.push_back("");
  for (const std::string& sel : selectors) {
    if (sel == "reference") continue;
    auto s = std::make_unique<Slot>();
    try {
      s->backend = Backend::open(sel);
    } catch (const Error& e) {
      throw Error("--devices: cannot open '" + (sel.empty() ? std::string("default") : sel) + "': " + e.what());
    }
    const DeviceInfo& info = s->backend->device()->info();
    s->key = std::to_string(info.platform_index) + ":" + std::to_string(info.device_index);
    s->name = info.name;
    s->type = info.type;
    s->global_memory = info.global_memory;
    if (slot(s->key)) continue;  // two selectors of one device
    slots_.push_back(std::move(s));
  }
  auto ref = std::make_unique<Slot>();
  ref->key = ref->name = ref->type = "reference";
  ref->backend = Backend::open("reference");
  ref->warm = true;
  slots_.push_back(std::move(ref));
  for (auto& s : slots_) s->thread = std::thread([this, p = s.get()] { worker(*p); });
}

Scheduler::~Scheduler() {
  {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    stopping_ = true;
  }
  work_cv_.notify_all();
  for (auto& s : slots_)
    if (s->thread.joinable()) s->thread.join();
}

Scheduler::Slot* Scheduler::slot(const std::string& key) const {
  for (const auto& s : slots_)
    if (s->key == key) return s.get();
  return nullptr;
}

std::string Scheduler::device_key(const std::string& selector) {
  if (selector.empty() || selector == "default") return slots_.front()->key;
  if (selector == "reference") return "reference";
  {
    std::lock_guard<std::mutex> lock(selector_mutex_);
    auto it = selector_keys_.find(selector);
    if (it != selector_keys_.end()) return it->second;
  }
  std::string served;
  for (const auto& s : slots_) served += (served.empty() ? "" : ", ") + s->key + " '" + s->name + "'";
  std::string key;
  try {
    const DeviceInfo info = select_device(selector);
    key = std::to_string(info.platform_index) + ":" + std::to_string(info.device_index);
  } catch (const Error&) {
    throw Error("'" + selector.substr(0, 60) + "' names no device here (serving " + served + ")");
  }
  if (!slot(key)) throw Error("'" + selector.substr(0, 60) + "' is not served (serving " + served + "; see --devices)");
  std::lock_guard<std::mutex> lock(selector_mutex_);
  if (selector_keys_.size() < 256) selector_keys_[selector] = key;
  return key;
}

std::uint64_t Scheduler::device_memory(const std::string& key) const {
  const Slot* s = slot(key);
  return s ? s->global_memory : 0;
}

int Scheduler::retry_after_locked() const {
  int queued = 0;
  for (const auto& s : slots_) queued += static_cast<int>(s->jobs.size());
  const double seconds = mean_job_seconds_ * queued / static_cast<double>(slots_.size());
  return static_cast<int>(std::clamp(std::ceil(seconds), 1.0, 60.0));
}

void Scheduler::submit(JobRecord& r, double units, const std::string& choice) {
  std::unique_lock<std::mutex> lock(queue_mutex_);
  if (stopping_) throw QueueFull("the server is shutting down", 5);
  int queued = 0;
  for (const auto& s : slots_) queued += static_cast<int>(s->jobs.size());
  if (queued >= options_.max_queue)
    throw QueueFull("the queue is full (" + std::to_string(queued) + " jobs waiting, --max-queue " +
                        std::to_string(options_.max_queue) + "); retry later",
                    retry_after_locked());
  Slot* s = slot(r.device);
  if (!s) throw Error("device '" + r.device + "' is not served");
  store_.insert(r);  // under the lock: the queue and the store agree on every job
  s->jobs.push_back(r.id);
  job_units_[r.id] = units;
  if (!choice.empty()) {
    if (choices_.size() >= 4096) choices_.erase(choices_.begin());  // bounded: the oldest ids first
    choices_[r.id] = choice;
  }
  lock.unlock();
  work_cv_.notify_all();
}

void Scheduler::resume(const JobRecord& r) {
  std::unique_lock<std::mutex> lock(queue_mutex_);
  Slot* s = slot(r.device);
  if (!s) {
    lock.unlock();
    store_.finish(r.id, JobState::Failed, now_seconds(),
                  "device '" + r.device + "' is no longer served (the server restarted with other --devices)", 1, "");
    return;
  }
  s->jobs.push_back(r.id);
  lock.unlock();
  work_cv_.notify_all();
}

std::string Scheduler::choose_device(double units, std::string* why) const {
  std::vector<DeviceCandidate> candidates;
  std::vector<std::string> keys;
  {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    for (const auto& s : slots_) {
      if (s->key == "reference") continue;  // chosen only by name
      double backlog = 0;
      for (const std::string& id : s->jobs) {
        const auto it = job_units_.find(id);
        if (it != job_units_.end()) backlog += it->second;
      }
      if (!s->running.empty()) {
        const auto it = job_units_.find(s->running);
        if (it != job_units_.end()) backlog += it->second;  // all of it: its progress is not in units
      }
      candidates.push_back({s->key, s->name, s->rate, backlog});
    }
  }
  const int i = fastest_device(candidates, units, why);
  return i < 0 ? std::string() : candidates[static_cast<size_t>(i)].key;
}

std::string Scheduler::device_choice(const std::string& id) const {
  std::lock_guard<std::mutex> lock(queue_mutex_);
  const auto it = choices_.find(id);
  return it == choices_.end() ? std::string() : it->second;
}

std::future<void> Scheduler::run_now(const std::string& key, const std::string& label,
                                     std::function<void(Backend&)> work) {
  Slot* s = slot(key);
  if (!s) throw Error("device '" + key + "' is not served");
  std::packaged_task<void()> task([this, s, label, work = std::move(work)] {
    std::lock_guard<std::mutex> use(s->use);
    const auto t0 = std::chrono::steady_clock::now();
    // GET /v1/devices says what the device does while the table bakes (busy, and which table).
    struct Busy {
      Scheduler* self;
      Slot* slot;
      std::chrono::steady_clock::time_point t0;
      Busy(Scheduler* sch, Slot* sl, const std::string& what, std::chrono::steady_clock::time_point start)
          : self(sch), slot(sl), t0(start) {
        std::lock_guard<std::mutex> lock(self->queue_mutex_);
        slot->table = what;
      }
      ~Busy() {
        std::lock_guard<std::mutex> lock(self->queue_mutex_);
        slot->table.clear();
        slot->busy_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      }
      Busy(const Busy&) = delete;
      Busy& operator=(const Busy&) = delete;
    } busy{this, s, label, t0};
    work(*s->backend);
  });
  std::future<void> f = task.get_future();
  {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    if (stopping_) throw QueueFull("the server is shutting down", 5);
    if (static_cast<int>(s->tasks.size()) >= options_.max_queue)
      throw QueueFull("the table queue of device " + key + " is full; retry later", 1);
    s->tasks.push_back(std::move(task));
  }
  work_cv_.notify_all();
  return f;
}

void Scheduler::warm_up(Slot& s) {
  // The programs most requests need are built (or fetched from the binary cache) before the first
  // request, so that the first table costs what every other one does.
  std::lock_guard<std::mutex> use(s.use);
  try {
    for (const char* kind : {"ggx", "fresnel"}) {
      TableRequest t;
      t.kind = table_kind_from_name(kind);
      t.params = {{"size", 4.0}};
      if (t.kind == TableKind::Fresnel) {
        t.params.push_back({"model", std::string("schlick")});
        t.params.push_back({"f0", 0.04});
      }
      validate_table(t);
      (void)bake_table(t, *s.backend);
    }
  } catch (const std::exception& e) {
    log_line("warming up device " + s.key + " failed: " + e.what());
  }
  double rate = 0;
  try {
    TableRequest t = calibration_table();
    validate_table(t);
    const auto t0 = std::chrono::steady_clock::now();
    (void)bake_table(t, *s.backend);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (seconds > 0) rate = job_work_units({t}) / seconds;
  } catch (const std::exception& e) {
    log_line("timing device " + s.key + " failed: " + e.what());
  }
  std::lock_guard<std::mutex> lock(queue_mutex_);
  s.warm = true;
  if (s.rate <= 0) s.rate = rate;
}

// Called with queue_mutex_ held: the worker's task or job ended.
void Scheduler::end_busy(Slot& s) {
  const double now = steady_seconds();
  if (s.busy_since >= 0) s.recent.emplace_back(s.busy_since, now);
  s.busy_since = -1;
  while (!s.recent.empty() && s.recent.front().second < now - kLoadWindowSeconds) s.recent.pop_front();
}

void Scheduler::worker(Slot& s) {
  if (options_.warm_up && !s.warm) warm_up(s);
  for (;;) {
    std::unique_lock<std::mutex> lock(queue_mutex_);
    work_cv_.wait(lock, [&] { return stopping_ || !s.tasks.empty() || !s.jobs.empty(); });
    if (stopping_) return;  // queued jobs stay queued in the store for the next start
    if (!s.tasks.empty()) {
      std::packaged_task<void()> task = std::move(s.tasks.front());
      s.tasks.pop_front();
      s.busy_since = steady_seconds();
      lock.unlock();
      task();
      lock.lock();
      end_busy(s);
      continue;
    }
    const std::string id = s.jobs.front();
    s.jobs.pop_front();
    s.running = id;
    s.busy_since = steady_seconds();
    auto control = std::make_shared<Control>();
    running_[id] = control;
    lock.unlock();
    run_job(s, id);
    lock.lock();
    end_busy(s);
    s.running.clear();
    running_.erase(id);
    job_units_.erase(id);
    lock.unlock();
    finished_cv_.notify_all();
  }
}

void Scheduler::run_job(Slot& s, const std::string& id) {
  std::shared_ptr<Control> control;
  {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    control = running_.at(id);
  }
  std::optional<JobRecord> rec;
  try {
    rec = store_.get(id);
  } catch (const std::exception& e) {
    log_line("job " + id + ": " + e.what());
    return;
  }
  if (!rec || rec->state != JobState::Queued) return;  // cancelled while it waited
  auto public_text = [this](const std::string& m) { return options_.public_text ? options_.public_text(m) : m; };
  const auto t0 = std::chrono::steady_clock::now();
  auto steady = [] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  };
  if (rec->timeout > 0) control->deadline = steady() + rec->timeout;
  auto finish = [&](JobState state, const std::string& error, int exit_code, const std::string& manifest) {
    try {
      store_.finish(id, state, now_seconds(), error, exit_code, manifest);
    } catch (const std::exception& e) {
      // The store cannot record it (a full disk): the job stays "running" there and the next start
      // runs it again.
      log_line("job " + id + ": cannot record that it " + (state == JobState::Done ? "finished" : "failed") + ": " +
               e.what());
    }
  };
  try {
    store_.mark_running(id, now_seconds(), rec->attempts + 1);
  } catch (const std::exception& e) {
    log_line("job " + id + ": " + e.what());
    return;
  }
  try {
    Job job = parse_job(rec->job, rec->source);
    // The name of the client's output folder (kept from the submission), for an engine's files.
    const std::string engine_name = fs::path(job.output_dir).filename().string();
    const fs::path out = options_.jobs_dir / id;
    std::error_code ec;
    fs::remove_all(out, ec);  // what an interrupted earlier attempt may have left
    job.output_dir = out.string();

    // Every device the job uses, locked in one global order (no two workers can wait on each other).
    std::vector<std::string> keys = {s.key};
    for (const auto& t : job.tables) keys.push_back(device_key(t.device.empty() ? job.device : t.device));
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    std::vector<std::unique_lock<std::mutex>> locks;
    for (const auto& k : keys) locks.emplace_back(slot(k)->use);

    RunHooks hooks;
    if (!engine_name.empty() && engine_name != "." && engine_name != "..") hooks.engine_name = engine_name;
    hooks.backend = [&](const std::string& selector) {
      return slot(device_key(selector.empty() ? job.device : selector))->backend;
    };
    hooks.checkpoint = [&] {
      const int why = control->stop.load();
      if (why >= 0) throw Stopped{static_cast<Stopped::Why>(why)};
      if (control->deadline > 0 && steady() > control->deadline) throw Stopped{Stopped::Timeout};
    };
    // The same reasons stop a bake at its next step (a launch, a row, a level), not only between
    // tables: a cancel, a timeout or a shutdown frees the device within a step.
    hooks.stop_requested = [&] {
      return control->stop.load() >= 0 || (control->deadline > 0 && steady() > control->deadline);
    };
    auto on_progress = [&](const JobEvent& e) {
      std::lock_guard<std::mutex> lock(control->mutex);
      control->progress = {e.bake, e.bakes, e.what, e.fraction};
    };
    Manifest m;
    try {
      try {
        m = brdfbake::run_job(job, on_progress, hooks);
      } catch (const Cancelled&) {
        // stop_requested said stop: why, as the checkpoint would have
        hooks.checkpoint();
        throw;
      }
    } catch (...) {
      const double busy = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::lock_guard<std::mutex> lock(queue_mutex_);
      for (const auto& k : keys) slot(k)->busy_seconds += busy;
      throw;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    {
      std::lock_guard<std::mutex> lock(queue_mutex_);
      for (const auto& k : keys) slot(k)->busy_seconds += seconds;
      mean_job_seconds_ = 0.8 * mean_job_seconds_ + 0.2 * seconds;
      // the device's rate, from what this job measured (it alone used the device: keys.size() 1)
      const auto units = job_units_.find(id);
      if (units != job_units_.end() && units->second > 0 && seconds > 0 && keys.size() == 1) {
        const double measured = units->second / seconds;
        s.rate = s.rate > 0 ? 0.7 * s.rate + 0.3 * measured : measured;
      }
    }
    std::vector<bool> seen(static_cast<size_t>(std::max(m.bakes, 0)), false);
    for (const auto& f : m.files)
      if (f.bake >= 0 && static_cast<size_t>(f.bake) < seen.size() && !seen[static_cast<size_t>(f.bake)]) {
        seen[static_cast<size_t>(f.bake)] = true;
        metrics_.observe_bake(table_kind_name(f.kind), f.seconds);
      }
    finish(JobState::Done, "", 0, manifest_to_json(m));
  } catch (const Stopped& st) {
    if (st.why == Stopped::Shutdown) {
      try {
        (void)store_.requeue(id, now_seconds());  // or cancelled, when a DELETE came first
      } catch (const std::exception& e) {
        log_line("job " + id + ": cannot re-queue it: " + e.what());
      }
    } else if (st.why == Stopped::Cancel) {
      finish(JobState::Cancelled, "cancelled (DELETE /v1/jobs/" + id + ") while running; nothing was written", 1, "");
    } else {
      char buf[160];
      std::snprintf(buf, sizeof buf, "timed out: still running after its timeout of %g s; nothing was written",
                    rec->timeout);
      finish(JobState::Failed, buf, 1, "");
    }
  } catch (const Cancelled& e) {
    finish(JobState::Failed, public_text(e.what()), 1, "");
  } catch (const RuntimeFailure& e) {
    // The server failed, not the request (a full disk, the device, a kind this build lacks): exit 1.
    finish(JobState::Failed, public_text(e.what()), 1, "");
  } catch (const Error& e) {
    finish(JobState::Failed, public_text(e.what()), 2, "");
  } catch (const std::exception& e) {
    finish(JobState::Failed, public_text(e.what()), 1, "");
  }
}

CancelResult Scheduler::cancel(const std::string& id) {
  std::unique_lock<std::mutex> lock(queue_mutex_);
  for (auto& s : slots_) {
    auto it = std::find(s->jobs.begin(), s->jobs.end(), id);
    if (it != s->jobs.end()) {
      s->jobs.erase(it);
      job_units_.erase(id);
      store_.finish(id, JobState::Cancelled, now_seconds(), "cancelled (DELETE /v1/jobs/" + id + ") before it started",
                    1, "");
      lock.unlock();
      finished_cv_.notify_all();
      return CancelResult::Cancelled;
    }
  }
  auto r = running_.find(id);
  if (r != running_.end()) {
    int none = -1;
    r->second->stop.compare_exchange_strong(none, Stopped::Cancel);
    // Recorded, so that a server stopped (or killed) before the job stops does not run it again.
    try {
      store_.request_cancel(id);
    } catch (const std::exception& e) {
      log_line("job " + id + ": cannot record its cancellation: " + e.what());
    }
    return CancelResult::Stopping;
  }
  lock.unlock();
  const auto rec = store_.get(id, false);
  if (!rec) return CancelResult::Unknown;
  return CancelResult::Finished;
}

std::optional<JobProgressInfo> Scheduler::progress(const std::string& id) const {
  std::shared_ptr<Control> c;
  {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    auto it = running_.find(id);
    if (it == running_.end()) return std::nullopt;
    c = it->second;
  }
  std::lock_guard<std::mutex> lock(c->mutex);
  return c->progress;
}

void Scheduler::wait_finished(const std::string& id, double seconds) {
  std::unique_lock<std::mutex> lock(queue_mutex_);
  auto pending = [&] {
    if (stopping_) return false;
    if (running_.count(id)) return true;
    for (const auto& s : slots_)
      if (std::find(s->jobs.begin(), s->jobs.end(), id) != s->jobs.end()) return true;
    return false;
  };
  finished_cv_.wait_for(lock, std::chrono::duration<double>(seconds), [&] { return !pending(); });
}

std::vector<DeviceStatus> Scheduler::devices() const {
  std::lock_guard<std::mutex> lock(queue_mutex_);
  std::vector<DeviceStatus> out;
  for (const auto& s : slots_) {
    DeviceStatus d;
    d.key = s->key;
    d.name = s->name;
    d.type = s->type;
    d.global_memory = s->global_memory;
    d.warm = s->warm;
    d.running = s->running;
    d.table = s->table;
    d.busy = !s->running.empty() || !s->table.empty();
    d.queued = static_cast<int>(s->jobs.size());
    d.rate = s->rate;
    d.busy_seconds = s->busy_seconds;
    // The busy part of the last minute: finished intervals and the one under way, clipped to it.
    const double now = steady_seconds(), from = now - kLoadWindowSeconds;
    double busy = s->busy_since >= 0 ? now - std::max(s->busy_since, from) : 0.0;
    for (const auto& [start, end] : s->recent)
      if (end > from) busy += end - std::max(start, from);
    d.load = std::min(1.0, busy / kLoadWindowSeconds);
    out.push_back(d);
  }
  return out;
}

int Scheduler::queued_total() const {
  std::lock_guard<std::mutex> lock(queue_mutex_);
  int n = 0;
  for (const auto& s : slots_) n += static_cast<int>(s->jobs.size());
  return n;
}

int Scheduler::running_total() const {
  std::lock_guard<std::mutex> lock(queue_mutex_);
  return static_cast<int>(running_.size());
}

int Scheduler::tables_running() const {
  std::lock_guard<std::mutex> lock(queue_mutex_);
  int n = 0;
  for (const auto& s : slots_) n += s->table.empty() ? 0 : 1;
  return n;
}

bool Scheduler::shutdown(double grace, double hard) {
  std::unique_lock<std::mutex> lock(queue_mutex_);
  stopping_ = true;
  for (auto& s : slots_) s->tasks.clear();  // their callers get a broken promise: 503
  work_cv_.notify_all();
  finished_cv_.notify_all();
  finished_cv_.wait_for(lock, std::chrono::duration<double>(grace), [&] { return running_.empty(); });
  for (auto& [id, c] : running_) {
    int none = -1;
    c->stop.compare_exchange_strong(none, Stopped::Shutdown);
  }
  const bool stopped =
      finished_cv_.wait_for(lock, std::chrono::duration<double>(hard), [&] { return running_.empty(); });
  lock.unlock();
  if (!stopped) return false;
  for (auto& s : slots_)
    if (s->thread.joinable()) s->thread.join();
  return true;
}

}  // namespace brdfbake::server
