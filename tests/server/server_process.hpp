// A `brdfbake serve` child process for the server tests: started on 127.0.0.1 with an ephemeral
// port (the URL comes back through --url-file), stopped by signal, killed when the test ends.
#pragma once

#include <gtest/gtest.h>
#include <httplib.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "support/temp_dir.hpp"

namespace brdfbake::test {

namespace fs = std::filesystem;
using json = nlohmann::json;

inline std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_file(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << text;
}

class ServerProcess {
 public:
  // `args` come after "serve --listen 127.0.0.1:0 --url-file F"; `in_child` runs in the child
  // before exec (e.g. a file size limit).
  ServerProcess(const fs::path& dir, std::vector<std::string> args, std::function<void()> in_child = {})
      : dir_(dir), args_(std::move(args)), in_child_(std::move(in_child)) {}
  ~ServerProcess() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }

  // Starts and waits (at most 30 s) until it listens; returns false with the reason in error().
  bool start() {
    const fs::path url_file = dir_ / "server.url";
    std::error_code ec;
    fs::remove(url_file, ec);
    std::vector<std::string> argv = {
        std::getenv("BRDFBAKE_CLI_UNDER_TEST") ? std::getenv("BRDFBAKE_CLI_UNDER_TEST") : BRDFBAKE_CLI,
        "serve",
        "--listen",
        "127.0.0.1:0",
        "--url-file",
        url_file.string()};
    argv.insert(argv.end(), args_.begin(), args_.end());
    const std::string out = (dir_ / "server.out").string(), err = (dir_ / "server.err").string();
    pid_ = ::fork();
    if (pid_ == 0) {
      if (in_child_) in_child_();
      std::FILE* o = std::freopen(out.c_str(), "a", stdout);
      std::FILE* e = std::freopen(err.c_str(), "a", stderr);
      (void)o, (void)e;
      std::vector<char*> cargv;
      for (auto& a : argv) cargv.push_back(a.data());
      cargv.push_back(nullptr);
      ::execv(cargv[0], cargv.data());
      ::_exit(127);
    }
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (std::chrono::steady_clock::now() < until) {
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        exit_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        error_ = "the server exited (" + std::to_string(exit_status_) + "): " + read_file(dir_ / "server.err");
        return false;
      }
      std::string u = read_file(url_file);
      if (!u.empty() && u.back() == '\n') {
        u.pop_back();
        url_ = u;
        return true;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    error_ = "the server did not listen within 30 s: " + read_file(dir_ / "server.err");
    return false;
  }

  const std::string& url() const { return url_; }
  const std::string& error() const { return error_; }
  pid_t pid() const { return pid_; }
  int port() const { return std::stoi(url_.substr(url_.rfind(':') + 1)); }
  std::string stderr_text() const { return read_file(dir_ / "server.err"); }

  void signal(int sig) {
    if (pid_ > 0) ::kill(pid_, sig);
  }
  // Waits for the process to exit (at most `seconds`); its exit code, -1 when killed, -2 when it
  // is still running.
  int wait_exit(double seconds) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (pid_ > 0 && std::chrono::steady_clock::now() < until) {
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return pid_ > 0 ? -2 : exit_status_;
  }

  httplib::Client client(const std::string& token = {}) const {
    httplib::Client c(url_);
    c.set_read_timeout(60, 0);
    if (!token.empty()) c.set_bearer_token_auth(token.c_str());
    return c;
  }

 private:
  fs::path dir_;
  std::vector<std::string> args_;
  std::function<void()> in_child_;
  pid_t pid_ = -1;
  int exit_status_ = -1;
  std::string url_, error_;
};

// The body of a response as JSON (null when it is not JSON).
inline json body_json(const httplib::Result& r) { return r ? json::parse(r->body, nullptr, false) : json(); }

// Polls a job until it is finished (at most `seconds`); its last status.
inline json wait_job(httplib::Client& c, const std::string& id, double seconds = 60) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  json s;
  while (std::chrono::steady_clock::now() < until) {
    auto r = c.Get(("/v1/jobs/" + id + "?wait=1").c_str());
    if (!r) continue;
    s = body_json(r);
    const std::string state = s.value("state", "");
    if (state == "done" || state == "failed" || state == "cancelled") return s;
  }
  return s;
}

// Submits a job document; its id ("" when refused).
inline std::string submit(httplib::Client& c, const json& job) {
  auto r = c.Post("/v1/jobs", job.dump(), "application/json");
  if (!r || r->status != 202) return {};
  return body_json(r).value("id", "");
}

// The data lines of a CSV (the '#' metadata and the header row dropped).
inline std::vector<std::vector<double>> csv_rows(const std::string& text) {
  std::vector<std::vector<double>> rows;
  std::stringstream in(text);
  std::string line;
  bool header = true;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header) {
      header = false;
      continue;
    }
    std::vector<double> row;
    std::stringstream cells(line);
    std::string cell;
    while (std::getline(cells, cell, ',')) row.push_back(std::stod(cell));
    rows.push_back(row);
  }
  return rows;
}

// A test suite sharing one server, started once for the suite: `Suite` (the derived fixture) names
// its folder (`static constexpr const char* kFolder`) and writes its inputs there, returning the
// server's arguments (`static std::vector<std::string> arguments(const fs::path& dir)`).
template <class Suite>
class SharedServer : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir(Suite::kFolder);
    server_ = new ServerProcess(dir_->path, Suite::arguments(dir_->path));
    started_ = server_->start();
  }
  static void TearDownTestSuite() {
    delete server_;
    delete dir_;
    server_ = nullptr;
    dir_ = nullptr;
  }
  void SetUp() override { ASSERT_TRUE(started_) << server_->error(); }

  static inline TempDir* dir_ = nullptr;
  static inline ServerProcess* server_ = nullptr;
  static inline bool started_ = false;
};

}  // namespace brdfbake::test
