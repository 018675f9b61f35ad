// Exceptions of brdfbake. Only the command-line tool turns them into messages and exit codes.
#pragma once

#include <stdexcept>
#include <string>

namespace brdfbake {

// Bad input or a failed operation, with a complete one-line message.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// An OpenCL call failed: names the call, the kernel or program (when known) and the error.
class ClError : public Error {
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
