// Shared pieces of the command-line front end.
#pragma once

#include <cxxopts.hpp>
#include <memory>
#include <string>
#include <vector>

#include "brdfbake/device.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/io.hpp"
#include "brdfbake/job.hpp"
#include "brdfbake/table.hpp"

namespace brdfbake::cli {

// Exit codes: 0 success, 1 runtime failure (OpenCL, I/O), 2 bad usage or bad input.
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;

// A usage error (unknown option, missing argument, bad value): exit code 2.
class UsageError : public Error {
 public:
  explicit UsageError(const std::string& m) : Error(m) {}
};

// The options every baking command shares: --device, --precision, --quiet, -h/--help.
void add_common_options(cxxopts::Options& options);

// Handles -h/--help and stray positional arguments; true when help was printed.
bool help_or_stray(const cxxopts::Options& options, const cxxopts::ParseResult& r);

Precision precision_option(const cxxopts::ParseResult& r);
std::string device_option(const cxxopts::ParseResult& r);  // "" = default, "reference", or a selector
bool quiet_option(const cxxopts::ParseResult& r);

// A progress line on standard error for long runs: shown only on a terminal, once the run has
// taken more than half a second, and never with --quiet.
class ProgressLine {
 public:
  explicit ProgressLine(bool quiet);
  void update(const std::string& what, double fraction);
  void finish();  // ends the line if one was shown

 private:
  bool enabled_;
  bool shown_ = false;
  double start_;
};

int cmd_devices(int argc, char** argv);
int cmd_fresnel(int argc, char** argv);
int cmd_kinds(int argc, char** argv);
int cmd_run(int argc, char** argv);
int cmd_bake(int argc, char** argv);
int cmd_view(int argc, char** argv);
int cmd_report(int argc, char** argv);
int cmd_serve(int argc, char** argv);

// How bake and run share their output folder: --wait, and a note on stderr when waiting.
RunOptions run_options(bool wait, bool quiet);

// Parses, turning cxxopts' exceptions into UsageError with the command's name; an unknown option
// says which known one is closest ("unknown option '--sise' (did you mean --size?)").
cxxopts::ParseResult parse(cxxopts::Options& options, int argc, char** argv);
// The name among `names` that `given` is most likely a slip for (a third of its letters wrong at
// most), else the names it is the start of ("cube-size or --cube-format", at most three), or "".
std::string closest_name(const std::string& given, const std::vector<std::string>& names);

// A message as one line of standard error (issue 34, class 7): a control character of a name it
// quotes (a newline, a carriage return, an escape) is written as \n, \r or \xHH, so that no name splits
// an error into two lines or forges a "warning:" line of its own.
std::string one_line(const std::string& message);
// "warning: MESSAGE" (one_line) on standard error.
void print_warning(const std::string& message);

// The process ends with _exit once the command has returned and the streams are flushed (main.cpp):
// tearing down the OpenCL implementation's and LLVM's state (~5-10 ms) serves no one then. Sanitizer
// builds (BRDFBAKE_ASAN, cmake/Sanitizers.cmake) end normally, so that LeakSanitizer still looks at
// the heap.
// Keeps `object` (a backend and its OpenCL context) alive until the process ends, so that its
// teardown is skipped with the rest; where the process ends normally, nothing (it goes when its
// last owner lets go, before the OpenCL implementation's own static state).
void keep_until_exit(std::shared_ptr<void> object);
// run_options' backends, each kept until the process ends.
std::shared_ptr<Backend> open_backend_kept(const std::string& selector);

// --memory-budget SIZE (every command that reads environment images): the option's help, and its
// value in bytes (0 when it is not given: the default).
std::string memory_budget_help();
std::uint64_t memory_budget_option(const cxxopts::ParseResult& r);

// The value of an option that must be a finite number / a positive integer.
double finite_number(const cxxopts::ParseResult& r, const std::string& name);
int integer(const cxxopts::ParseResult& r, const std::string& name);

}  // namespace brdfbake::cli
