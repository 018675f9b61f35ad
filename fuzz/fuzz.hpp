// Shared by the libFuzzer harnesses (docs/RELIABILITY.md, "Sanitizers and fuzzing"). A harness feeds
// one input to a reader through its public entry point; brdfbake::Error (a clear refusal) is the
// expected outcome of most inputs, anything else escaping (another exception, a crash, a sanitizer
// report, a hang) is a finding.
//
// Only the reader's own call may refuse: what a harness then checks on an accepted input (it
// validates, prints, round-trips) runs outside the refusal wrapper, through `invariant` and
// `require`, so that a broken invariant aborts, brdfbake::Error included, rather than passing as
// one more refused input.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <optional>
#include <string>
#include <system_error>
#include <utility>

#include "brdfbake/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace brdfbake::fuzz {

// A folder of this process under the temporary folder ($TMPDIR/brdfbake-fuzz-NAME-PID), made on the
// first call and removed with what it holds when the process exits (the corpus replay is a test:
// it leaves nothing in $TMPDIR, issue 34). One name a harness: the first call's name is kept.
inline const std::filesystem::path& scratch_dir(const std::string& name) {
  static const struct Folder {
    std::filesystem::path path;
    explicit Folder(const std::string& n)
        : path(std::filesystem::temp_directory_path() / ("brdfbake-fuzz-" + n + "-" + std::to_string(::getpid()))) {
      std::filesystem::create_directories(path);
    }
    ~Folder() {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  } folder(name);
  return folder.path;
}

inline std::string text(const uint8_t* data, size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// Runs `f`, treating brdfbake::Error as the reader's answer; any other exception escapes (libFuzzer
// reports it as a crash with its input).
template <class F>
void expect_answer(F&& f) {
  try {
    f();
  } catch (const brdfbake::Error&) {
  }
}

// Runs the reader `f`: its result when it accepts the input, nothing when it refuses it with
// brdfbake::Error; any other exception escapes.
template <class F>
auto accepted(F&& f) -> std::optional<decltype(f())> {
  try {
    return f();
  } catch (const brdfbake::Error&) {
    return std::nullopt;
  }
}

// A finding: names the broken invariant on stderr and aborts (libFuzzer saves the input; the
// replay's ctest fails).
[[noreturn]] inline void broken(const char* what, const std::string& detail = {}) {
  std::fprintf(stderr, "fuzz invariant broken: %s%s%s\n", what, detail.empty() ? "" : ": ", detail.c_str());
  std::abort();
}

// A check on an accepted input.
inline void require(bool ok, const char* what) {
  if (!ok) broken(what);
}

// Runs `f`, a step that must succeed on an accepted input: any exception, brdfbake::Error
// included, is a finding.
template <class F>
void invariant(const char* what, F&& f) {
  try {
    std::forward<F>(f)();
  } catch (const std::exception& e) {
    broken(what, e.what());
  } catch (...) {
    broken(what, "a non-standard exception");
  }
}

}  // namespace brdfbake::fuzz
