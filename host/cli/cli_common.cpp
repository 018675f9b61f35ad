#include "cli_common.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <map>
#include <sstream>
#include <vector>

#include "brdfbake/backend.hpp"
#include "brdfbake/environment.hpp"

namespace brdfbake::cli {

namespace {

// The optimal string alignment distance (Levenshtein with adjacent transpositions) of a and b.
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= a.size(); ++i)
    for (size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

// Every long option name of `options`, aliases included.
std::vector<std::string> long_option_names(const cxxopts::Options& options) {
  std::vector<std::string> names;
  for (const std::string& g : options.groups())
    for (const auto& o : options.group_help(g).options)
      for (const std::string& l : o.l) names.push_back(l);
  return names;
}

// The argument that names no option of `known`, as typed ("--sise"), or "".
std::string unknown_argument(int argc, char** argv, const std::vector<std::string>& known, const std::string& what) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.size() < 2 || a[0] != '-' || a == "--") continue;
    const size_t dashes = a[1] == '-' ? 2 : 1;
    const std::string name =
        a.substr(dashes, a.find('=') == std::string::npos ? std::string::npos : a.find('=') - dashes);
    if (name.empty() || std::isdigit(static_cast<unsigned char>(name[0])) || name[0] == '.') continue;  // -8, -.5
    if (dashes == 1 && name.size() == 1) continue;  // a short option: cxxopts names it itself
    if (std::find(known.begin(), known.end(), name) == known.end() && what.find(name) != std::string::npos)
      return a.substr(0, dashes + name.size());
  }
  return "";
}

}  // namespace

std::string closest_name(const std::string& given, const std::vector<std::string>& names) {
  std::string best;
  size_t best_distance = std::string::npos;
  for (const std::string& n : names) {
    if (n.size() < 2) continue;
    const size_t d = edit_distance(given, n);
    if (d < best_distance) {
      best_distance = d;
      best = n;
    }
  }
  // Close enough to be a slip: a third of the word (at least one edit, at most three).
  const size_t allowed = std::clamp<size_t>(given.size() / 3, 1, 3);
  if (best_distance <= allowed) return best;
  // Or the start of one to three names (--sh-ord, --cube: --cube-size or --cube-format).
  std::vector<std::string> starting;
  for (const std::string& n : names)
    if (given.size() >= 3 && n.size() > given.size() && n.compare(0, given.size(), given) == 0 &&
        std::find(starting.begin(), starting.end(), n) == starting.end())
      starting.push_back(n);
  if (starting.empty() || starting.size() > 3) return "";
  std::string s;
  for (size_t k = 0; k < starting.size(); ++k)
    s += (k == 0 ? "" : k + 1 == starting.size() ? " or --" : ", --") + starting[k];
  return s;
}

cxxopts::ParseResult parse(cxxopts::Options& options, int argc, char** argv) {
  try {
    return options.parse(argc, argv);
  } catch (const cxxopts::exceptions::no_such_option& e) {
    const std::vector<std::string> names = long_option_names(options);
    const std::string typed = unknown_argument(argc, argv, names, e.what());
    if (typed.empty()) throw UsageError(e.what());
    const std::string name = typed.substr(typed[1] == '-' ? 2 : 1);
    // An alias meant (--cube-sze, --cube): its option's canonical name, the first of its long names.
    std::map<std::string, std::string> canonical;
    for (const std::string& g : options.groups())
      for (const auto& o : options.group_help(g).options)
        for (size_t k = 1; k < o.l.size(); ++k) canonical[o.l[k]] = o.l.front();
    std::string close;
    std::istringstream words(closest_name(name, names));
    for (std::string w; words >> w;) {
      const bool comma = !w.empty() && w.back() == ',';
      if (comma) w.pop_back();
      const size_t dashes = w.rfind("--", 0) == 0 ? 2 : 0;
      if (w != "or") {
        const auto c = canonical.find(w.substr(dashes));
        if (c != canonical.end()) w = w.substr(0, dashes) + c->second;
      }
      close += (close.empty() ? "" : " ") + w + (comma ? "," : "");
    }
    throw UsageError("unknown option '" + typed + "' (" +
                     (close.empty() ? "see --help" : "did you mean --" + close + "?") + ")");
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
  options.add_options()("precision", "fp32 | fp64", cxxopts::value<std::string>()->default_value("fp32"))(
      "device",
      "P:D, cpu, gpu, a name substring, or reference (default: BRDFBAKE_DEVICE, else the first GPU, "
      "else the first CPU)",
      cxxopts::value<std::string>())("quiet", "no progress or summary lines")("h,help", "this help");
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
  return std::string(
             "the memory an input image may take decoded, checked from its header before anything is "
             "allocated (e.g. 2GiB, 512MiB; default: half the machine's memory, ") +
         gib + ")";
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
  o.on_warning = [](const std::string& w) { print_warning(w); };
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

std::string one_line(const std::string& message) {
  std::string out;
  out.reserve(message.size());
  for (const char ch : message) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '\n')
      out += "\\n";
    else if (c == '\r')
      out += "\\r";
    else if (c < 0x20 || c == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    } else
      out += ch;
  }
  return out;
}

void print_warning(const std::string& message) { std::fprintf(stderr, "warning: %s\n", one_line(message).c_str()); }

}  // namespace brdfbake::cli
