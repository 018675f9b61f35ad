// What an image file may make the reader allocate (docs/RELIABILITY.md, "Untrusted input"): every
// reader checks the header's promise against these before any pixel buffer exists. Header-only: the
// OpenImageIO module (a separate shared object) uses it too.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

namespace brdfbake::io {

struct ImageLimits {
  uint64_t max_pixels = uint64_t(1) << 28;  // 16384 x 16384
  // The memory the decoded image may take (float32, every channel, every copy the reader makes);
  // 0: no limit beyond max_pixels. Callers pass the memory budget (--memory-budget).
  uint64_t max_bytes = 0;
};

inline std::string mib_text(uint64_t bytes) {
  char b[48];
  std::snprintf(b, sizeof b, bytes >= (uint64_t(1) << 30) ? "%.1f GiB" : "%.1f MiB",
                double(bytes) / double(bytes >= (uint64_t(1) << 30) ? (uint64_t(1) << 30) : (uint64_t(1) << 20)));
  return b;
}

// Why a w x h image of `channels` channels, decoded into `copies` float buffers, breaks `limits`
// (empty: it does not).
inline std::string image_limits_problem(uint64_t w, uint64_t h, uint64_t channels, uint64_t copies,
                                        const ImageLimits& limits) {
  if (w * h > limits.max_pixels) return "too large (" + std::to_string(w) + "x" + std::to_string(h) + ")";
  const uint64_t need = w * h * channels * 4 * copies;
  if (limits.max_bytes > 0 && need > limits.max_bytes)
    return "the header promises " + std::to_string(w) + "x" + std::to_string(h) + " pixels of " +
           std::to_string(channels) + " channel(s), " + mib_text(need) + " decoded, above the memory budget of " +
           mib_text(limits.max_bytes) + " (--memory-budget)";
  return {};
}

}  // namespace brdfbake::io
