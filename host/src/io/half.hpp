// IEEE 754 binary16 ("half") conversion for the .ktx2 and .h writers, through Imath's half:
// float -> half rounds to nearest even, magnitudes beyond 65504 become infinity, NaN stays NaN;
// half -> float is exact.
#pragma once

#include <Imath/half.h>

#include <cstdint>

namespace brdfbake::io {

inline uint16_t float_to_half_bits(float value) { return Imath::half(value).bits(); }

inline float half_bits_to_float(uint16_t bits) {
  Imath::half value;
  value.setBits(bits);
  return static_cast<float>(value);
}

}  // namespace brdfbake::io
