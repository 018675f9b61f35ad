// Internal: the one place programs are built, from embedded kernel sources, with #defines and a
// binary cache on disk.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "brdfbake/device.hpp"
#include "runtime/device_impl.hpp"

namespace brdfbake::detail {

// The text of kernels/<path> with its #include "..." lines expanded (each file once), taken from
// the sources embedded at build time, or from $BRDFBAKE_KERNEL_DIR when set (developer switch).
std::string kernel_source(const std::string& path);

struct ProgramSpec {
  std::string file;                                          // e.g. "dfg_lut.cl"
  std::vector<std::pair<std::string, std::string>> defines;  // injected as #define NAME VALUE
  Precision precision = Precision::Fp32;                     // Fp64 defines BRDFBAKE_FP64 1
  std::string options;                                       // extra build options
};

// Builds (or fetches from the in-memory and on-disk caches) the program for `spec` on `device`.
// Throws Error with the build log when the build fails, and when fp64 is asked of a device
// without it.
cl::Program build_program(Device::Impl& device, const ProgramSpec& spec);

// The on-disk cache: $BRDFBAKE_CACHE_DIR, else $XDG_CACHE_HOME/brdfbake/kernels, else
// ~/.cache/brdfbake/kernels. set_program_cache_dir overrides (an empty path disables the cache).
std::string program_cache_dir();
void set_program_cache_dir(const std::string& dir);

struct ProgramCacheStats {
  uint64_t disk_hits = 0;       // programs created from a cached binary
  uint64_t source_builds = 0;   // programs built from source
  uint64_t bad_entries = 0;     // cache entries that could not be used (fell back to source)
  uint64_t write_failures = 0;  // binaries that could not be written to the cache
};
ProgramCacheStats program_cache_stats();

// Seconds between the start and the end of a profiled event.
double event_seconds(const cl::Event& event);

}  // namespace brdfbake::detail
