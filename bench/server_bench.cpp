// Benchmarks of `brdfbake serve` (docs/BENCHMARKS.md, "The server"); not tests. Three modes:
//   server_bench tables URL N [BODY]      N x POST /v1/tables (default: a 128^2 GGX DFG table), after
//                                         10 warm-up requests: latency p50/p90/p99/max
//   server_bench misses URL N [BODY]      N x POST /v1/tables the result cache does not hold (default:
//                                         a 128^2 ggx-multiscatter DFG table, each request naming
//                                         another output file), after 10 warm-up requests: latency
//                                         p50/p90/p99/max, and the server's own split of each request
//                                         (its Server-Timing header) at the median
//   server_bench process N CMD ARGS...    N runs of a whole process (e.g. cmgen), wall time p50/p99
//   server_bench load URL CLIENTS SECONDS CLIENTS threads submit small jobs for SECONDS, each waiting
//                                         for its job before the next; then every job is checked:
//                                         accounted for once, done; latency, throughput, server memory
#include <httplib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <thread>
#include <vector>

namespace {

using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t i = static_cast<size_t>(std::min<double>(double(v.size() - 1), std::ceil(p * double(v.size())) - 1));
  return v[i];
}

void report(const char* what, const std::vector<double>& ms) {
  double sum = 0;
  for (double x : ms) sum += x;
  std::printf("%s: n %zu, mean %.2f ms, p50 %.2f ms, p90 %.2f ms, p99 %.2f ms, max %.2f ms\n", what, ms.size(),
              ms.empty() ? 0.0 : sum / double(ms.size()), percentile(ms, 0.5), percentile(ms, 0.9),
              percentile(ms, 0.99), percentile(ms, 1.0));
}

std::uint64_t server_rss(httplib::Client& c) {
  auto r = c.Get("/metrics");
  if (!r) return 0;
  const std::string key = "\nbrdfbake_process_resident_bytes ";
  const auto at = r->body.find(key);
  return at == std::string::npos ? 0 : std::strtoull(r->body.c_str() + at + key.size(), nullptr, 10);
}

int tables(const std::string& url, int n, const std::string& body) {
  httplib::Client c(url);
  c.set_read_timeout(60, 0);
  std::vector<double> ms;
  std::string cache;
  size_t bytes = 0;
  for (int i = -10; i < n; ++i) {
    const auto t0 = Clock::now();
    auto r = c.Post("/v1/tables", body, "application/json");
    const double t = ms_since(t0);
    if (!r || r->status != 200) {
      std::fprintf(stderr, "request %d failed: %s\n", i, r ? r->body.c_str() : httplib::to_string(r.error()).c_str());
      return 1;
    }
    cache = r->get_header_value("X-Brdfbake-Cache");
    bytes = r->body.size();
    if (i >= 0) ms.push_back(t);
  }
  std::printf("POST /v1/tables %s -> %zu bytes, cache %s\n", body.c_str(), bytes, cache.c_str());
  report("latency", ms);
  return 0;
}

// The server's split of a request: Server-Timing "name;dur=MS, ..." as name -> milliseconds.
std::map<std::string, double> server_timing(const std::string& header) {
  std::map<std::string, double> out;
  size_t at = 0;
  while (at < header.size()) {
    size_t end = header.find(',', at);
    if (end == std::string::npos) end = header.size();
    const std::string part = header.substr(at, end - at);
    const size_t semi = part.find(";dur=");
    if (semi != std::string::npos) {
      std::string name = part.substr(0, semi);
      name.erase(0, name.find_first_not_of(' '));
      out[name] = std::atof(part.c_str() + semi + 5);
    }
    at = end + 1;
  }
  return out;
}

