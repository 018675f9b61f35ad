// What happens while OpenCL programs build, for front ends that want to show it. The library itself
// never writes to the process's standard error: the OpenCL compiler's build log, and anything an
// OpenCL implementation prints on its own during clBuildProgram (PoCL's "N warnings generated."), is
// captured and handed to the observer set here, or dropped when none is set. A build that fails
// carries its log in the thrown Error instead.
#pragma once

#include <functional>
#include <string>

namespace brdfbake {

struct ProgramBuild {
  std::string program;      // kernels/<file> with its options, e.g. "kernels/dfg_lut.cl fp32"
  std::string device;       // the device's name
  bool from_cache = false;  // true: a cached binary was loaded (no compilation)
  double seconds = 0.0;     // wall time of the build or load
  std::string log;          // the build log and whatever the implementation printed, trimmed
};

// Called before a program is compiled from source (a cold cache: about a second a program on PoCL).
using ProgramBuildStartObserver = std::function<void(const std::string& program, const std::string& device)>;
// Called after each build or cached load.
using ProgramBuildObserver = std::function<void(const ProgramBuild&)>;

// Process-wide; pass {} to remove. The observers may be called from any thread, one call at a time.
void set_program_build_observers(ProgramBuildStartObserver on_start, ProgramBuildObserver on_done);

// Problems of the machine's set-up that the runtime works around and the user should hear of, one
// line each, at most once a process: a kernel cache folder that cannot be written (the OpenCL
// implementation's or brdfbake's), with what was done instead. Process-wide; {} removes it; called
// from any thread, one call at a time; without an observer the warnings are dropped.
using RuntimeWarningObserver = std::function<void(const std::string& warning)>;
void set_runtime_warning_observer(RuntimeWarningObserver on_warning);

}  // namespace brdfbake
