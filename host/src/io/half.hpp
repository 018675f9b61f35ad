// IEEE 754 binary16 ("half") conversion for the .ktx2 and .h writers, through Imath's half:
// float -> half rounds to nearest even, magnitudes beyond 65504 become infinity, NaN stays NaN;
// half -> float is exact.
#pragma once

#include <Imath/half.h>

#include <cstddef>
#include <cstdint>

namespace brdfbake::io {

inline uint16_t float_to_half_bits(float value) { return Imath::half(value).bits(); }

inline float half_bits_to_float(uint16_t bits) {
  Imath::half value;
  value.setBits(bits);
  return static_cast<float>(value);
}

// The same conversions over arrays (io/half.cpp): with the CPU's F16C instructions where it has
// them, giving the same bits as the scalar functions above.
void floats_to_half_bits(const float* in, std::size_t n, uint16_t* out);
void half_bits_to_floats(const uint16_t* in, std::size_t n, float* out);

}  // namespace brdfbake::io
