#include "brdfbake/math/sampling.hpp"

namespace brdfbake::math {

// Mirror the 32 bits by swapping halves, then bytes, nibbles, pairs and single bits (Warren,
// "Hacker's Delight", 7-1), and scale by 2^-32.
double radical_inverse_base2(std::uint32_t i) {
  i = (i << 16) | (i >> 16);
  i = ((i & 0x00FF00FFu) << 8) | ((i & 0xFF00FF00u) >> 8);
  i = ((i & 0x0F0F0F0Fu) << 4) | ((i & 0xF0F0F0F0u) >> 4);
  i = ((i & 0x33333333u) << 2) | ((i & 0xCCCCCCCCu) >> 2);
  i = ((i & 0x55555555u) << 1) | ((i & 0xAAAAAAAAu) >> 1);
  return static_cast<double>(i) * 2.3283064365386963e-10;  // 2^-32
}

Point2 hammersley(std::uint32_t k, std::uint32_t n) {
  return {(static_cast<double>(k) + 0.5) / static_cast<double>(n), radical_inverse_base2(k)};
}

}  // namespace brdfbake::math
