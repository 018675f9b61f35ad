// Finding and loading the OpenImageIO module (io/oiio_module.hpp) on first use.
#include <dlfcn.h>
#include <link.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <string>
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

// The shared object that holds this code (the Python extension module, a user's shared library),
// or "" when it is the executable itself: the loaded object whose segments contain this function
// (dl_iterate_phdr names the executable "").
fs::path own_shared_object() {
  struct Search {
    ElfW(Addr) address;
    std::string name;
  } search{reinterpret_cast<ElfW(Addr)>(&own_shared_object), {}};
  ::dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void* data) {
        auto* s = static_cast<Search*>(data);
        for (int i = 0; i < info->dlpi_phnum; ++i) {
          const ElfW(Phdr)& ph = info->dlpi_phdr[i];
          const ElfW(Addr) start = info->dlpi_addr + ph.p_vaddr;
          if (ph.p_type == PT_LOAD && s->address >= start && s->address < start + ph.p_memsz) {
            s->name = info->dlpi_name != nullptr ? info->dlpi_name : "";
            return 1;
          }
        }
        return 0;
      },
      &search);
  return search.name;
}

}  // namespace

std::vector<std::string> oiio_module_candidates() {
  if (const char* env = std::getenv("BRDFBAKE_OIIO_MODULE"); env != nullptr && *env != '\0') return {env};
  std::vector<std::string> out;
  // In a shared object (the Python package's extension): its own folder only, never the
  // interpreter's, and never a path of the build that made it (pip builds in a temporary folder,
  // deleted afterwards, whose path anyone may create again and fill).
  const fs::path object = own_shared_object();
  if (!object.empty()) {
    out.push_back((fs::absolute(object).parent_path() / kModuleFile).lexically_normal().string());
    return out;
  }
  // In the executable: beside it, and in the install tree's lib/brdfbake/.
  const fs::path dir = executable_dir();
  if (!dir.empty()) {
    out.push_back((dir / kModuleFile).string());
    out.push_back((dir / ".." / "lib" / "brdfbake" / kModuleFile).lexically_normal().string());
  }
#if defined(BRDFBAKE_OIIO_MODULE_BUILD_PATH) && defined(BRDFBAKE_BUILD_ROOT)
  // The build tree's copy, for the build tree's own programs (tests, benchmarks) alone: an
  // executable that lies in that tree, which therefore still exists and is the builder's.
  if (!dir.empty() && fs::path(BRDFBAKE_BUILD_ROOT).is_absolute()) {
    const fs::path root = fs::path(BRDFBAKE_BUILD_ROOT).lexically_normal();
    const fs::path rel = dir.lexically_normal().lexically_relative(root);
    if (!rel.empty() && *rel.begin() != "..") out.emplace_back(BRDFBAKE_OIIO_MODULE_BUILD_PATH);
  }
#endif
  return out;
}

namespace {

OiioModule load() {
  std::string tried;
  for (const std::string& path : oiio_module_candidates()) {
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
