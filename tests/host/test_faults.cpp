// Faults while brdfbake writes (docs/RELIABILITY.md, "Faults"): SIGTERM and SIGINT stop a run at
// its next check and leave no file; SIGKILL leaves temporaries that the next run into the folder
// removes; two runs into one folder never write it together. Each test starts the command-line tool
// as a child process, waits for a state it can see on disk, and signals it. Bounded: every wait has
// a deadline of seconds.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "support/temp_dir.hpp"

#ifndef BRDFBAKE_CLI
#define BRDFBAKE_CLI "brdfbake"
#endif

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// A fresh, empty folder `name` in the test's temporary folder (removed when the test ends).
fs::path temp_dir(const std::string& name) { return brdfbake::test::test_temp_dir(name); }

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The command-line tool as a child: its pid, a pipe to its standard input (kept open until closed),
// its standard error in a file.
struct Child {
  pid_t pid = -1;
  int stdin_fd = -1;
  fs::path err;

  Child(const std::vector<std::string>& args, const fs::path& cwd, bool pipe_stdin = false) {
    err = cwd / (".stderr-" + std::to_string(reinterpret_cast<uintptr_t>(this)));
    int fds[2] = {-1, -1};
    if (pipe_stdin && ::pipe(fds) != 0) return;
    pid = ::fork();
    if (pid == 0) {
      if (::chdir(cwd.c_str()) != 0) ::_exit(127);
      if (pipe_stdin) {
        ::dup2(fds[0], 0);
        ::close(fds[0]);
        ::close(fds[1]);
      } else {
        const int null_fd = ::open("/dev/null", O_RDONLY);
        ::dup2(null_fd, 0);
      }
      const int out = ::open("/dev/null", O_WRONLY);
      ::dup2(out, 1);
      const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(e, 2);
      std::vector<char*> argv;
      std::string cli = BRDFBAKE_CLI;
      argv.push_back(cli.data());
      std::vector<std::string> copy = args;
      for (auto& a : copy) argv.push_back(a.data());
      argv.push_back(nullptr);
      ::execv(cli.c_str(), argv.data());
      ::_exit(127);
    }
    if (pipe_stdin) {
      ::close(fds[0]);
      stdin_fd = fds[1];
    }
  }
  ~Child() {
    if (stdin_fd >= 0) ::close(stdin_fd);
    if (pid > 0 && !reaped) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
    }
    std::error_code ec;
    fs::remove(err, ec);
  }
  // Waits (at most `seconds`) for the exit; the exit code, 128 + signal when killed, -1 on timeout.
  int wait(double seconds = 60) {
    const auto end = Clock::now() + std::chrono::duration<double>(seconds);
    while (Clock::now() < end) {
      int status = 0;
      const pid_t r = ::waitpid(pid, &status, WNOHANG);
      if (r == pid) {
        reaped = true;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return -1;
  }
  std::string stderr_text() const { return read_file(err); }
  bool reaped = false;
};

// Polls `ready` every 20 ms for at most `seconds`.
bool eventually(const std::function<bool()>& ready, double seconds = 60) {
  const auto end = Clock::now() + std::chrono::duration<double>(seconds);
  while (Clock::now() < end) {
    if (ready()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

// Entries of `dir` whose names hold `part`.
std::vector<std::string> entries_with(const fs::path& dir, const std::string& part) {
  std::vector<std::string> out;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); it != fs::recursive_directory_iterator(); it.increment(ec))
    if (it->path().filename().string().find(part) != std::string::npos) out.push_back(it->path().string());
  return out;
}

// A job whose second table runs for minutes on a CPU device, in launches of about a second: a run
// is sure to be inside it when signalled, and honours the signal within one launch.
const char* kSlowJob = R"({"brdfbake_job": 1, "tables": [
  {"kind": "ggx", "size": 4, "output": "quick.exr"},
  {"kind": "ggx", "size": 1024, "estimator": "vndf", "samples": 65536, "output": "slow.exr"}]})";

void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

// The run has started writing: its staging folder exists.
bool staging_exists(const fs::path& dir) { return !entries_with(dir, ".out.tmp-").empty(); }

TEST(Faults, SigtermStopsARunAndLeavesNoFile) {
  const fs::path dir = temp_dir("sigterm");
  write(dir / "job.json", kSlowJob);
  Child run({"run", "job.json", "-o", "out", "--quiet"}, dir);
  ASSERT_TRUE(eventually([&] { return staging_exists(dir); })) << run.stderr_text();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // inside the slow table
  ::kill(run.pid, SIGTERM);
  const auto t0 = Clock::now();
  const int code = run.wait(60);
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  EXPECT_EQ(code, 128 + SIGTERM) << run.stderr_text();
  EXPECT_NE(run.stderr_text().find("interrupted by SIGTERM"), std::string::npos) << run.stderr_text();
  // within one bounded launch (about a second on a 2-core CPU device; generous under load)
  EXPECT_LT(seconds, 30.0);
  EXPECT_FALSE(fs::exists(dir / "out"));
  EXPECT_TRUE(entries_with(dir, ".tmp-").empty());
  EXPECT_TRUE(entries_with(dir, ".lock").empty());
}

