#include "brdfbake/cancel.hpp"

#include <atomic>
#include <csignal>

namespace brdfbake {

namespace {
// Lock-free, so that a signal handler may store to it.
std::atomic<int> g_requested{0};  // 0: none; else the signal number + 1
static_assert(std::atomic<int>::is_always_lock_free);
}  // namespace

void request_cancel(int signal) noexcept { g_requested.store(signal + 1, std::memory_order_relaxed); }

bool cancel_requested() noexcept { return g_requested.load(std::memory_order_relaxed) != 0; }

int cancel_signal() noexcept {
  const int v = g_requested.load(std::memory_order_relaxed);
  return v > 0 ? v - 1 : 0;
}

void reset_cancel() noexcept { g_requested.store(0, std::memory_order_relaxed); }

void throw_if_cancelled() {
  if (!cancel_requested()) return;
  const int s = cancel_signal();
  const std::string name = s == SIGINT    ? "SIGINT"
                           : s == SIGTERM ? "SIGTERM"
                           : s == SIGHUP  ? "SIGHUP"
                           : s == SIGPIPE ? "SIGPIPE (the reader of the output went away)"
                           : s            ? "signal " + std::to_string(s)
                                          : "";
  throw Cancelled(
      (name.empty() ? std::string("cancelled") : "interrupted by " + name) + " (unfinished outputs were removed)", s);
}

}  // namespace brdfbake
