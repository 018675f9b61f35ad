#include "server/server.hpp"

#include <fcntl.h>
#include <httplib.h>
#include <netinet/in.h>
#include <sys/file.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <list>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <sstream>

#include "brdfbake/error_figures.hpp"
#include "brdfbake/job.hpp"
#include "brdfbake/plan.hpp"
#include "brdfbake/runner.hpp"
#include "brdfbake/scene.hpp"
#include "brdfbake/version.hpp"
#include "io/json_input.hpp"
#include "io/special_files.hpp"
#include "server/confine.hpp"
#include "server/connections.hpp"
#include "server/job_files.hpp"
#include "server/job_store.hpp"
#include "server/metrics.hpp"
#include "server/reply.hpp"
#include "server/scheduler.hpp"
#include "server/site_policy.hpp"
#include "server/web_routes.hpp"

namespace brdfbake::server {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

bool is_loopback(const std::string& host) {
  if (host == "localhost" || host == "::1" || host == "[::1]") return true;
  if (host.rfind("127.", 0) != 0) return false;
  int parts = 0;
  for (size_t i = 0, start = 0; i <= host.size(); ++i)
    if (i == host.size() || host[i] == '.') {
      const std::string p = host.substr(start, i - start);
      if (p.empty() || p.size() > 3 || p.find_first_not_of("0123456789") != std::string::npos || std::stoi(p) > 255)
        return false;
      ++parts;
      start = i + 1;
    }
  return parts == 4;
}

namespace {

double ms_between(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

std::string human_bytes(double b) {
  char buf[48];
  if (b >= double(1ull << 30))
    std::snprintf(buf, sizeof buf, "%.1f GiB", b / double(1ull << 30));
  else
    std::snprintf(buf, sizeof buf, "%.0f MiB", std::ceil(b / double(1ull << 20)));
  return buf;
}

// The Content-Type of an output file, from its extension.
std::string content_type(const std::string& name) {
  std::string ext = fs::path(name).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".json") return "application/json";
  if (ext == ".csv") return "text/csv; charset=utf-8";
  if (ext == ".h") return "text/x-c; charset=utf-8";
  if (ext == ".png") return "image/png";
  if (ext == ".exr") return "image/x-exr";
  if (ext == ".hdr") return "image/vnd.radiance";
  if (ext == ".ktx2") return "image/ktx2";
  if (ext == ".ktx") return "image/ktx";
  if (ext == ".dds") return "image/vnd-ms.dds";
  return "application/octet-stream";
}

// A failure of the server's storage (a full disk or quota, a file size limit, SQLite's "full"), as
// the system's or the library's words say it: the server answers 507, not 500 or 400.
bool storage_full(const std::string& message) {
  for (int e : {ENOSPC, EDQUOT, EFBIG})
    if (message.find(std::strerror(e)) != std::string::npos) return true;
  return message.find("database or disk is full") != std::string::npos;
}

// A header value: printable ASCII, one line, at most 300 characters.
std::string header_text(const std::string& s) {
  std::string out;
  for (char c : s)
    if (c >= 0x20 && c < 0x7f) out += c;
  return out.substr(0, 300);
}

// What a client calls its job in messages (?source=job.json; `run --server` sends the file's path as
// the user typed it, so that messages read as a local run's): printable characters, at most 200.
// Only a label: the server opens nothing by it.
std::string source_name(const httplib::Request& req, const std::string& fallback) {
  if (!req.has_param("source")) return fallback;
  std::string out;
  for (char c : req.get_param_value("source"))
    if (c >= 0x20 && c < 0x7f) out += c;
  out = out.substr(0, 200);
  return out.empty() ? fallback : out;
}

double number_param(const httplib::Request& req, const std::string& name, double fallback, double lo, double hi) {
  if (!req.has_param(name.c_str())) return fallback;
  const std::string text = req.get_param_value(name.c_str());
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi) {
    char range[96];
    std::snprintf(range, sizeof range, "%g..%g", lo, hi);
    throw Error("?" + name + ": must be a number in " + range + " (got '" + text.substr(0, 40) + "')");
  }
  return v;
}

std::uint64_t resident_bytes() {
  std::ifstream in("/proc/self/statm");
  std::uint64_t size = 0, resident = 0;
  in >> size >> resident;
  return resident * static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE));
}

// What POST /v1/tables sends back, kept by the result cache.
struct TableReply {
  std::string bytes, content_type, filename, summary;
  std::string error_name, error_value;  // the figure's name (error_figures.hpp) and its text, as the file records it
  std::vector<std::string> warnings;
  double seconds = 0;
  std::string timing;  // the device task's part of Server-Timing
};

// The fast path's results by request, least recently used dropped first.
class ResultCache {
 public:
  explicit ResultCache(std::uint64_t capacity) : capacity_(capacity) {}
  std::shared_ptr<const TableReply> get(const std::string& key) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = index_.find(key);
    if (it == index_.end()) return nullptr;
    order_.splice(order_.begin(), order_, it->second);
    return it->second->second;
  }
  void put(const std::string& key, std::shared_ptr<const TableReply> r) {
    if (r->bytes.size() > capacity_ / 4) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (index_.count(key)) return;
    order_.emplace_front(key, r);
    index_[key] = order_.begin();
    bytes_ += r->bytes.size();
    while (bytes_ > capacity_ && !order_.empty()) {
      bytes_ -= order_.back().second->bytes.size();
      index_.erase(order_.back().first);
      order_.pop_back();
    }
  }

 private:
  using Entry = std::pair<std::string, std::shared_ptr<const TableReply>>;
  std::uint64_t capacity_, bytes_ = 0;
  std::mutex mutex_;
  std::list<Entry> order_;
  std::map<std::string, std::list<Entry>::iterator> index_;
};

}  // namespace

