// The encodings of the storage formats, shared by the writers and by the measurement of what a
// file stores (io/storage.hpp), so that the error a file records is the error of its bytes:
//   binary16 (.ktx2 f16, .h f16): round to nearest even, beyond 65504 infinite (io/half.hpp);
//   16-bit UNORM (.png): round(v * 65535) of v clamped to [0, 1];
//   Radiance RGBE (.hdr): Ward's shared exponent of the largest channel, mantissas truncated
//   (Graphics Gems II, "Real Pixels"; what stb_image_write and OpenImageIO write), decoded as
//   m * 2^(e - 136) (stb_image and OpenImageIO read it so).
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

// The largest RGBE value: mantissa 255 under exponent byte 255, (255 / 256) * 2^127.
inline constexpr float kRgbeMax = 0x1.FEp126f;

struct Rgbe {
  uint8_t r = 0, g = 0, b = 0, e = 0;
};
// Negative and NaN channels become 0, values beyond kRgbeMax become kRgbeMax.
inline Rgbe rgbe_encode(float r, float g, float b) {
  auto clean = [](float v) { return v >= 0.0f ? std::min(v, kRgbeMax) : 0.0f; };
  r = clean(r);
  g = clean(g);
  b = clean(b);
  const float m = std::max(r, std::max(g, b));
  if (m < 1e-32f) return {};
  int exponent = 0;
  const float scale = std::frexp(m, &exponent) * 256.0f / m;
  return {static_cast<uint8_t>(std::min(255.0f, r * scale)), static_cast<uint8_t>(std::min(255.0f, g * scale)),
          static_cast<uint8_t>(std::min(255.0f, b * scale)), static_cast<uint8_t>(exponent + 128)};
}
inline void rgbe_decode(const Rgbe& p, float* rgb) {
  if (p.e == 0) {
    rgb[0] = rgb[1] = rgb[2] = 0.0f;
    return;
  }
  const float f = std::ldexp(1.0f, static_cast<int>(p.e) - (128 + 8));
  rgb[0] = static_cast<float>(p.r) * f;
  rgb[1] = static_cast<float>(p.g) * f;
  rgb[2] = static_cast<float>(p.b) * f;
}

}  // namespace brdfbake::io