TEST(Faults, SigintStopsAOneTableCommand) {
  const fs::path dir = temp_dir("sigint");
  Child lut({"lut", "--size", "1024", "--estimator", "vndf", "--samples", "65536", "-o", "t.exr", "--quiet"}, dir);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // the program is built, launches run
  ::kill(lut.pid, SIGINT);
  EXPECT_EQ(lut.wait(60), 128 + SIGINT) << lut.stderr_text();
  EXPECT_NE(lut.stderr_text().find("interrupted by SIGINT"), std::string::npos) << lut.stderr_text();
  EXPECT_FALSE(fs::exists(dir / "t.exr"));
  EXPECT_TRUE(entries_with(dir, ".tmp-").empty());
}

TEST(Faults, SigintStopsAStreamWaitingForInput) {
  const fs::path dir = temp_dir("stream");
  write(dir / "m.json", R"({"materials": [{"name": "a", "model": "lambert"}]})");
  Child eval({"eval", "--material", "m.json", "-i", "-", "-o", "f.csv", "--quiet"}, dir, true);
  const std::string lines = "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,1,0,0,1\n";
  ASSERT_EQ(::write(eval.stdin_fd, lines.data(), lines.size()), static_cast<ssize_t>(lines.size()));
  ASSERT_TRUE(eventually([&] { return !entries_with(dir, ".f.csv.tmp-").empty(); }, 30));  // writing
  ::kill(eval.pid, SIGINT);  // standard input stays open: the read is interrupted
  EXPECT_EQ(eval.wait(30), 128 + SIGINT) << eval.stderr_text();
  EXPECT_FALSE(fs::exists(dir / "f.csv"));
  EXPECT_TRUE(entries_with(dir, ".tmp-").empty());
}

TEST(Faults, SigkillLeftoversAreRemovedByTheNextRun) {
  const fs::path dir = temp_dir("sigkill");
  write(dir / "job.json", kSlowJob);
  {
    Child run({"run", "job.json", "-o", "out", "--quiet"}, dir);
    ASSERT_TRUE(eventually([&] { return staging_exists(dir); })) << run.stderr_text();
    ::kill(run.pid, SIGKILL);
    EXPECT_EQ(run.wait(30), 128 + SIGKILL);
  }
  ASSERT_FALSE(entries_with(dir, ".out.tmp-").empty()) << "SIGKILL should leave the staging folder";
  write(dir / "job.json", R"({"brdfbake_job": 1, "tables": [{"kind": "ggx", "size": 4, "output": "quick.exr"}]})");
  Child again({"run", "job.json", "-o", "out", "--quiet"}, dir);
  EXPECT_EQ(again.wait(120), 0) << again.stderr_text();
  EXPECT_TRUE(fs::exists(dir / "out" / "quick.exr"));
  EXPECT_TRUE(entries_with(dir, ".tmp-").empty()) << "the killed run's staging folder is still there";
  EXPECT_TRUE(entries_with(dir, ".lock").empty());
}

TEST(Faults, TwoRunsIntoOneFolder) {
  const fs::path dir = temp_dir("two");
  write(dir / "job.json", kSlowJob);
  write(dir / "quick.json", R"({"brdfbake_job": 1, "tables": [{"kind": "ggx", "size": 4, "output": "other.exr"}]})");
  Child first({"run", "job.json", "-o", "out", "--quiet"}, dir);
  ASSERT_TRUE(eventually([&] { return staging_exists(dir); })) << first.stderr_text();
  // A second run fails at once, naming the first.
  Child second({"run", "quick.json", "-o", "out", "--quiet"}, dir);
  EXPECT_EQ(second.wait(60), 1) << second.stderr_text();
  EXPECT_NE(second.stderr_text().find("pid " + std::to_string(first.pid)), std::string::npos) << second.stderr_text();
  // With --wait it queues behind the first and runs when the first ends (here: stopped).
  Child waiting({"run", "quick.json", "-o", "out", "--wait", "--quiet"}, dir);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  EXPECT_FALSE(fs::exists(dir / "out" / "other.exr"));  // still waiting
  ::kill(first.pid, SIGTERM);
  EXPECT_EQ(first.wait(60), 128 + SIGTERM) << first.stderr_text();
  EXPECT_EQ(waiting.wait(120), 0) << waiting.stderr_text();
  EXPECT_TRUE(fs::exists(dir / "out" / "other.exr"));
  EXPECT_FALSE(fs::exists(dir / "out" / "slow.exr"));
  // The manifest describes what this run wrote, and nothing of the stopped one.
  const std::string manifest = read_file(dir / "out" / "manifest.json");
  EXPECT_NE(manifest.find("other.exr"), std::string::npos);
  EXPECT_EQ(manifest.find("quick.exr"), std::string::npos);
  EXPECT_TRUE(entries_with(dir, ".tmp-").empty());
  EXPECT_TRUE(entries_with(dir, ".lock").empty());
}

}  // namespace