struct Server::Impl {
  ServerOptions opt;
  std::string token;
  SitePolicy site;
  int lock_fd = -1;
  std::unique_ptr<Roots> roots;
  std::unique_ptr<JobStore> store;
  Metrics metrics;
  std::unique_ptr<Scheduler> scheduler;
  std::unique_ptr<ResultCache> cache;
  GuardedServer http;
  int listen_fd = -1;
  int port = 0;
  std::vector<std::string> notes;
  std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();
  std::atomic<bool> stopping{false};
  std::mutex stop_mutex;
  bool stopped = false, stop_result = true;

  fs::path jobs_dir() const { return roots->data_dir() / "jobs"; }
  fs::path tmp_dir() const { return roots->data_dir() / "tmp"; }

  void open(ServerOptions options);
  void recover();
  void routes();
  bool authorized(const httplib::Request& req) const;

  // Request handling.
  void submit_document(json doc, const std::string& origin, const httplib::Request& req, httplib::Response& res);
  void check_memory(const Job& job, const std::string& origin);
  json job_json(const JobRecord& r, bool full);
  json job_files(const std::string& id, const json& manifest) const;
  void get_job(const httplib::Request& req, httplib::Response& res);
  void delete_job(const httplib::Request& req, httplib::Response& res);
  void get_file(const httplib::Request& req, httplib::Response& res);
  void post_bake(const httplib::Request& req, httplib::Response& res);
  void post_table(const httplib::Request& req, httplib::Response& res);
  std::string metrics_text();
  // An error reply; the message without the server's own paths (Roots::public_text).
  void fail(httplib::Response& res, int status, const std::string& message) const {
    reply_error(res, status, roots ? roots->public_text(message) : message);
  }
};

void Server::Impl::open(ServerOptions options) {
  opt = std::move(options);
  if (opt.data_dir.empty()) throw Error("--data: the data directory is required");
  if (opt.max_queue < 1) throw Error("--max-queue: must be at least 1");
  if (opt.threads < 2) throw Error("--threads: must be at least 2");
  if (opt.max_connections < 1) throw Error("--max-connections: must be at least 1");
  if (opt.max_client_connections < 1) throw Error("--max-client-connections: must be at least 1");
  // Every connection is a file: the process may need more than the usual soft limit of 1024.
  {
    const rlim_t want = static_cast<rlim_t>(opt.max_connections) + 64 + 256;  // the reserve, SQLite, files, OpenCL
    rlimit files{};
    if (::getrlimit(RLIMIT_NOFILE, &files) == 0 && files.rlim_cur < want) {
      files.rlim_cur = std::min(want, files.rlim_max);
      (void)::setrlimit(RLIMIT_NOFILE, &files);
      (void)::getrlimit(RLIMIT_NOFILE, &files);
      if (files.rlim_cur < want) {
        const int fit = std::max(1, static_cast<int>(files.rlim_cur) - 64 - 256);
        notes.push_back("--max-connections " + std::to_string(opt.max_connections) + " lowered to " +
                        std::to_string(fit) + ": the process may open " + std::to_string(files.rlim_cur) +
                        " files (ulimit -n)");
        opt.max_connections = fit;
        opt.max_client_connections = std::min(opt.max_client_connections, fit);
      }
    }
  }
  if (!opt.token_file.empty()) {
    token = io::read_token_file(opt.token_file, "--token-file");  // bounded, printable (io/special_files.hpp)
    if (token.size() < 16) throw Error("--token-file: the token (its first line) must have at least 16 characters");
  } else if (!is_loopback(opt.host)) {
    throw Error("--listen: refusing to listen on '" + opt.host +
                "', which is not a loopback address, without --token-file (anyone who reaches it could run jobs)");
  }
  std::error_code ec;
  fs::create_directories(opt.data_dir, ec);
  if (ec) throw Error("--data: cannot create '" + opt.data_dir + "': " + ec.message());
  roots = std::make_unique<Roots>(opt.input_root, opt.data_dir);
  // One server a data directory: the lock lasts as long as the process.
  const std::string lock_path = (roots->data_dir() / "server.lock").string();
  lock_fd = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd < 0 || ::flock(lock_fd, LOCK_EX | LOCK_NB) != 0)
    throw Error("--data: '" + opt.data_dir + "' is in use by another brdfbake serve (" + lock_path + " is locked)");
  fs::create_directories(jobs_dir(), ec);
  fs::create_directories(tmp_dir(), ec);
  if (ec) throw Error("--data: cannot create folders in '" + opt.data_dir + "': " + ec.message());
  if (opt.max_memory == 0)
    opt.max_memory =
        static_cast<std::uint64_t>(::sysconf(_SC_PHYS_PAGES)) * static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE)) / 2;
  store = std::make_unique<JobStore>((roots->data_dir() / "jobs.db").string());
  if (opt.table_cache_bytes > 0) cache = std::make_unique<ResultCache>(opt.table_cache_bytes);
  SchedulerOptions so;
  so.devices = opt.devices;
  so.jobs_dir = jobs_dir();
  so.max_queue = opt.max_queue;
  so.warm_up = opt.warm_up;
  so.public_text = [this](const std::string& m) { return roots->public_text(m); };
  scheduler = std::make_unique<Scheduler>(*store, metrics, so);
  recover();
  routes();
}

void Server::Impl::recover() {
  std::error_code ec;
  // Temporary files of requests and staging folders of jobs a killed server left behind.
  for (const auto& e : fs::directory_iterator(tmp_dir(), ec)) fs::remove_all(e.path(), ec);
  int stale = 0;
  for (const auto& e : fs::directory_iterator(jobs_dir(), ec))
    if (e.path().filename().string().rfind(".", 0) == 0) {
      fs::remove_all(e.path(), ec);
      ++stale;
    }
  if (stale) notes.push_back("removed " + std::to_string(stale) + " unfinished staging folder(s)");
  const auto running_before = store->list(JobState::Running, 1 << 30);
  const auto failed = store->recover(2, now_seconds());
  for (const auto& r : failed) notes.push_back("job " + r.id + " failed: the server stopped while running it twice");
  int cancelled = 0;
  for (const auto& r : running_before) cancelled += r.cancel_requested ? 1 : 0;
  if (cancelled)
    notes.push_back("cancelled " + std::to_string(cancelled) +
                    " job(s) that were asked to stop (DELETE) before the server stopped; not run again");
  int requeued = static_cast<int>(running_before.size() - failed.size()) - cancelled;
  if (requeued)
    notes.push_back("re-queued " + std::to_string(requeued) + " job(s) that were running when the server stopped");
  const auto queued = store->queued();
  for (const auto& r : queued) scheduler->resume(r);
  if (!queued.empty()) notes.push_back(std::to_string(queued.size()) + " job(s) queued");
}

