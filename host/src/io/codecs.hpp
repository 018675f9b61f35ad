// The encodings of the storage formats, shared by the writers and by the measurement of what a
// file stores (io/storage.hpp), so that the error a file records is the error of its bytes:
//   binary16 (.ktx2 f16, .h f16): round to nearest even, beyond 65504 infinite (io/half.hpp);
//   16-bit UNORM (.png): round(v * 65535) of v clamped to [0, 1];
//   Radiance RGBE (.hdr): io/rgbe.hpp's float_to_rgbe / rgbe_to_float, the .hdr writer's own.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "io/half.hpp"

namespace brdfbake::io {

inline float half_round_trip(float v) { return half_bits_to_float(float_to_half_bits(v)); }

inline uint16_t unorm16_encode(float v) {
  const float unit = std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f);
  return static_cast<uint16_t>(std::lround(unit * 65535.0f));
}
inline float unorm16_decode(uint16_t q) { return static_cast<float>(q) / 65535.0f; }

}  // namespace brdfbake::io
