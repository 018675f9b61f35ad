// A reader of DDS files (Microsoft, "DDS" programming guide: DDS_HEADER, DDS_PIXELFORMAT,
// DDS_HEADER_DXT10): uncompressed RGBA half or float 2-D textures and cubemaps with mip levels, with
// the DX10 header (DXGI_FORMAT_R16G16B16A16_FLOAT / R32G32B32A32_FLOAT) or the legacy one
// (D3DFMT_A16B16G16R16F = 113 / A32B32G32R32F = 116), as the cube writer (io/cubemap_io.hpp) writes
// them. No arrays, volumes or block-compressed formats.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace brdfbake::io {

struct DdsImage {
  uint32_t width = 0, height = 0;  // of level 0
  uint32_t faces = 1;              // 1 or 6
  uint32_t levels = 1;
  uint32_t component_bytes = 2;  // 2 (half) or 4 (float); always four components (RGBA)
  bool dx10_header = false;
  // level_data[l]: every face of level l in KTX order (+X, -X, +Y, -Y, +Z, -Z; DDS stores each face
  // with all its levels, this is reordered), row 0 first, little-endian components.
  std::vector<std::vector<uint8_t>> level_data;
};

// Parses and validates; throws Error("invalid DDS file '<origin>': <reason>").
DdsImage decode_dds(const uint8_t* data, size_t size, const std::string& origin);
DdsImage read_dds(const std::string& path);

}  // namespace brdfbake::io
