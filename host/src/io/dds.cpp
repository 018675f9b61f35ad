// DDS reader. Layout: "DDS " magic, DDS_HEADER (124 bytes: dwSize, dwFlags, dwHeight, dwWidth,
// dwPitchOrLinearSize, dwDepth, dwMipMapCount, dwReserved1[11], DDS_PIXELFORMAT (32 bytes: dwSize,
// dwFlags, dwFourCC, dwRGBBitCount, four masks), dwCaps, dwCaps2, dwCaps3, dwCaps4, dwReserved2),
// then DDS_HEADER_DXT10 (20 bytes: dxgiFormat, resourceDimension, miscFlag, arraySize, miscFlags2)
// when dwFourCC is "DX10", then the data: each face with its whole mip chain, face after face.
#include "io/dds.hpp"

#include <algorithm>

#include "brdfbake/error.hpp"
#include "io/cubemap_io.hpp"
#include "io/png_image.hpp"

namespace brdfbake::io {

DdsImage decode_dds(const uint8_t* data, size_t size, const std::string& origin) {
  auto fail = [&](const std::string& why) -> Error { return Error("invalid DDS file '" + origin + "': " + why); };
  auto u32 = [&](size_t at) {
    return uint32_t(data[at]) | uint32_t(data[at + 1]) << 8 | uint32_t(data[at + 2]) << 16 |
           uint32_t(data[at + 3]) << 24;
  };
  if (size < 128 || u32(0) != kDdsMagic) throw fail("not a DDS file (bad magic)");
  if (u32(4) != 124 || u32(76) != 32) throw fail("bad header size");
  const uint32_t flags = u32(8);
  DdsImage d;
  d.height = u32(12);
  d.width = u32(16);
  d.levels = (flags & kDdsdMipMapCount) ? std::max<uint32_t>(1, u32(28)) : 1;
  const uint32_t pf_flags = u32(80), four_cc = u32(84);
  const uint32_t caps2 = u32(112);
  size_t at = 128;
  bool cube = (caps2 & kDdsCaps2CubemapAllFaces) == kDdsCaps2CubemapAllFaces;
  if (!(pf_flags & kDdpfFourCC)) throw fail("only floating-point RGBA formats are supported (no FourCC)");
  if (four_cc == kFourCCDx10) {
    if (size < 148) throw fail("the DX10 header is truncated");
    d.dx10_header = true;
    const uint32_t dxgi = u32(128), dimension = u32(132), misc = u32(136), array = u32(140);
    if (dxgi == kDxgiR16G16B16A16Float)
      d.component_bytes = 2;
    else if (dxgi == kDxgiR32G32B32A32Float)
      d.component_bytes = 4;
    else
      throw fail("DXGI format " + std::to_string(dxgi) +
                 " is not supported (expected R16G16B16A16_FLOAT or R32G32B32A32_FLOAT)");
    if (dimension != kD3d10ResourceDimensionTexture2d) throw fail("only 2-D textures and cubemaps are supported");
    if (array > 1) throw fail("texture arrays are not supported");
    cube = cube || (misc & kDdsResourceMiscTextureCube);
    at = 148;
  } else if (four_cc == kD3dFmtA16B16G16R16F) {
    d.component_bytes = 2;
  } else if (four_cc == kD3dFmtA32B32G32R32F) {
    d.component_bytes = 4;
  } else {
    throw fail("FourCC " + std::to_string(four_cc) + " is not supported (expected DX10, 113 or 116)");
  }
  d.faces = cube ? 6 : 1;
  if (d.width == 0 || d.height == 0 || d.width > 65536 || d.height > 65536) throw fail("unsupported size");
  if (cube && d.width != d.height) throw fail("cube faces are not square");
  uint32_t max_levels = 1;
  while ((std::max(d.width, d.height) >> max_levels) > 0) ++max_levels;
  if (d.levels > max_levels) throw fail("dwMipMapCount " + std::to_string(d.levels) + " is too large");

  const size_t texel = 4u * d.component_bytes;
  std::vector<size_t> level_bytes(d.levels);
  size_t face_chain = 0;
  for (uint32_t l = 0; l < d.levels; ++l) {
    level_bytes[l] = size_t(std::max<uint32_t>(1, d.width >> l)) * std::max<uint32_t>(1, d.height >> l) * texel;
    face_chain += level_bytes[l];
  }
  if (size - at < face_chain * d.faces) throw fail("the data is truncated");
  d.level_data.resize(d.levels);
  for (uint32_t f = 0; f < d.faces; ++f)
    for (uint32_t l = 0; l < d.levels; ++l) {
      d.level_data[l].insert(d.level_data[l].end(), data + at, data + at + level_bytes[l]);
      at += level_bytes[l];
    }
  return d;
}

DdsImage read_dds(const std::string& path) {
  const std::vector<uint8_t> bytes = read_binary_file(path, "DDS file");
  return decode_dds(bytes.data(), bytes.size(), path);
}

}  // namespace brdfbake::io