bool Server::Impl::authorized(const httplib::Request& req) const {
  if (token.empty()) return true;
  const std::string want = "Bearer " + token;
  const std::string got = req.get_header_value("Authorization");
  // Compared in constant time for the token's length.
  unsigned diff = got.size() == want.size() ? 0u : 1u;
  for (size_t i = 0; i < want.size(); ++i) diff |= static_cast<unsigned>(want[i] ^ (i < got.size() ? got[i] : 0));
  return diff == 0;
}

void Server::Impl::check_memory(const Job& job, const std::string& origin) {
  // Environments are held for the whole job: a builtin's float RGBA pixels, a file's bytes at least.
  std::uint64_t env = 0;
  std::set<std::string> seen;
  for (const auto& t : job.tables) {
    if (!table_kind_uses_environment(t.kind)) continue;
    const std::string spec = t.environment.empty() ? job.environment : t.environment;
    if (!seen.insert(spec).second) continue;
    if (spec.rfind("builtin:", 0) == 0) {
      env += 1024ull * 512ull * 16ull;
    } else {
      std::stringstream parts(spec);
      std::string p;
      std::error_code ec;
      while (std::getline(parts, p, ',')) env += static_cast<std::uint64_t>(fs::file_size(p, ec));
    }
  }
  for (size_t i = 0; i < job.tables.size(); ++i) {
    const TableRequest& t = job.tables[i];
    const std::uint64_t need = estimate_table_bytes(t);
    const std::string where = origin + ": tables[" + std::to_string(i) + "] (" + table_kind_name(t.kind) + ")";
    if (need + env > opt.max_memory)
      throw Error(where + ": needs about " + human_bytes(double(need + env)) +
                  ", more than the server allows a bake (" + human_bytes(double(opt.max_memory)) +
                  ", --max-memory); nothing was started");
    const std::string key = scheduler->device_key(t.device.empty() ? job.device : t.device);
    const std::uint64_t device = scheduler->device_memory(key);
    if (device > 0 && need > device)
      throw Error(where + ": needs about " + human_bytes(double(need)) + ", more than device " + key + " has (" +
                  human_bytes(double(device)) + "); nothing was started");
  }
}

void Server::Impl::submit_document(json doc, const std::string& origin, const httplib::Request& req,
                                   httplib::Response& res) {
  JobRecord r;
  Job job;
  double units = 0;
  std::string choice;
  try {
    roots->confine_job_document(doc, origin);
    job = parse_job(doc.dump(), origin);
    // Devices: the job's and each table's must be served here.
    try {
      r.device = scheduler->device_key(job.device);
    } catch (const Error& e) {
      throw Error(origin + ": device: " + e.what());
    }
    // The job runs on its first table's device (and holds the others its tables name).
    for (size_t i = 0; i < job.tables.size(); ++i) {
      const std::string& sel = job.tables[i].device;
      if (sel.empty()) continue;
      try {
        const std::string key = scheduler->device_key(sel);
        if (i == 0) r.device = key;
      } catch (const Error& e) {
        throw Error(origin + ": tables[" + std::to_string(i) + "].device: " + e.what());
      }
    }
    for (size_t i = 0; i < job.tables.size(); ++i) {
      std::string why;
      if (!table_kind_available(job.tables[i].kind, &why))
        throw NotAvailableError(origin + ": tables[" + std::to_string(i) + "] (" + table_kind_name(job.tables[i].kind) +
                                "): not available in this build: " + why);
    }
    check_memory(job, origin);
    r.timeout = number_param(req, "timeout", opt.job_timeout, 0.01, opt.job_timeout);
    // A job that names no device, where several are served, goes to the one that finishes it first
    // (Scheduler::choose_device: backlogs and measured rates); the job then names it, so that its
    // tables bake there, and its status says why (device_choice).
    units = job_work_units(job.tables);
    const bool named = !job.device.empty() || std::any_of(job.tables.begin(), job.tables.end(),
                                                          [](const TableRequest& t) { return !t.device.empty(); });
    if (!named) {
      const std::string pick = scheduler->choose_device(units, &choice);
      if (!pick.empty()) {
        r.device = pick;
        job.device = pick;
      } else {
        choice.clear();
      }
    }
  } catch (const NotAvailableError& e) {
    fail(res, 501, e.what());
    return;
  } catch (const Error& e) {
    fail(res, 400, e.what());
    return;
  }
  // The server chooses where files go (DATA/jobs/<id>/); of the client's folder only its name is
  // kept: an engine target names its files after it, as a local run does.
  {
    std::string folder = job.output_dir;
    while (folder.size() > 1 && folder.back() == '/') folder.pop_back();
    const std::string name = fs::path(folder).filename().string();
    job.output_dir = name == "." || name == ".." || name.size() > 200 ? std::string() : name;
  }
  r.source = origin;
  r.job = job_to_json(job);
  r.submitted = now_seconds();
  try {
    scheduler->submit(r, units, choice);
  } catch (const QueueFull& e) {
    res.set_header("Retry-After", std::to_string(e.retry_after));
    fail(res, 503, e.what());
    return;
  } catch (const Error& e) {
    fail(res, storage_full(e.what()) ? 507 : 500, e.what());  // the store could not record it
    return;
  }
  json body;
  body["id"] = r.id;
  body["state"] = "queued";
  body["url"] = "/v1/jobs/" + r.id;
  body["tables"] = job.tables.size();
  body["device"] = r.device;
  if (!choice.empty()) body["device_choice"] = choice;
  res.set_header("Location", "/v1/jobs/" + r.id);
  reply_json(res, 202, body);
}

