// Runs a function with the process's standard error (file descriptor 2) redirected into an unlinked
// temporary file, and returns what was written there. OpenCL implementations may print compiler
// diagnostics straight to fd 2 during clBuildProgram (PoCL 3.1 prints "N warnings generated."); the
// library contains that text and hands it to its observer instead (brdfbake/diagnostics.hpp).
// One capture runs at a time in the process; text other threads write to stderr meanwhile is
// captured with it.
#pragma once

#include <functional>
#include <string>

namespace brdfbake::detail {

std::string run_with_stderr_captured(const std::function<void()>& fn);

}  // namespace brdfbake::detail