int misses(const std::string& url, int n, const std::string& body_text) {
  httplib::Client c(url);
  c.set_read_timeout(60, 0);
  json body = json::parse(body_text);
  std::string ext = ".exr";
  if (body.contains("output")) {
    const std::string o = body["output"];
    if (o.rfind('.') != std::string::npos) ext = o.substr(o.rfind('.'));
  }
  std::vector<double> ms;
  std::map<std::string, std::vector<double>> parts;
  std::string cache, summary;
  size_t bytes = 0;
  const std::string tag = std::to_string(::getpid()) + "_" + std::to_string(Clock::now().time_since_epoch().count());
  for (int i = -10; i < n; ++i) {
    body["output"] = "miss_" + tag + "_" + std::to_string(i + 10) + ext;  // a new file name: not in the cache
    const std::string b = body.dump();
    const auto t0 = Clock::now();
    auto r = c.Post("/v1/tables", b, "application/json");
    const double t = ms_since(t0);
    if (!r || r->status != 200) {
      std::fprintf(stderr, "request %d failed: %s\n", i, r ? r->body.c_str() : httplib::to_string(r.error()).c_str());
      return 1;
    }
    cache = r->get_header_value("X-Brdfbake-Cache");
    if (cache != "miss") {
      std::fprintf(stderr, "request %d: X-Brdfbake-Cache %s (expected miss)\n", i, cache.c_str());
      return 1;
    }
    bytes = r->body.size();
    summary = r->get_header_value("X-Brdfbake-Summary");
    if (i < 0) continue;
    ms.push_back(t);
    for (const auto& [name, d] : server_timing(r->get_header_value("Server-Timing"))) parts[name].push_back(d);
  }
  std::printf("POST /v1/tables %s, a new output name each -> %zu bytes, cache %s\n%s\n", body_text.c_str(), bytes,
              cache.c_str(), summary.c_str());
  report("latency", ms);
  if (!parts.empty()) {
    std::printf("server's split (Server-Timing), p50 each:");
    for (const auto& [name, v] : parts) std::printf(" %s %.2f ms", name.c_str(), percentile(v, 0.5));
    std::printf("\n");
  }
  return 0;
}

int process(int n, char** cmd) {
  std::vector<double> ms;
  for (int i = -2; i < n; ++i) {
    const auto t0 = Clock::now();
    const pid_t pid = ::fork();
    if (pid == 0) {
      std::FILE* o = std::freopen("/dev/null", "w", stdout);
      std::FILE* e = std::freopen("/dev/null", "w", stderr);
      (void)o, (void)e;
      ::execvp(cmd[0], cmd);
      ::_exit(127);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      std::fprintf(stderr, "%s failed\n", cmd[0]);
      return 1;
    }
    if (i >= 0) ms.push_back(ms_since(t0));
  }
  std::string line;
  for (char** a = cmd; *a; ++a) line += std::string(a == cmd ? "" : " ") + *a;
  report(line.c_str(), ms);
  return 0;
}

