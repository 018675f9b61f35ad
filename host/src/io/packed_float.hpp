// OpenGL's packed unsigned floats GL_R11F_G11F_B10F (OpenGL 4.6 core, section 2.3.4.3
// "Unsigned 11-Bit Floating-Point Numbers" and 2.3.4.4 "Unsigned 10-Bit Floating-Point
// Numbers"; the packing of GL_UNSIGNED_INT_10F_11F_11F_REV, table 8.8): R in bits 0-10, G in bits
// 11-21, B in bits 22-31 of a little-endian UInt32. Each is a 5-bit exponent (bias 15) over a 6-bit
// (R, G) or 5-bit (B) mantissa, with no sign bit, denormals below 2^-14, and exponent 31 reserved
// for infinity and NaN.
//
// The encoder rounds to nearest, ties to even (the same rounding as float -> half), and never
// produces infinity or NaN: values at or beyond the largest finite value (65024 for 11 bits, 64512
// for 10 bits) are stored as that value, negative values and -0 as 0, NaN as 0 (environments are
// validated before baking, so NaN never reaches the writer; the guard keeps a file free of it
// regardless). The decoder is exact.
#pragma once

#include <cstdint>

namespace brdfbake::io {

// Mantissa widths of the two unsigned float formats.
inline constexpr int kUf11MantissaBits = 6;
inline constexpr int kUf10MantissaBits = 5;

// The largest finite values: (2 - 2^-m) * 2^15.
inline constexpr double kUf11Max = 65024.0;
inline constexpr double kUf10Max = 64512.0;

// One channel: the (5 + mantissa_bits)-bit code of `value`, rounded to nearest even and saturated
// as above. `saturated`, when given, is set when the value was beyond the largest finite value.
uint32_t encode_unsigned_float(double value, int mantissa_bits, bool* saturated = nullptr);
double decode_unsigned_float(uint32_t code, int mantissa_bits);

// A whole texel, packed as GL_UNSIGNED_INT_10F_11F_11F_REV; `saturated` counts channels clamped.
uint32_t pack_r11g11b10(float r, float g, float b, int* saturated = nullptr);
void unpack_r11g11b10(uint32_t packed, float rgb[3]);

// Half the spacing of representable values around `value`: the largest rounding error of the
// format there (the channel's relative precision is 2^-(m+1), 1/128 for 11 bits, 1/64 for 10).
double unsigned_float_half_ulp(double value, int mantissa_bits);

}  // namespace brdfbake::io