json Server::Impl::job_files(const std::string& id, const json& manifest) const {
  // Every file of the job's folder by its own path, so that a client fetches each as it is: the
  // manifest's outputs in its order (a folder output, a cube written as images, by each of its
  // files), then what else the job wrote (an engine target's files), manifest.json last.
  const fs::path dir = jobs_dir() / id;
  std::vector<std::string> out;
  std::set<std::string> listed = {"manifest.json"};
  auto files_below = [&](const fs::path& folder) {
    std::vector<std::string> found;
    std::error_code ec;
    for (fs::recursive_directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
      if (it->symlink_status(ec).type() == fs::file_type::regular)
        found.push_back(it->path().lexically_relative(dir).generic_string());
    std::sort(found.begin(), found.end());
    return found;
  };
  auto add = [&](const std::string& name) {
    if (listed.insert(name).second) out.push_back(name);
  };
  if (manifest.is_object() && manifest.contains("files") && manifest["files"].is_array())
    for (const auto& f : manifest["files"]) {
      const std::string path = f.is_object() ? f.value("path", "") : "";
      if (path.empty()) continue;
      std::error_code ec;
      if (fs::symlink_status(dir / path, ec).type() == fs::file_type::directory) {
        for (const auto& name : files_below(dir / path)) add(name);
      } else {
        add(path);
      }
    }
  for (const auto& name : files_below(dir)) add(name);
  out.push_back("manifest.json");
  return json(out);
}

json Server::Impl::job_json(const JobRecord& r, bool full) {
  json o;
  o["id"] = r.id;
  o["state"] = job_state_name(r.state);
  o["source"] = r.source;
  o["device"] = r.device;
  if (const std::string c = scheduler->device_choice(r.id); !c.empty()) o["device_choice"] = c;
  o["submitted"] = r.submitted;
  o["started"] = r.started > 0 ? json(r.started) : json(nullptr);
  o["finished"] = r.finished > 0 ? json(r.finished) : json(nullptr);
  if (r.state == JobState::Running && r.started > 0)
    o["seconds"] = now_seconds() - r.started;
  else if (r.finished > 0 && r.started > 0)
    o["seconds"] = r.finished - r.started;
  o["attempts"] = r.attempts;
  if (!r.error.empty()) o["error"] = r.error;
  if (job_finished(r.state)) o["exit_code"] = r.exit_code;
  if (!full) return o;
  if (r.state == JobState::Running) {
    if (auto p = scheduler->progress(r.id)) {
      json pr;
      pr["bake"] = p->bake;
      pr["bakes"] = p->bakes;
      pr["what"] = p->what;
      pr["fraction"] = p->fraction;
      pr["overall"] = p->bakes > 0 ? (p->bake + p->fraction) / p->bakes : 0.0;
      o["progress"] = pr;
    }
  }
  if (r.state == JobState::Done && !r.manifest.empty()) {
    const json m = json::parse(r.manifest, nullptr, false);
    o["files"] = job_files(r.id, m);
    // What was changed on the way to the files (clamp_f16, a sanitized environment), naming them
    // inside the job's folder as the file list does.
    const std::string folder = (jobs_dir() / r.id).string() + "/";
    json warnings = json::array();
    if (m.is_object() && m.contains("warnings") && m["warnings"].is_array())
      for (const auto& w : m["warnings"]) {
        std::string text = w.is_string() ? w.get<std::string>() : w.dump();
        for (size_t at = text.find(folder); at != std::string::npos; at = text.find(folder, at))
          text.erase(at, folder.size());
        warnings.push_back(text);
      }
    o["warnings"] = warnings;
    // Each file's error figures under their names (docs/CONVENTIONS.md, "Error figures"), as the
    // command line prints them and the files record them (error_bound_text: rounded up to three
    // digits), by its path: a table's `error_name` and its figure (error_bound in an older
    // manifest), an engine file's error_rms_rel and error_max_rel (engine.file_entries).
    // `error_bounds` is the deprecated alias of the first release (path: the text alone).
    json figures = json::object(), bounds = json::object();
    if (m.is_object() && m.contains("files") && m["files"].is_array())
      for (const auto& f : m["files"]) {
        if (!f.is_object() || !f.contains("path") || !f["path"].is_string()) continue;
        const std::string figure = f.contains("error_name") && f["error_name"].is_string()
                                       ? f["error_name"].get<std::string>()
                                       : std::string(kLegacyErrorBoundName);
        json e;
        e["error_name"] = figure;
        e[figure] = nullptr;
        if (f.contains(figure) && f[figure].is_number()) {
          e[figure] = error_bound_text(f[figure].get<double>());
          bounds[f["path"].get<std::string>()] = e[figure];
        }
        figures[f["path"].get<std::string>()] = e;
      }
    if (m.is_object() && m.contains("engine") && m["engine"].is_object() && m["engine"].contains("file_entries") &&
        m["engine"]["file_entries"].is_array())
      for (const auto& f : m["engine"]["file_entries"]) {
        if (!f.is_object() || !f.contains("path") || !f["path"].is_string()) continue;
        json e;
        e["error_name"] = kEngineErrorName;
        for (const char* name : {"error_rms_rel", "error_max_rel"})
          e[name] = f.contains(name) && f[name].is_number() ? json(error_bound_text(f[name].get<double>())) : json();
        figures[f["path"].get<std::string>()] = e;
      }
    o["error_figures"] = figures;
    o["error_bounds"] = bounds;  // deprecated (docs/SERVICE.md): error_figures
    o["manifest"] = m;
  }
  return o;
}

void Server::Impl::get_job(const httplib::Request& req, httplib::Response& res) {
  const std::string id = req.matches[1];
  double wait = 0;
  try {
    wait = number_param(req, "wait", 0, 0, 60);
  } catch (const Error& e) {
    return fail(res, 400, e.what());
  }
  if (wait > 0) scheduler->wait_finished(id, wait);
  const auto r = store->get(id);
  if (!r) return fail(res, 404, "no job '" + id.substr(0, 40) + "'");
  reply_json(res, 200, job_json(*r, true));
}

void Server::Impl::delete_job(const httplib::Request& req, httplib::Response& res) {
  const std::string id = req.matches[1];
  const bool purge =
      req.has_param("purge") && req.get_param_value("purge") != "0" && req.get_param_value("purge") != "false";
  switch (scheduler->cancel(id)) {
    case CancelResult::Unknown:
      return fail(res, 404, "no job '" + id.substr(0, 40) + "'");
    case CancelResult::Cancelled: {
      json o;
      o["id"] = id;
      o["state"] = "cancelled";
      return reply_json(res, 200, o);
    }
    case CancelResult::Stopping: {
      json o;
      o["id"] = id;
      o["state"] = "running";
      o["cancelling"] = true;
      o["note"] = "the job stops before its next table; GET it to see it cancelled";
      return reply_json(res, 202, o);
    }
    case CancelResult::Finished:
      break;
  }
  const auto r = store->get(id, false);
  if (!r) return fail(res, 404, "no job '" + id.substr(0, 40) + "'");
  if (!purge)
    return fail(res, 409,
                "job " + id + " already finished (" + job_state_name(r->state) + "); DELETE /v1/jobs/" + id +
                    "?purge=1 removes it and its files");
  std::error_code ec;
  fs::remove_all(jobs_dir() / id, ec);
  store->remove(id);
  json o;
  o["id"] = id;
  o["purged"] = true;
  reply_json(res, 200, o);
}

void Server::Impl::get_file(const httplib::Request& req, httplib::Response& res) {
  const std::string id = req.matches[1], name = req.matches[2];
  const JobFile file = find_job_file(*store, *roots, jobs_dir(), id, name, "served");
  if (file.path.empty()) {
    std::error_code ec;
    if (file.missing && fs::symlink_status((jobs_dir() / id / fs::path(name)).lexically_normal(), ec).type() ==
                            fs::file_type::directory)
      return fail(res, 404,
                  "job " + id + ": '" + name.substr(0, 80) +
                      "' is a folder; its files are listed one by one in the job's \"files\" (GET /v1/jobs/" + id +
                      ")");
    return fail(res, file.status, file.error);
  }
  const std::string& path = file.path;
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
  struct stat st {};
  if (fd < 0 || ::fstat(fd, &st) != 0) {
    if (fd >= 0) ::close(fd);
    return fail(res, 404, "job " + id + " has no file '" + name.substr(0, 80) + "'");
  }
  const auto size = static_cast<size_t>(st.st_size);
  res.set_header("Content-Disposition", content_disposition(fs::path(name).filename().string()));
  res.set_header("X-Content-Type-Options", "nosniff");
  res.set_content_provider(
      size, content_type(name),
      [fd](size_t offset, size_t length, httplib::DataSink& sink) {
        char buf[1 << 16];
        const size_t n = std::min(length, sizeof buf);
        const ssize_t got = ::pread(fd, buf, n, static_cast<off_t>(offset));
        if (got <= 0) return false;  // the connection is closed: no short file is ever sent as whole
        return sink.write(buf, static_cast<size_t>(got));
      },
      [fd](bool) { ::close(fd); });
}

void Server::Impl::post_bake(const httplib::Request& req, httplib::Response& res) {
  const std::string origin = source_name(req, "bake");
  json doc;
  Plan plan;
  try {
    plan = bake_plan(req.body, origin, *roots);
    doc = json::parse(job_to_json(plan.job));
  } catch (const Error& e) {
    return fail(res, 400, e.what());
  }
  submit_document(std::move(doc), origin, req, res);
}

void Server::Impl::post_table(const httplib::Request& req, httplib::Response& res) {
  const auto received = std::chrono::steady_clock::now();
  const std::string origin = "table";
  // Messages name the fields as "table.size", not as the job a table is wrapped in.
  auto local = [](std::string m) {
    const std::string wrapped = "table: tables[0]";
    for (size_t at = m.find(wrapped); at != std::string::npos; at = m.find(wrapped, at))
      m.replace(at, wrapped.size(), "table");
    return m;
  };
  TableRequest t;
  std::string key, environment;
  bool sanitize = false;
  try {
    const json body = io::parse_json(req.body, origin);
    if (!body.is_object()) throw Error(origin + ": the request is one table as a JSON object (a job's tables[] entry)");
    json doc;
    doc["brdfbake_job"] = 1;
    doc["tables"] = json::array({body});
    roots->confine_job_document(doc, origin);
    sanitize = req.has_param("sanitize") && req.get_param_value("sanitize") != "0" &&
               req.get_param_value("sanitize") != "false";
    Job job = parse_job(doc.dump(), origin);
    if (job.tables.size() != 1) throw Error(origin + ": one table is expected");
    t = job.tables[0];
    for (const auto& d : table_schema(t.kind))
      if (d.type == ParamType::Path && d.output_only && t.find(d.name))
        throw Error(origin + "." + d.name + ": a second output file is for jobs (POST /v1/jobs), not for one table");
    if (fs::path(t.output).extension().empty())
      throw Error(origin + ".output: '" + t.output +
                  "' is a folder output; POST /v1/tables returns one file (submit a job)");
    try {
      key = scheduler->device_key(t.device);
    } catch (const Error& e) {
      throw Error(origin + ".device: " + e.what());
    }
    std::string why;
    if (!table_kind_available(t.kind, &why)) throw Error(origin + ": not available in this build: " + why);
    check_memory(job, origin);
    const std::uint64_t need = estimate_table_bytes(t);
    if (need > opt.table_max_bytes)
      throw Error(origin + ": needs about " + human_bytes(double(need)) + ", more than POST /v1/tables bakes (" +
                  human_bytes(double(opt.table_max_bytes)) + "); submit it as a job (POST /v1/jobs)");
    environment = table_kind_uses_environment(t.kind) ? (t.environment.empty() ? job.environment : t.environment) : "";
  } catch (const Error& e) {
    return fail(res, 400, local(e.what()));
  }
  // The files the table reads are part of its key: their size and modification time.
  std::string inputs_key;
  {
    std::vector<std::string> files;
    for (const auto& d : table_schema(t.kind))
      if (d.type == ParamType::Path && !d.output_only && t.find(d.name)) files.push_back(t.text(d.name));
    if (!environment.empty() && environment.rfind("builtin:", 0) != 0) {
      std::stringstream parts(environment);
      for (std::string p; std::getline(parts, p, ',');) files.push_back(p);
    }
    for (const auto& f : files) {
      struct stat st {};
      if (::stat(f.c_str(), &st) == 0)
        inputs_key += "|" + f + "@" + std::to_string(st.st_size) + ":" + std::to_string(st.st_mtim.tv_sec) + "." +
                      std::to_string(st.st_mtim.tv_nsec);
    }
  }
  // How the file is written is part of the key too: every output parameter (symbol, png_range,
  // clamp_f16: a request without clamp_f16 must not get a clamped file).
  std::string outputs_key;
  for (const auto& d : table_schema(t.kind))
    if (d.output_only && t.find(d.name)) outputs_key += "|" + d.name + "=" + param_value_text(*t.find(d.name));
  const std::string cache_key = table_bake_key(t) + inputs_key + "|format=" + t.format + "|pixel=" + t.pixel +
                                "|output=" + fs::path(t.output).filename().string() + outputs_key +
                                "|sanitize=" + (sanitize ? "1" : "0");
  const auto checked = std::chrono::steady_clock::now();
  auto send = [&](const TableReply& r, bool hit) {
    metrics.count_table(hit);
    res.status = 200;
    res.set_header("Content-Disposition", content_disposition(r.filename));
    res.set_header("X-Brdfbake-Summary", header_text(r.summary));
    // The file's error figure under its name (docs/CONVENTIONS.md, "Error figures"); the value only
    // where one was measured. X-Brdfbake-Error-Bound: the deprecated alias of the value.
    res.set_header("X-Brdfbake-Error-Name", r.error_name);
    if (!r.error_value.empty()) {
      res.set_header("X-Brdfbake-Error-Value", r.error_value);
      res.set_header("X-Brdfbake-Error-Bound", r.error_value);
    }
    for (const auto& w : r.warnings) res.set_header("X-Brdfbake-Warning", header_text(w));
    res.set_header("X-Brdfbake-Cache", hit ? "hit" : "miss");
    // Where the time went (docs/SERVICE.md): checking the request, then on a miss the device task's
    // steps, and the whole handler; what a client measures beyond it is HTTP.
    char total[96];
    std::snprintf(total, sizeof total, "request;dur=%.3f", ms_between(received, checked));
    std::string timing = total;
    if (!hit && !r.timing.empty()) timing += ", " + r.timing;
    std::snprintf(total, sizeof total, ", handler;dur=%.3f", ms_between(received, std::chrono::steady_clock::now()));
    res.set_header("Server-Timing", timing + total);
    res.set_header("X-Content-Type-Options", "nosniff");
    res.set_content(r.bytes, r.content_type);
  };
  if (cache)
    if (auto hit = cache->get(cache_key)) return send(*hit, true);

  auto reply = std::make_shared<TableReply>();
  auto abandoned = std::make_shared<std::atomic<bool>>(false);
  std::future<void> done;
  try {
    const auto queued = std::chrono::steady_clock::now();
    const std::string label =
        table_kind_name(t.kind) +
        (t.find(table_size_param(t.kind)) ? " " + param_value_text(*t.find(table_size_param(t.kind))) : std::string());
    done = scheduler->run_now(key, label, [this, t, environment, sanitize, reply, abandoned, queued](Backend& backend) {
      if (*abandoned) return;  // the client stopped waiting before the device was free
      const auto began = std::chrono::steady_clock::now();
      TableRequest request = t;
      request.environment = environment;
      TableRunOptions o;
      o.delivery = TableDelivery::Bytes;
      o.backend = &backend;
      o.load.sanitize = sanitize;
      o.scratch_dir = tmp_dir().string();
      o.stop_requested = [abandoned] { return abandoned->load(); };  // a 504 stops the bake at its next step
      TableRun run = run_table(request, o);
      metrics.observe_bake(table_kind_name(t.kind), run.result.seconds);
      std::vector<DeliveredFile>& files = run.delivery.files;
      if (files.size() != 1)
        throw Error("table.output: '" + t.output + "' is written as " + std::to_string(files.size()) +
                    " files (a sidecar); POST /v1/tables returns one: submit a job, or choose another format");
      reply->bytes = std::move(files.front().bytes);
      reply->content_type = content_type(t.output);
      reply->filename = fs::path(t.output).filename().string();
      reply->summary = run.result.summary;
      reply->error_name = error_figure(t.kind).name;
      reply->error_value = run.delivery.error_bound_text;  // what the file records
      reply->warnings = run.warnings;
      reply->seconds = run.result.seconds;
      char timing[160];
      std::snprintf(timing, sizeof timing,
                    "queue;dur=%.3f, inputs;dur=%.3f, bake;dur=%.3f, device;dur=%.3f, deliver;dur=%.3f",
                    ms_between(queued, began), run.input_seconds * 1e3, run.bake_seconds * 1e3,
                    run.result.device_seconds * 1e3, run.deliver_seconds * 1e3);
      reply->timing = timing;
    });
  } catch (const QueueFull& e) {
    res.set_header("Retry-After", std::to_string(e.retry_after));
    return fail(res, 503, e.what());
  }
  if (done.wait_for(std::chrono::duration<double>(opt.table_timeout)) != std::future_status::ready) {
    *abandoned = true;
    char m[160];
    std::snprintf(m, sizeof m,
                  "table: not ready within %g s (--table-timeout); the device is busy or the table is large: "
                  "submit it as a job",
                  opt.table_timeout);
    return fail(res, 504, m);
  }
  try {
    done.get();
  } catch (const std::future_error&) {
    return fail(res, 503, "the server is shutting down");
  } catch (const RuntimeFailure& e) {
    // The server failed, not the request: its storage is full (507), or the device (500).
    return fail(res, storage_full(e.what()) ? 507 : 500, local(e.what()));
  } catch (const Error& e) {
    return fail(res, 400, local(e.what()));
  } catch (const std::exception& e) {
    return fail(res, 500, e.what());
  }
  if (cache) cache->put(cache_key, reply);
  send(*reply, false);
}

std::string Server::Impl::metrics_text() {
  std::string s;
  s += "# HELP brdfbake_jobs Jobs in the store, by state.\n# TYPE brdfbake_jobs gauge\n";
  for (const auto& [state, n] : store->count_by_state())
    s += "brdfbake_jobs{state=\"" + state + "\"} " + std::to_string(n) + "\n";
  const auto devices = scheduler->devices();
  s += "# HELP brdfbake_queue_length Jobs waiting, by device.\n# TYPE brdfbake_queue_length gauge\n";
  for (const auto& d : devices)
    s += "brdfbake_queue_length{device=\"" + prometheus_label(d.key) + "\"} " + std::to_string(d.queued) + "\n";
  s += "# HELP brdfbake_device_busy_seconds_total Seconds each device spent on jobs and tables.\n"
       "# TYPE brdfbake_device_busy_seconds_total counter\n";
  for (const auto& d : devices) {
    char v[64];
    std::snprintf(v, sizeof v, "%.6f", d.busy_seconds);
    s += "brdfbake_device_busy_seconds_total{device=\"" + prometheus_label(d.key) + "\",name=\"" +
         prometheus_label(d.name) + "\"} " + v + "\n";
  }
  s += "# HELP brdfbake_process_resident_bytes Resident memory of the server.\n"
       "# TYPE brdfbake_process_resident_bytes gauge\n";
  s += "brdfbake_process_resident_bytes " + std::to_string(resident_bytes()) + "\n";
  s += metrics.render();
  return s;
}

void Server::Impl::routes() {
  // Slow and heavy clients (docs/SERVICE.md): requests are received whole before a worker takes
  // them, within --io-timeout each; connections are capped; a reserve answers health and status.
  ConnectionLimits limits;
  limits.request_seconds = opt.io_timeout;
  limits.write_stall_seconds = opt.io_timeout;
  limits.idle_seconds = 5;
  limits.max_body = opt.max_body;
  limits.max_upload = opt.max_upload;
  limits.workers = opt.threads;
  limits.max_connections = opt.max_connections;
  limits.max_client_connections = opt.max_client_connections;
  http.set_limits(limits);
  http.set_on_refused([this](int status) { metrics.count_request(status); });
  http.set_payload_max_length(std::max(opt.max_body, opt.max_upload));  // each route's limit: connections.cpp
  http.set_tcp_nodelay(true);
  http.set_keep_alive_max_count(1000);
  http.set_keep_alive_timeout(5);
  const auto io = static_cast<time_t>(std::max(1.0, opt.io_timeout));
  http.set_read_timeout(io, 0);
  http.set_write_timeout(io, 0);
  // Keep the listening socket: Debian's library listens with a backlog of 5, which drops
  // connections when many clients connect at once; listen() again with a longer one after binding.
  http.set_socket_options([this](int sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    listen_fd = sock;
  });
  site.listen_host = opt.host;
  // A token already keeps other pages out (they cannot know it), so its Host names are the
  // operator's; without one (loopback only) every name but loopback's is refused.
  site.check_host = token.empty() || !opt.allowed_hosts.empty();
  site.allowed_hosts = opt.allowed_hosts;
  site.allowed_origins = opt.allowed_origins;
  http.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    const std::string refused = refuse_by_site(site, req.method, req.get_header_value("Host"),
                                               req.get_header_value("Origin"), req.get_header_value("Sec-Fetch-Site"));
    if (!refused.empty()) {
      fail(res, 403, refused);
      return httplib::Server::HandlerResponse::Handled;
    }
    if (authorized(req) || web_public_route(req.method, req.path)) return httplib::Server::HandlerResponse::Unhandled;
    res.set_header("WWW-Authenticate", "Bearer realm=\"brdfbake\"");
    fail(res, 401, "missing or wrong bearer token (Authorization: Bearer ...; see --token-file)");
    return httplib::Server::HandlerResponse::Handled;
  });
  http.set_error_handler([this](const httplib::Request&, httplib::Response& res) {
    if (!res.body.empty()) return;
    if (res.status == 413)
      fail(res, 413,
           "request body larger than the server accepts (" + std::to_string(opt.max_body) + " bytes, --max-body)");
    else if (res.status == 404)
      fail(res, 404,
           "no such route (see docs/SERVICE.md: /v1/jobs, /v1/tables, /v1/bake, /v1/devices, /v1/health, /metrics)");
    else if (res.status == 400)
      fail(res, 400, "malformed HTTP request");
    else
      fail(res, res.status, "HTTP error " + std::to_string(res.status));
  });
  http.set_exception_handler([this](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
    try {
      std::rethrow_exception(ep);
    } catch (const std::exception& e) {
      fail(res, 500, e.what());
    } catch (...) {
      fail(res, 500, "internal error");
    }
  });
  http.set_logger([this](const httplib::Request&, const httplib::Response& res) { metrics.count_request(res.status); });

  http.Get("/v1/health", [this](const httplib::Request&, httplib::Response& res) {
    json h;
    h["status"] = stopping ? "stopping" : "ok";
    h["version"] = kVersion;
    h["uptime_seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    h["queued"] = scheduler->queued_total();
    h["running"] = scheduler->running_total();
    h["tables_running"] = scheduler->tables_running();
    bool warm = true;
    const auto devices = scheduler->devices();
    for (const auto& d : devices) warm = warm && d.warm;
    h["devices"] = devices.size();
    h["warm"] = warm;
    reply_json(res, 200, h);
  });
  http.Get("/v1/devices", [this](const httplib::Request&, httplib::Response& res) {
    json a = json::array();
    for (const auto& d : scheduler->devices()) {
      json e;
      e["key"] = d.key;
      e["name"] = d.name;
      e["type"] = d.type;
      e["global_memory"] = d.global_memory;
      e["warm"] = d.warm;
      e["busy"] = d.busy;
      e["running"] = d.running.empty() ? json(nullptr) : json(d.running);
      e["table"] = d.table.empty() ? json(nullptr) : json(d.table);
      e["queued"] = d.queued;
      e["busy_seconds"] = d.busy_seconds;
      e["load"] = d.load;
      // the work rate the choice of a job's device reads (bytes of output a second, measured)
      e["rate"] = d.rate > 0 ? json(d.rate) : json(nullptr);
      a.push_back(e);
    }
    json o;
    o["devices"] = a;
    o["default"] = a.empty() ? json(nullptr) : a[0]["key"];
    reply_json(res, 200, o);
  });
  http.Get("/metrics", [this](const httplib::Request&, httplib::Response& res) {
    res.set_content(metrics_text(), "text/plain; version=0.0.4; charset=utf-8");
  });
  http.Post("/v1/jobs", [this](const httplib::Request& req, httplib::Response& res) {
    const std::string origin = source_name(req, "job");
    json doc;
    try {
      doc = io::parse_json(req.body, origin);
      if (!doc.is_object()) throw Error(origin + ": a job is a JSON object with a \"tables\" array");
    } catch (const Error& e) {
      return fail(res, 400, e.what());
    }
    submit_document(std::move(doc), origin, req, res);
  });
  http.Post("/v1/bake", [this](const httplib::Request& req, httplib::Response& res) { post_bake(req, res); });
  http.Post("/v1/tables", [this](const httplib::Request& req, httplib::Response& res) { post_table(req, res); });
  http.Get("/v1/jobs", [this](const httplib::Request& req, httplib::Response& res) {
    std::optional<JobState> state;
    int limit = 100;
    try {
      if (req.has_param("state")) {
        state = job_state_from_name(req.get_param_value("state"));
        if (!state) throw Error("?state: must be queued, running, done, failed or cancelled");
      }
      limit = static_cast<int>(number_param(req, "limit", 100, 1, 1000000));
    } catch (const Error& e) {
      return fail(res, 400, e.what());
    }
    json a = json::array();
    for (const auto& r : store->list(state, limit)) a.push_back(job_json(r, false));
    json o;
    o["jobs"] = a;
    reply_json(res, 200, o);
  });
  http.Get(R"(/v1/jobs/([A-Za-z0-9_-]+))",
           [this](const httplib::Request& req, httplib::Response& res) { get_job(req, res); });
  http.Delete(R"(/v1/jobs/([A-Za-z0-9_-]+))",
              [this](const httplib::Request& req, httplib::Response& res) { delete_job(req, res); });
  http.Get(R"(/v1/jobs/([A-Za-z0-9_-]+)/files/(.+))",
           [this](const httplib::Request& req, httplib::Response& res) { get_file(req, res); });
  WebContext web{store.get(), roots.get(), jobs_dir(), tmp_dir(), opt.max_memory, opt.table_timeout, {}};
  web.on_device = [this](const std::string& selector, const std::function<void(Backend&)>& work) {
    scheduler->run_now(scheduler->device_key(selector), "dry-run estimate", [&work](Backend& b) { work(b); }).get();
  };
  register_web_routes(http, web);  // GET / (web_routes.hpp)
}

