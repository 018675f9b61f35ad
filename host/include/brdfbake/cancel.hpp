// Cooperative cancellation: a process-wide flag that long work checks between device launches,
// between the tables of a job and between the chunks of a stream (docs/RELIABILITY.md, "Faults").
// The command-line tool sets it from its SIGINT and SIGTERM handlers; the server and the Python
// package may set it too. What is being written is removed as the Cancelled exception unwinds
// (temporary files and folders), so a cancelled run leaves no file.
#pragma once

#include <string>

#include "brdfbake/error.hpp"

namespace brdfbake {

// The run was stopped by request: `signal()` is the signal number (SIGINT 2, SIGTERM 15), or 0.
class Cancelled : public Error {
 public:
  Cancelled(const std::string& message, int signal) : Error(message), signal_(signal) {}
  int signal() const { return signal_; }

 private:
  int signal_;
};

// Asks the work in progress to stop at its next check. Async-signal-safe: a signal handler may call it.
void request_cancel(int signal = 0) noexcept;
bool cancel_requested() noexcept;
// The signal passed to request_cancel (0 when none).
int cancel_signal() noexcept;
// Clears the request (tests; a server between jobs).
void reset_cancel() noexcept;
// Throws Cancelled ("interrupted by SIGINT" ...) when a stop was requested.
void throw_if_cancelled();

}  // namespace brdfbake
