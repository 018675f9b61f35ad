// The folders OpenCL programs are cached in, checked before they are needed (docs/RELIABILITY.md,
// "Special files"): a cache that cannot be written costs time, never the device.
#pragma once

#include <string>

namespace brdfbake::detail {

// Hands `warning` to the runtime warning observer (brdfbake/diagnostics.hpp), once a process per text.
void runtime_warning(const std::string& warning);

// Before the first OpenCL platform is loaded (once a process): PoCL refuses to start when it cannot
// create its kernel cache ($POCL_CACHE_DIR, else $XDG_CACHE_HOME/pocl/kcache, else
// ~/.cache/pocl/kcache), and the platform then lists no device. When that folder cannot be written,
// POCL_CACHE_DIR is pointed at a private folder of this user under the temporary folder (created
// 0700 and checked to be ours), and a runtime warning says why.
void check_implementation_cache();

// Why `dir` cannot hold a cache ("" when it can): created when missing, probed with a file.
std::string cache_dir_problem(const std::string& dir);

}  // namespace brdfbake::detail