Server::Server(ServerOptions options) : impl_(std::make_unique<Impl>()) {
  impl_->open(std::move(options));
  Impl& m = *impl_;
  if (m.opt.port == 0) {
    m.port = m.http.bind_to_any_port(m.opt.host);
    if (m.port <= 0) throw Error("--listen: cannot listen on " + m.opt.host + " (any port)");
  } else {
    if (!m.http.bind_to_port(m.opt.host, m.opt.port))
      throw Error("--listen: cannot listen on " + m.opt.host + ":" + std::to_string(m.opt.port) +
                  " (in use, or not an address of this machine)");
    m.port = m.opt.port;
  }
  if (m.listen_fd >= 0) ::listen(m.listen_fd, SOMAXCONN);
  if (!m.opt.url_file.empty()) {
    const std::string tmp = m.opt.url_file + ".tmp-" + std::to_string(::getpid());
    {
      std::ofstream out(tmp);
      out << url() << "\n";
      if (!out) throw Error("--url-file: cannot write '" + m.opt.url_file + "'");
    }
    fs::rename(tmp, m.opt.url_file);
  }
}

Server::~Server() {
  if (!stop()) {
    // A device worker is still inside a long bake and uses what Impl holds: leave it be (the
    // process is about to end; the job's record says running and the next start re-queues it).
    (void)impl_.release();
    return;
  }
  if (impl_->lock_fd >= 0) ::close(impl_->lock_fd);
}

std::string Server::url() const {
  const std::string& h = impl_->opt.host;
  const bool v6 = h.find(':') != std::string::npos && h.front() != '[';
  return "http://" + (v6 ? "[" + h + "]" : h) + ":" + std::to_string(impl_->port);
}

const std::vector<std::string>& Server::recovery_notes() const { return impl_->notes; }

bool Server::run() { return impl_->http.listen_after_bind(); }

bool Server::stop() {
  std::lock_guard<std::mutex> lock(impl_->stop_mutex);
  if (impl_->stopped) return impl_->stop_result;
  impl_->stopped = true;
  impl_->stopping = true;
  impl_->http.stop();
  impl_->stop_result = impl_->scheduler->shutdown(impl_->opt.shutdown_grace, 5.0);
  return impl_->stop_result;
}

}  // namespace brdfbake::server
