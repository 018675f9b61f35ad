#include "cli_common.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <vector>
#include <cstdlib>

#include "brdfbake/backend.hpp"
#include "brdfbake/environment.hpp"

namespace brdfbake::cli {

cxxopts::ParseResult parse(cxxopts::Options& options, int argc, char** argv) {
  try {
    return options.parse(argc, argv);
  } catch (const cxxopts::exceptions::exception& e) {
    throw UsageError(e.what());
  }
}

double finite_number(const cxxopts::ParseResult& r, const std::string& name) {
  const std::string text = r[name].as<std::string>();
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v))
    throw UsageError("--" + name + " must be a finite number (got '" + text + "')");
  return v;
}

int integer(const cxxopts::ParseResult& r, const std::string& name) {
  const std::string text = r[name].as<std::string>();
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || v < -2147483647L || v > 2147483647L)
    throw UsageError("--" + name + " must be an integer (got '" + text + "')");
  return static_cast<int>(v);
}

void add_common_options(cxxopts::Options& options) {
  options.add_options()
      ("precision", "fp32 | fp64", cxxopts::value<std::string>()->default_value("fp32"))
      ("device", "P:D, cpu, gpu, a name substring, or reference (default: BRDFBAKE_DEVICE, else the first GPU, "
                 "else the first CPU)", cxxopts::value<std::string>())
      ("quiet", "no progress or summary lines")
      ("h,help", "this help");
}

bool help_or_stray(const cxxopts::Options& options, const cxxopts::ParseResult& r) {
  if (r.count("help")) {
    std::printf("%s\n", options.help().c_str());
    return true;
  }
  if (!r.unmatched().empty()) throw UsageError("unexpected argument '" + r.unmatched().front() + "'");
  return false;
}

Precision precision_option(const cxxopts::ParseResult& r) {
  return precision_from_name(r["precision"].as<std::string>());
}
std::string device_option(const cxxopts::ParseResult& r) {
  return r.count("device") ? r["device"].as<std::string>() : std::string();
}
bool quiet_option(const cxxopts::ParseResult& r) { return r.count("quiet") > 0; }

std::string memory_budget_help() {
  char gib[32];
  std::snprintf(gib, sizeof gib, "%.1f GiB", double(default_memory_budget()) / double(uint64_t(1) << 30));
  return std::string("the memory an input image may take decoded, checked from its header before anything is "
                     "allocated (e.g. 2GiB, 512MiB; default: half the machine's memory, ") + gib + ")";
}

std::uint64_t memory_budget_option(const cxxopts::ParseResult& r) {
  if (!r.count("memory-budget")) return 0;
  try {
    return parse_byte_size(r["memory-budget"].as<std::string>());
  } catch (const Error& e) {
    throw UsageError(std::string("--memory-budget: ") + e.what());
  }
}

void keep_until_exit(std::shared_ptr<void> object) {
#ifndef BRDFBAKE_ASAN
  static std::vector<std::shared_ptr<void>>* kept = new std::vector<std::shared_ptr<void>>();  // never destroyed
  kept->push_back(std::move(object));
#else
  (void)object;
#endif
}

std::shared_ptr<Backend> open_backend_kept(const std::string& selector) {
  std::shared_ptr<Backend> b = Backend::open(selector);
  keep_until_exit(b);
  return b;
}

RunOptions run_options(bool wait, bool quiet) {
  RunOptions o;
  o.wait_for_lock = wait;
  o.backend = open_backend_kept;
  o.on_warning = [](const std::string& w) { std::fprintf(stderr, "warning: %s\n", w.c_str()); };
  if (!quiet)
    o.on_wait = [](long pid) {
      std::fprintf(stderr, "waiting for another brdfbake run%s to finish writing the output folder...\n",
                   pid > 0 ? (" (pid " + std::to_string(pid) + ")").c_str() : "");
    };
  return o;
}

namespace {
double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

ProgressLine::ProgressLine(bool quiet) : enabled_(!quiet && ::isatty(2)), start_(now_seconds()) {}

void ProgressLine::update(const std::string& what, double fraction) {
  if (!enabled_ || (!shown_ && now_seconds() - start_ < 0.5)) return;
  shown_ = true;
  std::fprintf(stderr, "\r%s: %3.0f%%", what.c_str(), 100.0 * fraction);
  std::fflush(stderr);
}

void ProgressLine::finish() {
  if (shown_) std::fprintf(stderr, "\n");
  shown_ = false;
}

}  // namespace brdfbake::cli
