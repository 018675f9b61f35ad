#include "runtime/cache_dirs.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <set>

#include "brdfbake/diagnostics.hpp"

namespace brdfbake {

namespace detail {

namespace {

namespace fs = std::filesystem;

std::mutex g_warning_mutex;
RuntimeWarningObserver g_warning_observer;
std::set<std::string> g_warned;

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v ? std::string(v) : std::string();
}

// PoCL's kernel cache folder, as PoCL chooses it (pocl_cache.c).
std::string pocl_cache_dir() {
  if (const std::string d = env("POCL_CACHE_DIR"); !d.empty()) return d;
  if (const std::string x = env("XDG_CACHE_HOME"); !x.empty()) return x + "/pocl/kcache";
  if (const std::string h = env("HOME"); !h.empty()) return h + "/.cache/pocl/kcache";
  return "/tmp/pocl/kcache";
}

// A folder only this user can use, under the temporary folder: the same one every run (so that it
// still caches), unless its name is taken by something that is not ours.
std::string private_cache_dir() {
  std::string tmp = env("TMPDIR");
  if (tmp.empty()) tmp = "/tmp";
  const std::string dir = tmp + "/brdfbake-pocl-cache-" + std::to_string(::getuid());
  ::mkdir(dir.c_str(), 0700);
  struct stat st {};
  if (::lstat(dir.c_str(), &st) == 0 && S_ISDIR(st.st_mode) && st.st_uid == ::getuid() && (st.st_mode & 077) == 0 &&
      cache_dir_problem(dir).empty())
    return dir;
  std::string pattern = tmp + "/brdfbake-pocl-cache-XXXXXX";  // taken or not ours: a new one
  if (::mkdtemp(pattern.data()) != nullptr) return pattern;
  return "";
}

}  // namespace

void runtime_warning(const std::string& warning) {
  std::lock_guard<std::mutex> lock(g_warning_mutex);
  if (!g_warned.insert(warning).second) return;
  if (g_warning_observer) g_warning_observer(warning);
}

std::string cache_dir_problem(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    fs::create_directories(dir, ec);
    if (ec) return "cannot create it: " + ec.message();
    if (!fs::is_directory(dir, ec)) return "it is not a folder";
  }
  const std::string probe = (fs::path(dir) / (".brdfbake-probe-" + std::to_string(::getpid()))).string();
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) {
    if (errno == EEXIST) return "";
    return std::strerror(errno);
  }
  ::close(fd);
  ::unlink(probe.c_str());
  return "";
}

void check_implementation_cache() {
  static std::once_flag once;
  std::call_once(once, [] {
    const std::string dir = pocl_cache_dir();
    const std::string problem = cache_dir_problem(dir);
    if (problem.empty()) return;
    const std::string instead = private_cache_dir();
    if (instead.empty()) return;  // nothing better: PoCL says what it says
    ::setenv("POCL_CACHE_DIR", instead.c_str(), 1);
    runtime_warning("the OpenCL implementation's kernel cache folder '" + dir + "' cannot be written (" + problem +
                    "): using '" + instead + "' instead (set POCL_CACHE_DIR to choose another)");
  });
}

}  // namespace detail

void set_runtime_warning_observer(RuntimeWarningObserver on_warning) {
  std::lock_guard<std::mutex> lock(detail::g_warning_mutex);
  detail::g_warning_observer = std::move(on_warning);
}

}  // namespace brdfbake
