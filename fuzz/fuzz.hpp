// Shared by the libFuzzer harnesses (docs/RELIABILITY.md, "Sanitizers and fuzzing"). A harness feeds
// one input to a reader through its public entry point; brdfbake::Error (a clear refusal) is the
// expected outcome of most inputs, anything else escaping (another exception, a crash, a sanitizer
// report, a hang) is a finding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "brdfbake/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace brdfbake::fuzz {

inline std::string text(const uint8_t* data, size_t size) { return std::string(reinterpret_cast<const char*>(data), size); }

// Runs `f`, treating brdfbake::Error as the reader's answer; any other exception escapes (libFuzzer
// reports it as a crash with its input).
template <class F>
void expect_answer(F&& f) {
  try {
    f();
  } catch (const brdfbake::Error&) {
  }
}

}  // namespace brdfbake::fuzz
