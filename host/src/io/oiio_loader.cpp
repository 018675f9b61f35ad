// Finding and loading the OpenImageIO module (io/oiio_module.hpp) on first use.
#include <dlfcn.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <vector>

#include "brdfbake/error.hpp"
#include "io/oiio_module.hpp"

namespace brdfbake::io {
namespace {

namespace fs = std::filesystem;

constexpr const char* kModuleFile = "brdfbake_oiio.so";

std::atomic<bool> g_loaded{false};

// The folder of the running executable (Linux: /proc/self/exe).
fs::path executable_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe.parent_path();
}

std::vector<std::string> candidates() {
  if (const char* env = std::getenv("BRDFBAKE_OIIO_MODULE"); env != nullptr && *env != '\0') return {env};
  std::vector<std::string> out;
  const fs::path dir = executable_dir();
  if (!dir.empty()) {
    out.push_back((dir / kModuleFile).string());
    out.push_back((dir / ".." / "lib" / "brdfbake" / kModuleFile).lexically_normal().string());
  }
#ifdef BRDFBAKE_OIIO_MODULE_BUILD_PATH
  out.emplace_back(BRDFBAKE_OIIO_MODULE_BUILD_PATH);
#endif
  return out;
}

OiioModule load() {
  std::string tried;
  for (const std::string& path : candidates()) {
    std::error_code ec;
    if (!fs::exists(path, ec)) {
      tried += (tried.empty() ? "" : ", ") + path;
      continue;
    }
    // RTLD_LOCAL: OpenImageIO's symbols stay inside the module; never closed (OpenImageIO keeps
    // global state and threads).
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* why = ::dlerror();
      throw Error("the OpenImageIO module '" + path + "' does not load: " + (why ? why : "unknown reason"));
    }
    const auto abi = reinterpret_cast<brdfbake_oiio_abi_version_fn>(::dlsym(handle, "brdfbake_oiio_abi_version"));
    OiioModule m;
    m.read = reinterpret_cast<brdfbake_oiio_read_fn>(::dlsym(handle, "brdfbake_oiio_read"));
    m.free = reinterpret_cast<brdfbake_oiio_free_fn>(::dlsym(handle, "brdfbake_oiio_free"));
    m.path = path;
    if (abi == nullptr || m.read == nullptr || m.free == nullptr)
      throw Error("'" + path + "' is not a brdfbake OpenImageIO module (missing functions)");
    if (abi() != BRDFBAKE_OIIO_ABI_VERSION)
      throw Error("the OpenImageIO module '" + path + "' has interface version " + std::to_string(abi()) +
                  ", this brdfbake needs " + std::to_string(BRDFBAKE_OIIO_ABI_VERSION));
    return m;
  }
  throw Error("the OpenImageIO module " + std::string(kModuleFile) + " is not installed (looked for " + tried +
              "; set BRDFBAKE_OIIO_MODULE to its path)");
}

}  // namespace

const OiioModule& oiio_module() {
  static std::mutex mutex;
  static OiioModule module;
  std::lock_guard<std::mutex> lock(mutex);
  if (!g_loaded) {
    module = load();  // throws and leaves g_loaded false: a later call tries again
    g_loaded = true;
  }
  return module;
}

bool oiio_module_loaded() { return g_loaded; }

}  // namespace brdfbake::io
