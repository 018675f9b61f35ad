// Running the brdfbake command-line tool from tests, as a user runs it.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace brdfbake::test {

struct CliRun {
  int code = -1;  // exit status, -1 when the process did not exit normally
  std::string out, err;
};

// Runs `BRDFBAKE_CLI args` through the shell (args are shell-quoted by the caller), with `input`
// on standard input when given and `env` ("NAME=value ...") set for the command, capturing
// standard output and standard error.
inline CliRun run_cli(const std::string& args, const std::string& input = {}, const std::string& env = {}) {
  namespace fs = std::filesystem;
  static int counter = 0;
  const std::string stem = "brdfbake-cli-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  const fs::path err_file = fs::temp_directory_path() / (stem + ".err");
  const fs::path in_file = fs::temp_directory_path() / (stem + ".in");
  std::string cmd =
      env + (env.empty() ? "" : " ") +
      std::string(std::getenv("BRDFBAKE_CLI_UNDER_TEST") ? std::getenv("BRDFBAKE_CLI_UNDER_TEST") : BRDFBAKE_CLI) +
      " " + args + " 2>" + err_file.string();
  if (!input.empty()) {
    std::ofstream(in_file, std::ios::binary) << input;
    cmd += " <" + in_file.string();
  }
  CliRun r;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  const int status = ::pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream e(err_file);
  std::stringstream s;
  s << e.rdbuf();
  r.err = s.str();
  fs::remove(err_file);
  fs::remove(in_file);
  return r;
}

inline int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

}  // namespace brdfbake::test
