// Reading a table the command-line tool wrote back (host/src/io/table_read.hpp) and holding it to
// the same table written as CSV: the shape, the channels, every value within what the format keeps
// (tolerances.hpp), and the metadata every output records. Used by the format tests of the table
// commands, which would otherwise check only that a file exists.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "brdfbake/error_figures.hpp"
#include "brdfbake/table.hpp"
#include "io/table_read.hpp"
#include "support/tolerances.hpp"

namespace brdfbake::test {

// The largest difference a value `want` may show after a round trip through the format of
// `path`'s extension, in a table whose largest magnitude is `largest`.
inline double table_format_tolerance(const std::string& path, double want, double largest) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".png") return kPng16Step * std::max(1.0, largest);
  if (ext == ".hdr") return kRgbeStepOfLargest * largest;
  if (ext == ".ktx2" || ext == ".h") return kBinary16Rounding * std::fabs(want) + kBinary16Subnormal;
  return 0.0;  // .exr (float32) and .csv (9 significant digits) keep every float
}

// Reads `path` back and compares it with `want` (the same table read from the command's CSV): the
// values, the recorded error bound, and every metadata key of `keys` (equal to want's).
inline void expect_table_file(const std::string& path, const Table& want, const std::vector<std::string>& keys) {
  SCOPED_TRACE(path);
  Table got;
  try {
    got = io::read_table(path);
  } catch (const std::exception& e) {
    ADD_FAILURE() << e.what();
    return;
  }
  ASSERT_EQ(got.width, want.width);
  ASSERT_EQ(got.height, want.height);
  EXPECT_EQ(got.channels, want.channels);
  ASSERT_EQ(got.data.size(), want.data.size());
  double largest = 0.0;
  for (float v : want.data) largest = std::max(largest, double(std::fabs(v)));
  ASSERT_GT(largest, 0.0) << "an all-zero table checks nothing";
  double worst = 0.0;  // as error bounds count: absolute below 1, relative above
  for (size_t k = 0; k < want.data.size(); ++k) {
    EXPECT_NEAR(got.data[k], want.data[k], table_format_tolerance(path, want.data[k], largest)) << "value " << k;
    worst = std::max(
        worst, std::fabs(double(got.data[k]) - double(want.data[k])) / std::max(1.0, std::fabs(double(want.data[k]))));
  }
  // The bound a file records covers its own storage (the delivered error, docs/BENCHMARKS.md): at least the
  // CSV's, and with it every difference between the two files.
  if (!want.meta("error_bound").empty()) {
    const double bound = std::stod(want.meta("error_bound"));
    // the file records it under its kind's name (brdfbake/error_figures.hpp)
    const auto figure = error_figure_value(got.metadata);
    ASSERT_TRUE(figure.has_value());
    EXPECT_NE(figure->first, kLegacyErrorBoundName);
    const double recorded = std::stod(figure->second);
    EXPECT_GE(recorded, bound);
    EXPECT_LE(worst, recorded + bound) << "the file differs from the CSV by more than their two bounds";
  }
  for (const std::string& key : keys) {
    EXPECT_NE(want.meta(key), "") << key;
    EXPECT_EQ(got.meta(key), want.meta(key)) << key;
  }
}

}  // namespace brdfbake::test
