// MERL BRDF binaries (decode_merl: the header, the size, every value) and the MERL lookup of
// arbitrary directions (merl_index: NaN, infinities and zero vectors must be refused, never turned
// into an out-of-range bin or an int conversion of a NaN).
#include <cstring>

#include "fuzz.hpp"
#include "io/merl.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace brdfbake;
  fuzz::expect_answer([&] { (void)decode_merl(fuzz::text(data, size), "fuzz.binary"); });
  if (size >= 6 * sizeof(double)) {
    double v[6];
    std::memcpy(v, data, sizeof v);
    fuzz::expect_answer([&] {
      const std::size_t bin = io::merl_index({v[0], v[1], v[2]}, {v[3], v[4], v[5]});
      if (bin >= kMerlBins) __builtin_trap();
    });
  }
  return 0;
}
