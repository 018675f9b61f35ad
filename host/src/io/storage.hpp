// What a table format stores: the values a file holds, decoded as its readers decode them, against
// the float values of the table (io/codecs.hpp encodes exactly as the writers do). The error a file
// records includes this storage error.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "brdfbake/io.hpp"
#include "brdfbake/table.hpp"

namespace brdfbake::io {

struct StorageReport {
  // max over every value of |stored - value| / max(1, |value|): absolute below 1, relative above
  // (the metric of the error bounds; docs/CONVENTIONS.md, "Error bounds").
  double max_error = 0.0;
  std::size_t out_of_range = 0;  // values the format cannot hold: outside [0, 1] in 16-bit PNG,
                                 // beyond 65504 in binary16, negative or NaN in RGBE, non-finite
  double largest = 0.0;          // the largest |value| among them
  std::string encoding;          // e.g. "binary16 (round to nearest even)"
};

StorageReport measure_storage(const Table& table, TableFormat format, PixelType pixel);

// The same for every texel of every level of a cube written with `pixel` texels (containers: RGBA
// binary16 or float32). The error is relative (|stored - value| / max(|value|, tiny)), the metric
// of the chains' bounds.
StorageReport measure_cube_storage(const std::vector<std::vector<float>>& levels, PixelType pixel);

}  // namespace brdfbake::io
