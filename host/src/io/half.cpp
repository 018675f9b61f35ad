#include "io/half.hpp"

#if defined(__x86_64__) || defined(__i386__)
#include <cpuid.h>
#include <immintrin.h>
#define BRDFBAKE_HAVE_F16C_PATH 1
#endif

namespace brdfbake::io {

namespace {

#ifdef BRDFBAKE_HAVE_F16C_PATH
// Eight values at a time with the F16C instructions (VCVTPS2PH with round to nearest even, the
// rounding Imath's half uses; beyond 65504 infinite; VCVTPH2PS is exact), taken only where the CPU
// has them.
__attribute__((target("avx,f16c"))) void to_half_f16c(const float* in, std::size_t n, uint16_t* out) {
  std::size_t k = 0;
  for (; k + 8 <= n; k += 8) {
    const __m128i h = _mm256_cvtps_ph(_mm256_loadu_ps(in + k), _MM_FROUND_TO_NEAREST_INT);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + k), h);
  }
  for (; k < n; ++k) out[k] = float_to_half_bits(in[k]);
}

__attribute__((target("avx,f16c"))) void from_half_f16c(const uint16_t* in, std::size_t n, float* out) {
  std::size_t k = 0;
  for (; k + 8 <= n; k += 8)
    _mm256_storeu_ps(out + k, _mm256_cvtph_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(in + k))));
  for (; k < n; ++k) out[k] = half_bits_to_float(in[k]);
}

// CPUID leaf 1: ECX bit 29 F16C, bit 28 AVX, bit 27 OSXSAVE; and the OS saves the AVX state (XCR0
// bits 1 and 2). (__builtin_cpu_supports has no "f16c" in clang 14.)
bool cpu_has_f16c() {
  static const bool has = [] {
    unsigned a = 0, b = 0, c = 0, d = 0;
    if (!__get_cpuid(1, &a, &b, &c, &d)) return false;
    const bool f16c = (c >> 29) & 1u, avx = (c >> 28) & 1u, osxsave = (c >> 27) & 1u;
    if (!(f16c && avx && osxsave)) return false;
    unsigned lo = 0, hi = 0;
    __asm__ volatile("xgetbv" : "=a"(lo), "=d"(hi) : "c"(0));
    return (lo & 6u) == 6u;
  }();
  return has;
}
#endif

}  // namespace

void floats_to_half_bits(const float* in, std::size_t n, uint16_t* out) {
#ifdef BRDFBAKE_HAVE_F16C_PATH
  if (cpu_has_f16c()) return to_half_f16c(in, n, out);
#endif
  for (std::size_t k = 0; k < n; ++k) out[k] = float_to_half_bits(in[k]);
}

void half_bits_to_floats(const uint16_t* in, std::size_t n, float* out) {
#ifdef BRDFBAKE_HAVE_F16C_PATH
  if (cpu_has_f16c()) return from_half_f16c(in, n, out);
#endif
  for (std::size_t k = 0; k < n; ++k) out[k] = half_bits_to_float(in[k]);
}

}  // namespace brdfbake::io