int load(const std::string& url, int clients, double seconds) {
  // A small job: a Schlick table and a 32^2 DFG table (two bakes, two files).
  const std::string job = R"({"brdfbake_job": 1, "tables": [
      {"kind": "fresnel", "model": "schlick", "f0": 0.04, "size": 64, "output": "f.csv"},
      {"kind": "ggx", "size": 32, "output": "dfg.exr"}]})";
  std::mutex m;
  std::vector<double> submit_ms, done_ms;
  std::vector<std::string> ids;
  std::atomic<int> refused{0}, errors{0}, failed{0};
  std::vector<std::uint64_t> rss;
  httplib::Client probe(url);
  rss.push_back(server_rss(probe));
  const auto end = Clock::now() + std::chrono::duration<double>(seconds);
  std::vector<std::thread> threads;
  for (int k = 0; k < clients; ++k)
    threads.emplace_back([&] {
      httplib::Client c(url);
      c.set_read_timeout(120, 0);
      while (Clock::now() < end) {
        const auto t0 = Clock::now();
        auto r = c.Post("/v1/jobs", job, "application/json");
        const double post = ms_since(t0);
        if (!r) {
          ++errors;
          continue;
        }
        if (r->status == 503) {
          ++refused;
          std::this_thread::sleep_for(
              std::chrono::seconds(std::max(1, std::atoi(r->get_header_value("Retry-After").c_str()))));
          continue;
        }
        if (r->status != 202) {
          ++errors;
          continue;
        }
        const std::string id = json::parse(r->body)["id"];
        {
          std::lock_guard<std::mutex> lock(m);
          ids.push_back(id);
          submit_ms.push_back(post);
        }
        std::string state;
        while (state != "done" && state != "failed" && state != "cancelled") {
          auto s = c.Get(("/v1/jobs/" + id + "?wait=30").c_str());
          if (!s) {
            ++errors;
            break;
          }
          state = json::parse(s->body).value("state", "");
        }
        if (state != "done") ++failed;
        std::lock_guard<std::mutex> lock(m);
        done_ms.push_back(ms_since(t0));
      }
    });
  std::thread sampler([&] {
    while (Clock::now() < end) {
      std::this_thread::sleep_for(std::chrono::seconds(5));
      std::lock_guard<std::mutex> lock(m);
      rss.push_back(server_rss(probe));
    }
  });
  for (auto& t : threads) t.join();
  sampler.join();
  rss.push_back(server_rss(probe));

  // Every job accounted for: each submitted id listed once, done; no id the clients did not submit.
  probe.set_read_timeout(120, 0);
  auto list = probe.Get("/v1/jobs?limit=1000000");
  if (!list || list->status != 200) {
    std::fprintf(stderr, "GET /v1/jobs failed\n");
    return 1;
  }
  std::map<std::string, int> seen;
  std::map<std::string, std::string> states;
  const json listed = json::parse(list->body);
  for (const auto& j : listed["jobs"]) {
    ++seen[j["id"].get<std::string>()];
    states[j["id"].get<std::string>()] = j["state"].get<std::string>();
  }
  const std::set<std::string> submitted(ids.begin(), ids.end());
  int missing = 0, duplicated = 0, not_done = 0, unknown = 0;
  for (const auto& id : ids) {
    if (!seen.count(id))
      ++missing;
    else if (seen[id] > 1)
      ++duplicated;
    else if (states[id] != "done")
      ++not_done;
  }
  for (const auto& [id, n] : seen) unknown += submitted.count(id) ? 0 : n;
  std::printf(
      "%d clients for %.0f s: %zu jobs submitted (%zu distinct ids), %.1f jobs/s; 503 answers %d, transport errors %d, "
      "not done %d\n",
      clients, seconds, ids.size(), submitted.size(), double(ids.size()) / seconds, refused.load(), errors.load(),
      failed.load());
  std::printf("accounting: missing %d, duplicated %d, listed but not done %d, listed but never submitted %d\n", missing,
              duplicated, not_done, unknown);
  report("POST /v1/jobs", submit_ms);
  report("submit to done", done_ms);
  std::printf("server resident memory (MiB) every 5 s:");
  for (auto b : rss) std::printf(" %.1f", double(b) / 1048576.0);
  std::printf("\n");
  return missing + duplicated + not_done + unknown == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  if (mode == "tables" && argc >= 4)
    return tables(argv[2], std::atoi(argv[3]), argc > 4 ? argv[4] : R"({"kind": "ggx", "size": 128})");
  if (mode == "misses" && argc >= 4)
    return misses(argv[2], std::atoi(argv[3]), argc > 4 ? argv[4] : R"({"kind": "ggx-multiscatter", "size": 128})");
  if (mode == "process" && argc >= 4) return process(std::atoi(argv[2]), argv + 3);
  if (mode == "load" && argc >= 5) return load(argv[2], std::atoi(argv[3]), std::atof(argv[4]));
  std::fprintf(
      stderr,
      "usage: server_bench tables URL N [BODY] | misses URL N [BODY] | process N CMD ARGS... | load URL CLIENTS "
      "SECONDS\n");
  return 2;
}
