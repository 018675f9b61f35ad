#include "server/job_store.hpp"

#include <sqlite3.h>

#include <random>

#include "brdfbake/error.hpp"

namespace brdfbake::server {

const char* job_state_name(JobState s) {
  switch (s) {
    case JobState::Queued:
      return "queued";
    case JobState::Running:
      return "running";
    case JobState::Done:
      return "done";
    case JobState::Failed:
      return "failed";
    default:
      return "cancelled";
  }
}

std::optional<JobState> job_state_from_name(const std::string& n) {
  for (JobState s : {JobState::Queued, JobState::Running, JobState::Done, JobState::Failed, JobState::Cancelled})
    if (n == job_state_name(s)) return s;
  return std::nullopt;
}

namespace {

// One prepared statement, finalized on scope exit; every failure throws with the database's words.
class Statement {
 public:
  Statement(sqlite3* db, const std::string& path, const char* sql) : db_(db), path_(path) {
    if (sqlite3_prepare_v2(db, sql, -1, &st_, nullptr) != SQLITE_OK) fail();
  }
  ~Statement() { sqlite3_finalize(st_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  Statement& bind(int i, const std::string& v) {
    check(sqlite3_bind_text(st_, i, v.data(), static_cast<int>(v.size()), SQLITE_TRANSIENT));
    return *this;
  }
  Statement& bind(int i, double v) {
    check(sqlite3_bind_double(st_, i, v));
    return *this;
  }
  Statement& bind(int i, std::int64_t v) {
    check(sqlite3_bind_int64(st_, i, v));
    return *this;
  }
  Statement& bind(int i, int v) {
    check(sqlite3_bind_int(st_, i, v));
    return *this;
  }
  // True while there is a row.
  bool step() {
    const int rc = sqlite3_step(st_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    fail();
    return false;
  }
  std::string text(int c) const {
    const auto* p = sqlite3_column_text(st_, c);
    return p ? std::string(reinterpret_cast<const char*>(p), static_cast<size_t>(sqlite3_column_bytes(st_, c)))
             : std::string();
  }
  double real(int c) const { return sqlite3_column_double(st_, c); }
  std::int64_t integer(int c) const { return sqlite3_column_int64(st_, c); }

 private:
  void check(int rc) {
    if (rc != SQLITE_OK) fail();
  }
  // The database failing is the server's failure (a full disk), not the request's.
  [[noreturn]] void fail() { throw RuntimeFailure("job database '" + path_ + "': " + sqlite3_errmsg(db_)); }
  sqlite3* db_;
  std::string path_;
  sqlite3_stmt* st_ = nullptr;
};

constexpr const char* kColumns =
    "id, seq, state, device, source, submitted, started, finished, attempts, timeout, error, exit_code, "
    "cancel_requested";

JobRecord read_row(const Statement& s, bool documents) {
  JobRecord r;
  r.id = s.text(0);
  r.seq = s.integer(1);
  r.state = job_state_from_name(s.text(2)).value_or(JobState::Failed);
  r.device = s.text(3);
  r.source = s.text(4);
  r.submitted = s.real(5);
  r.started = s.real(6);
  r.finished = s.real(7);
  r.attempts = static_cast<int>(s.integer(8));
  r.timeout = s.real(9);
  r.error = s.text(10);
  r.exit_code = static_cast<int>(s.integer(11));
  r.cancel_requested = s.integer(12) != 0;
  if (documents) {
    r.job = s.text(13);
    r.manifest = s.text(14);
  }
  return r;
}

std::string new_id() {
  static std::mutex m;
  static std::mt19937_64 g{std::random_device{}()};
  std::lock_guard<std::mutex> lock(m);
  char buf[32];
  std::snprintf(buf, sizeof buf, "j%016llx", static_cast<unsigned long long>(g()));
  return buf;
}

}  // namespace

JobStore::JobStore(const std::string& path) : path_(path) {
  if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX,
                      nullptr) != SQLITE_OK) {
    const std::string why = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    db_ = nullptr;
    throw Error("cannot open the job database '" + path + "': " + why);
  }
  sqlite3_busy_timeout(db_, 5000);
  exec("PRAGMA journal_mode=WAL");
  exec("PRAGMA synchronous=NORMAL");
  exec(
      "CREATE TABLE IF NOT EXISTS jobs("
      " seq INTEGER PRIMARY KEY AUTOINCREMENT,"
      " id TEXT NOT NULL UNIQUE,"
      " state TEXT NOT NULL,"
      " device TEXT NOT NULL,"
      " source TEXT NOT NULL,"
      " submitted REAL NOT NULL,"
      " started REAL NOT NULL DEFAULT 0,"
      " finished REAL NOT NULL DEFAULT 0,"
      " attempts INTEGER NOT NULL DEFAULT 0,"
      " timeout REAL NOT NULL DEFAULT 0,"
      " error TEXT NOT NULL DEFAULT '',"
      " exit_code INTEGER NOT NULL DEFAULT 0,"
      " job TEXT NOT NULL,"
      " manifest TEXT NOT NULL DEFAULT '')");
  exec("CREATE INDEX IF NOT EXISTS jobs_state ON jobs(state)");
  // Added after version 0.2.0's first schema: a database written before it gets the column.
  bool has_cancel = false;
  {
    Statement info(db_, path_, "PRAGMA table_info(jobs)");
    while (info.step()) has_cancel = has_cancel || info.text(1) == "cancel_requested";
  }
  if (!has_cancel) exec("ALTER TABLE jobs ADD COLUMN cancel_requested INTEGER NOT NULL DEFAULT 0");
}

JobStore::~JobStore() { sqlite3_close(db_); }

void JobStore::exec(const char* sql) {
  char* err = nullptr;
  if (sqlite3_exec(db_, sql, nullptr, nullptr, &err) != SQLITE_OK) {
    const std::string why = err ? err : sqlite3_errmsg(db_);
    sqlite3_free(err);
    throw Error("job database '" + path_ + "': " + why);
  }
}

void JobStore::insert(JobRecord& r) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (int attempt = 0;; ++attempt) {
    r.id = new_id();
    try {
      Statement s(db_, path_,
                  "INSERT INTO jobs(id, state, device, source, submitted, timeout, job) VALUES(?, ?, ?, ?, ?, ?, ?)");
      s.bind(1, r.id).bind(2, std::string(job_state_name(r.state))).bind(3, r.device).bind(4, r.source);
      s.bind(5, r.submitted).bind(6, r.timeout).bind(7, r.job);
      s.step();
      break;
    } catch (const Error&) {
      if (attempt >= 3 || sqlite3_extended_errcode(db_) != SQLITE_CONSTRAINT_UNIQUE) throw;  // an id drawn twice
    }
  }
  r.seq = sqlite3_last_insert_rowid(db_);
}

void JobStore::mark_running(const std::string& id, double started, int attempts) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement s(db_, path_, "UPDATE jobs SET state = 'running', started = ?, attempts = ? WHERE id = ?");
  s.bind(1, started).bind(2, attempts).bind(3, id);
  s.step();
}

