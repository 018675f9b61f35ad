// GL_R11F_G11F_B10F encoding (see packed_float.hpp for the format and the rounding).
#include "io/packed_float.hpp"

#include <algorithm>
#include <cmath>

namespace brdfbake::io {
namespace {

constexpr int kExponentBias = 15;
constexpr int kMaxFiniteExponentField = 30;  // 31 is infinity / NaN

// Round to nearest, ties to even, independent of the current rounding mode.
double round_half_even(double x) {
  const double f = std::floor(x);
  const double d = x - f;
  if (d > 0.5) return f + 1.0;
  if (d < 0.5) return f;
  return std::fmod(f, 2.0) == 0.0 ? f : f + 1.0;
}

}  // namespace

uint32_t encode_unsigned_float(double value, int mantissa_bits, bool* saturated) {
  if (saturated) *saturated = false;
  if (!(value > 0.0)) return 0;  // negative, zero, -0 and NaN
  const uint32_t max_code = (uint32_t(kMaxFiniteExponentField) << mantissa_bits) | ((1u << mantissa_bits) - 1u);
  const double max_value = decode_unsigned_float(max_code, mantissa_bits);
  if (value >= max_value) {
    if (saturated) *saturated = value > max_value;
    return max_code;
  }
  int e = 0;
  std::frexp(value, &e);  // value = f 2^e, f in [0.5, 1): the unbiased exponent is e - 1
  const int exponent = e - 1;
  uint32_t code = 0;
  if (exponent < 1 - kExponentBias) {
    // Denormal: value = mantissa 2^(1 - bias - m). Rounding up to 2^m carries into the exponent
    // field as the smallest normal, which the integer code represents by itself.
    code = uint32_t(round_half_even(std::ldexp(value, kExponentBias - 1 + mantissa_bits)));
  } else {
    // Normal: value = (1 + mantissa 2^-m) 2^exponent; a mantissa that rounds up to 2^m carries
    // into the exponent field (the next binade), again exactly as the integer code adds up.
    const double mantissa = round_half_even((std::ldexp(value, -exponent) - 1.0) * double(1u << mantissa_bits));
    code = (uint32_t(exponent + kExponentBias) << mantissa_bits) + uint32_t(mantissa);
  }
  return code > max_code ? max_code : code;
}

double decode_unsigned_float(uint32_t code, int mantissa_bits) {
  const uint32_t exponent = code >> mantissa_bits;
  const uint32_t mantissa = code & ((1u << mantissa_bits) - 1u);
  if (exponent == 0) return std::ldexp(double(mantissa), 1 - kExponentBias - mantissa_bits);
  if (exponent == 31) return mantissa == 0 ? HUGE_VAL : std::nan("");
  return std::ldexp(1.0 + std::ldexp(double(mantissa), -mantissa_bits), int(exponent) - kExponentBias);
}

uint32_t pack_r11g11b10(float r, float g, float b, int* saturated) {
  bool sr = false, sg = false, sb = false;
  const uint32_t cr = encode_unsigned_float(r, kUf11MantissaBits, &sr);
  const uint32_t cg = encode_unsigned_float(g, kUf11MantissaBits, &sg);
  const uint32_t cb = encode_unsigned_float(b, kUf10MantissaBits, &sb);
  if (saturated) *saturated += int(sr) + int(sg) + int(sb);
  return cr | cg << 11 | cb << 22;
}

void unpack_r11g11b10(uint32_t packed, float rgb[3]) {
  // Every code of both widths decoded once (3,072 floats): the same values as decode_unsigned_float,
  // without its two ldexp calls a channel (a 256^2 chain is 1.2 M channels: 20 ms of a preview).
  struct Tables {
    float uf11[1u << 11], uf10[1u << 10];
    Tables() {
      for (uint32_t c = 0; c < (1u << 11); ++c) uf11[c] = float(decode_unsigned_float(c, kUf11MantissaBits));
      for (uint32_t c = 0; c < (1u << 10); ++c) uf10[c] = float(decode_unsigned_float(c, kUf10MantissaBits));
    }
  };
  static const Tables t;
  rgb[0] = t.uf11[packed & 0x7FFu];
  rgb[1] = t.uf11[(packed >> 11) & 0x7FFu];
  rgb[2] = t.uf10[packed >> 22];
}

double unsigned_float_half_ulp(double value, int mantissa_bits) {
  const double v = std::fabs(value);
  int e = 0;
  std::frexp(v, &e);
  const int exponent = v > 0.0 ? std::max(e - 1, 1 - kExponentBias) : 1 - kExponentBias;
  return std::ldexp(0.5, exponent - mantissa_bits);
}

}  // namespace brdfbake::io
