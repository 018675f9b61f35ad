// Exceptions of brdfbake. Only the command-line tool turns them into messages and exit codes
// (docs/RELIABILITY.md, "What each failure returns"):
//   Error           bad input: the request, a file it names, an option          -> exit 2
//   RuntimeFailure  the system failed, not the request: I/O, OpenCL, a result    -> exit 1
//                   that is not finite, an output another run is writing
//   Cancelled       SIGINT / SIGTERM (brdfbake/cancel.hpp)                        -> exit 130 / 143
#pragma once

#include <stdexcept>
#include <string>

namespace brdfbake {

// Bad input or a failed operation, with a complete one-line message.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// A failure that is not the request's fault: the same request may succeed on another run or machine.
class RuntimeFailure : public Error {
 public:
  explicit RuntimeFailure(const std::string& message) : Error(message) {}
};

// A file could not be written, or read part-way (a full disk, an I/O error, a path through a file):
// "cannot write '<path>': <reason>". A missing or malformed input file is an Error.
class IoError : public RuntimeFailure {
 public:
  explicit IoError(const std::string& message) : RuntimeFailure(message) {}
};

// Another process holds the output's lock (brdfbake/io: OutputLock); names its pid when known.
class LockedError : public RuntimeFailure {
 public:
  LockedError(const std::string& message, long pid) : RuntimeFailure(message), pid_(pid) {}
  long pid() const { return pid_; }

 private:
  long pid_;
};

// An OpenCL call failed: names the call, the kernel or program (when known) and the error, and for
// the errors that mean the device ran out of memory or was lost, what to do about it.
class ClError : public RuntimeFailure {
 public:
  ClError(const std::string& call, int code, const std::string& what_for = {});
  int code() const { return code_; }
  const std::string& call() const { return call_; }

 private:
  std::string call_;
  int code_;
};

// The symbolic name of an OpenCL error code, e.g. -5 -> "CL_OUT_OF_RESOURCES".
const char* cl_error_name(int code);

}  // namespace brdfbake