void JobStore::finish(const std::string& id, JobState state, double finished, const std::string& error, int exit_code,
                      const std::string& manifest) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement s(db_, path_,
              "UPDATE jobs SET state = ?, finished = ?, error = ?, exit_code = ?, manifest = ? WHERE id = ?");
  s.bind(1, std::string(job_state_name(state))).bind(2, finished).bind(3, error).bind(4, exit_code);
  s.bind(5, manifest).bind(6, id);
  s.step();
}

void JobStore::request_cancel(const std::string& id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement s(db_, path_, "UPDATE jobs SET cancel_requested = 1 WHERE id = ? AND state = 'running'");
  s.bind(1, id);
  s.step();
}

bool JobStore::requeue(const std::string& id, double now) {
  std::lock_guard<std::mutex> lock(mutex_);
  {
    Statement s(db_, path_, "UPDATE jobs SET state = 'queued', started = 0 WHERE id = ? AND cancel_requested = 0");
    s.bind(1, id);
    s.step();
  }
  if (sqlite3_changes(db_) > 0) return true;
  const std::string why = "cancelled (DELETE /v1/jobs/" + id +
                          ") while running; the server stopped before the job did, and does not run it again";
  Statement s(db_, path_,
              "UPDATE jobs SET state = 'cancelled', finished = ?, error = ?, exit_code = 1 WHERE id = ? AND "
              "cancel_requested = 1");
  s.bind(1, now).bind(2, why).bind(3, id);
  s.step();
  return false;
}

bool JobStore::remove(const std::string& id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement s(db_, path_, "DELETE FROM jobs WHERE id = ?");
  s.bind(1, id);
  s.step();
  return sqlite3_changes(db_) > 0;
}

std::optional<JobRecord> JobStore::get(const std::string& id, bool with_documents) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::string sql =
      std::string("SELECT ") + kColumns + (with_documents ? ", job, manifest" : "") + " FROM jobs WHERE id = ?";
  Statement s(db_, path_, sql.c_str());
  s.bind(1, id);
  if (!s.step()) return std::nullopt;
  return read_row(s, with_documents);
}

std::vector<JobRecord> JobStore::list(std::optional<JobState> state, int limit) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::string sql = std::string("SELECT ") + kColumns + " FROM jobs" + (state ? " WHERE state = ?" : "") +
                          " ORDER BY seq DESC LIMIT ?";
  Statement s(db_, path_, sql.c_str());
  int i = 1;
  if (state) s.bind(i++, std::string(job_state_name(*state)));
  s.bind(i, limit);
  std::vector<JobRecord> out;
  while (s.step()) out.push_back(read_row(s, false));
  return out;
}

std::map<std::string, std::int64_t> JobStore::count_by_state() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::map<std::string, std::int64_t> out;
  for (JobState st : {JobState::Queued, JobState::Running, JobState::Done, JobState::Failed, JobState::Cancelled})
    out[job_state_name(st)] = 0;
  Statement s(db_, path_, "SELECT state, COUNT(*) FROM jobs GROUP BY state");
  while (s.step()) out[s.text(0)] = s.integer(1);
  return out;
}

std::vector<JobRecord> JobStore::recover(int max_attempts, double now) {
  std::vector<JobRecord> failed;
  for (const JobRecord& r : list(JobState::Running, 1 << 30)) {
    if (r.cancel_requested || r.attempts < max_attempts) {
      (void)requeue(r.id, now);  // cancelled instead when its cancel was recorded before the stop
    } else {
      const std::string why = "the server stopped while running it " + std::to_string(r.attempts) +
                              " times (a crash or kill); not started again";
      finish(r.id, JobState::Failed, now, why, 1, "");
      failed.push_back(r);
    }
  }
  return failed;
}

std::vector<JobRecord> JobStore::queued() {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::string sql = std::string("SELECT ") + kColumns + " FROM jobs WHERE state = 'queued' ORDER BY seq";
  Statement s(db_, path_, sql.c_str());
  std::vector<JobRecord> out;
  while (s.step()) out.push_back(read_row(s, false));
  return out;
}

std::string JobStore::integrity_check() {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement s(db_, path_, "PRAGMA integrity_check");
  std::string out;
  while (s.step()) out += (out.empty() ? "" : "; ") + s.text(0);
  return out;
}

}  // namespace brdfbake::server
