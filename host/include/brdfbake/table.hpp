// A baked table: a 1-D or 2-D grid of float texels with named channels, the coordinates of its
// cells and the metadata that every output file records.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace brdfbake {

// Ordered key/value pairs, written as EXR/PNG attributes, KTX2 key-values, CSV '#' lines, the
// comment block of a C header, or a sidecar JSON where the format has no metadata of its own.
using Metadata = std::vector<std::pair<std::string, std::string>>;

struct Table {
  int width = 0;                      // cells along x (n_dot_v for the DFG tables)
  int height = 1;                     // cells along y (roughness); 1 for a 1-D table
  std::vector<std::string> channels;  // channel names, e.g. {"scale", "bias", "diffuse"}
  std::string x_name;                 // CSV column of x, e.g. "n_dot_v"
  std::string y_name;                 // CSV column of y, e.g. "roughness"; empty for 1-D tables
  std::vector<double> x;              // x coordinate of each column, size width
  std::vector<double> y;              // y coordinate of each row, size height (empty for 1-D)
  std::vector<float> data;            // row-major, y outer, channels interleaved
  Metadata metadata;

  int channel_count() const { return static_cast<int>(channels.size()); }
  float& at(int i, int j, int c) {
    return data[(static_cast<size_t>(j) * static_cast<size_t>(width) + static_cast<size_t>(i)) * channels.size() +
                static_cast<size_t>(c)];
  }
  float at(int i, int j, int c) const {
    return data[(static_cast<size_t>(j) * static_cast<size_t>(width) + static_cast<size_t>(i)) * channels.size() +
                static_cast<size_t>(c)];
  }
  // Sets or replaces a metadata entry.
  void set_meta(const std::string& key, const std::string& value);
  // The value of a metadata entry, or "" when absent.
  std::string meta(const std::string& key) const;
};

}  // namespace brdfbake
