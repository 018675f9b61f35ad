// Shared pieces of the command-line front end.
#pragma once

#include <cxxopts.hpp>
#include <string>

#include "brdfbake/device.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/io.hpp"
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
// The options of a command that writes one table: -o/--output, --format, --pixel, --symbol.
void add_table_output_options(cxxopts::Options& options);

// Handles -h/--help and stray positional arguments; true when help was printed.
bool help_or_stray(const cxxopts::Options& options, const cxxopts::ParseResult& r);

Precision precision_option(const cxxopts::ParseResult& r);
std::string device_option(const cxxopts::ParseResult& r);  // "" = default, "reference", or a selector
bool quiet_option(const cxxopts::ParseResult& r);

// Where and how one table is written, validated before any slow work (the output folder is
// checked too).
struct TableOutput {
  std::string path;  // "-" for standard output
  TableFormat format = TableFormat::Csv;
  TableWriteOptions options;
};
TableOutput table_output_option(const cxxopts::ParseResult& r);
void write_table_output(const Table& table, const TableOutput& out);

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
int cmd_lut(int argc, char** argv);
int cmd_prefilter(int argc, char** argv);
int cmd_irradiance(int argc, char** argv);
int cmd_fresnel(int argc, char** argv);
int cmd_eval(int argc, char** argv);
int cmd_tabulate(int argc, char** argv);
int cmd_run(int argc, char** argv);
int cmd_bake(int argc, char** argv);

// Parses, turning cxxopts' exceptions into UsageError with the command's name.
cxxopts::ParseResult parse(cxxopts::Options& options, int argc, char** argv);

// The value of an option that must be a finite number / a positive integer.
double finite_number(const cxxopts::ParseResult& r, const std::string& name);
int integer(const cxxopts::ParseResult& r, const std::string& name);

}  // namespace brdfbake::cli
