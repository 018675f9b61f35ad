#include "runtime/stderr_capture.hpp"

#include <unistd.h>

#include <cstdio>
#include <mutex>

namespace brdfbake::detail {

namespace {
std::mutex g_capture_mutex;

// Restores fd 2 when the capture ends, exception or not.
class Redirect {
 public:
  Redirect() {
    std::fflush(stderr);
    file_ = std::tmpfile();
    if (!file_) return;
    saved_ = ::dup(2);
    if (saved_ < 0 || ::dup2(::fileno(file_), 2) < 0) {
      if (saved_ >= 0) ::close(saved_);
      saved_ = -1;
    }
  }
  ~Redirect() {
    restore();
    if (file_) std::fclose(file_);
  }
  Redirect(const Redirect&) = delete;
  Redirect& operator=(const Redirect&) = delete;

  void restore() {
    if (saved_ < 0) return;
    std::fflush(stderr);
    ::dup2(saved_, 2);
    ::close(saved_);
    saved_ = -1;
  }
  std::string text() {
    if (!file_) return {};
    std::string out;
    std::rewind(file_);
    char buf[4096];
    size_t n = 0;
    while ((n = std::fread(buf, 1, sizeof buf, file_)) > 0 && out.size() < (1u << 20)) out.append(buf, n);
    return out;
  }

 private:
  std::FILE* file_ = nullptr;
  int saved_ = -1;
};
}  // namespace

std::string run_with_stderr_captured(const std::function<void()>& fn) {
  std::lock_guard<std::mutex> lock(g_capture_mutex);
  Redirect redirect;  // when no temporary file can be made, fn runs uncaptured
  fn();
  redirect.restore();
  return redirect.text();
}

}  // namespace brdfbake::detail
