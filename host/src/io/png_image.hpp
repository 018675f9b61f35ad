// PNG through libpng: a reader for any PNG (the tables brdfbake writes are 16-bit, the contact sheets
// of `brdfbake view` 8-bit), and a writer of 8-bit sRGB RGB images with text chunks for the contact
// sheets. (PNG specification, W3C 2003: "IHDR", "sRGB", "tEXt".)
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace brdfbake::io {

struct PngImage {
  int width = 0;
  int height = 0;
  int channels = 0;   // 1 grey, 2 grey + alpha, 3 RGB, 4 RGBA (palettes are expanded to RGB(A))
  int bit_depth = 8;  // 8 or 16 (1, 2 and 4-bit grey are expanded to 8)
  // Row 0 first, channels interleaved, each sample 0 .. 2^bit_depth - 1.
  std::vector<uint16_t> samples;
  std::vector<std::pair<std::string, std::string>> text;  // tEXt, zTXt and iTXt chunks, in file order

  int max_sample() const { return bit_depth == 16 ? 65535 : 255; }
  uint16_t at(int x, int y, int c) const {
    return samples[(static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) *
                       static_cast<size_t>(channels) +
                   static_cast<size_t>(c)];
  }
};

// Reads a PNG; throws Error("cannot read '<path>': <reason>") for a missing, truncated or corrupt file.
PngImage read_png(const std::string& path);
PngImage decode_png(const std::vector<uint8_t>& bytes, const std::string& origin);

// Encodes an 8-bit RGB image (row 0 first, 3 bytes a pixel) with an sRGB chunk (the values are
// display-referred sRGB) and one tEXt chunk per entry (keys of 1 to 79 Latin-1 characters), at
// zlib's compression `level` (9: the smallest file; a 1600 x 700 sheet takes 0.3 s at 9, a tenth of
// that at 3).
std::vector<uint8_t> encode_png_rgb8(int width, int height, const std::vector<uint8_t>& rgb,
                                     const std::vector<std::pair<std::string, std::string>>& text, int level = 9);
// encode_png_rgb8, written atomically to `path`.
void write_png_rgb8(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb,
                    const std::vector<std::pair<std::string, std::string>>& text, int level = 9);

// The bytes of a regular file of at most 4 GiB (io/special_files.hpp); throws Error naming `what` and the path.
std::vector<uint8_t> read_binary_file(const std::string& path, const std::string& what);

}  // namespace brdfbake::io
