// Reading float images for `brdfbake view` and the table reader: OpenEXR through the OpenEXR
// library, Radiance RGBE (.hdr) through stb_image. (Environments are read by load_environment,
// brdfbake/environment.hpp.)
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace brdfbake::io {

struct FloatImage {
  int width = 0;
  int height = 0;
  std::vector<std::string> channel_names;  // EXR: as in the file, R G B A first; RGBE: R G B
  std::vector<float> pixels;               // row 0 (the top) first, channels interleaved
  // EXR string attributes, in the file's (alphabetical) order; empty for RGBE.
  std::vector<std::pair<std::string, std::string>> attributes;

  int channels() const { return static_cast<int>(channel_names.size()); }
};

// The data window of an OpenEXR file (scanline or tiled; a tiled, mip-mapped file gives level 0)
// as float. Channels R, G, B, A come first in that order, the others after them alphabetically.
// Throws Error("cannot read '<path>': <reason>").
FloatImage read_exr(const std::string& path);
// A Radiance RGBE file (flat or run-length encoded scanlines), RGB float.
FloatImage read_rgbe(const std::string& path);

}  // namespace brdfbake::io
