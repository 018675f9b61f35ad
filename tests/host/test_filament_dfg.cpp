// Filament's built-in DFG table as the preview's `filament` render computes it
// (host/src/engines/filament_dfg.cpp) against the table Filament 1.76 itself ships: extracted from the
// open3d-cpu 0.20.0 wheel's libOpen3D by tests/engines/filament/setup_open3d.py (which scripts/test.sh
// runs first) into BRDFBAKE_ENGINES_CACHE (default build/engines/) as filament-1.76-dfg.f16. Skips
// with a message where it was not extracted.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "engines/filament_dfg.hpp"
#include "io/half.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;

fs::path shipped_table() {
  const char* cache = std::getenv("BRDFBAKE_ENGINES_CACHE");
  return (cache && *cache ? fs::path(cache) : fs::path(BRDFBAKE_SOURCE_DIR) / "build" / "engines") /
         "filament-1.76-dfg.f16";
}

// Every value within one binary16 step of Filament's: its cmgen sums the same 1024 (4096) Hammersley
// samples in the same order, but its hammersley() and rounding to float before half can move a value
// across a rounding boundary; a step is 2^-11 relative. Most values are identical (measured: 98 %,
// 99.9 %, 98.7 % per channel). A wrong row mapping ((t + 0.5) / 128 instead of (t + 1.5) / 128) moves
// the values by 2.8-3.7 % (about 60 steps), the Estevez-Kulla visibility in z by 20 % and more.
TEST(FilamentDfg, IsTheTableFilament176Ships) {
  const fs::path path = shipped_table();
  if (!fs::is_regular_file(path))
    GTEST_SKIP() << "no " << path << " (python3 tests/engines/filament/setup_open3d.py extracts it from the "
                 << "open3d-cpu 0.20.0 wheel; scripts/test.sh runs it)";
  std::ifstream f(path, std::ios::binary);
  std::vector<uint16_t> raw(128 * 128 * 3);
  f.read(reinterpret_cast<char*>(raw.data()), std::streamsize(raw.size() * 2));
  ASSERT_EQ(f.gcount(), std::streamsize(raw.size() * 2));
  const Table& t = detail::filament_dfg_table();
  ASSERT_EQ(t.width, 128);
  ASSERT_EQ(t.height, 128);
  int identical = 0, off = 0;
  for (int row = 0; row < 128; ++row)
    for (int s = 0; s < 128; ++s)
      for (int c = 0; c < 3; ++c) {
        const uint16_t shipped = raw[(size_t(row) * 128 + size_t(s)) * 3 + size_t(c)];  // [row][column][rgb]
        const uint16_t ours = io::float_to_half_bits(t.at(s, row, c));
        const int steps = std::abs(int(ours) - int(shipped));
        identical += steps == 0;
        if (steps > 1) {
          if (++off < 10)
            ADD_FAILURE() << "row " << row << " column " << s << " channel " << c << ": ours "
                          << io::half_bits_to_float(ours) << ", Filament's " << io::half_bits_to_float(shipped);
        }
      }
  EXPECT_EQ(off, 0);
  EXPECT_GT(identical, 128 * 128 * 3 * 95 / 100) << "most values are Filament's to the bit";
}

}  // namespace
}  // namespace brdfbake
