// A reader of KTX 1.1 files (Khronos, "KTX File Format Specification", version 1.1): uncompressed
// RGB/RGBA half or float 2-D textures and cubemaps with mip levels, as the cube writer
// (io/cubemap_io.hpp) and Filament's cmgen write them. No arrays, no 3-D textures, no compressed
// formats.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace brdfbake::io {

struct Ktx1Image {
  uint32_t gl_type = 0;    // GL_HALF_FLOAT or GL_FLOAT
  uint32_t gl_format = 0;  // GL_RGB or GL_RGBA
  uint32_t gl_internal_format = 0;
  uint32_t width = 0, height = 0;  // of level 0
  uint32_t faces = 1;              // 1 or 6
  uint32_t levels = 1;
  // level_data[l]: every face of level l (+X, -X, +Y, -Y, +Z, -Z), row 0 first, rows tightly packed
  // (the file's 4-byte row alignment removed), little-endian components.
  std::vector<std::vector<uint8_t>> level_data;
  std::vector<std::pair<std::string, std::string>> key_values;  // values without their trailing NUL

  uint32_t components() const;       // 3 or 4
  uint32_t component_bytes() const;  // 2 or 4
};

// Parses and validates; throws Error("invalid KTX file '<origin>': <reason>") for anything
// malformed, truncated or outside the supported subset (big-endian files included).
Ktx1Image decode_ktx1(const uint8_t* data, size_t size, const std::string& origin);
Ktx1Image read_ktx1(const std::string& path);

// `file` (a KTX 1.1 file, any glType: the packed R11F_G11F_B10F too) with `key_values` set in its
// key/value data: a key it has already takes the new value in place, the others are appended. Only
// the key/value data and bytesOfKeyValueData change; the image data is copied as it is. Throws
// Error("invalid KTX file '<origin>': ...") for a header or key/value data it cannot parse.
std::vector<uint8_t> ktx1_with_key_values(const std::vector<uint8_t>& file,
                                          const std::vector<std::pair<std::string, std::string>>& key_values,
                                          const std::string& origin);

}  // namespace brdfbake::io
