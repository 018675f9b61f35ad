// Cubemap containers: the byte-exact encoders behind write_cubemap (brdfbake/environment.hpp), so
// that the tests can read every header field back from the bytes.
//
//   KTX 1.1   Khronos, "KTX File Format Specification" (version 1.1): 64-byte header, key/value
//             data, then per level UInt32 imageSize (the bytes of ONE face, for a non-array cube)
//             and the six faces, each padded to 4 bytes (cubePadding), the level padded to 4 bytes
//             (mipPadding).
//   DDS       Microsoft, "DDS" programming guide: "DDS " magic, DDS_HEADER (124 bytes), optionally
//             DDS_HEADER_DXT10 (20 bytes), then per face (+X, -X, +Y, -Y, +Z, -Z) every mip level.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "brdfbake/environment.hpp"

namespace brdfbake::io {

// OpenGL enums of KTX 1 headers.
inline constexpr uint32_t kGlHalfFloat = 0x140B;
inline constexpr uint32_t kGlFloat = 0x1406;
inline constexpr uint32_t kGlRgba = 0x1908;
inline constexpr uint32_t kGlRgba16f = 0x881A;
inline constexpr uint32_t kGlRgba32f = 0x8814;

// DDS constants.
inline constexpr uint32_t kDdsMagic = 0x20534444;  // "DDS "
inline constexpr uint32_t kDdsdCaps = 0x1, kDdsdHeight = 0x2, kDdsdWidth = 0x4, kDdsdPitch = 0x8,
                          kDdsdPixelFormat = 0x1000, kDdsdMipMapCount = 0x20000;
inline constexpr uint32_t kDdpfFourCC = 0x4;
inline constexpr uint32_t kDdsCapsComplex = 0x8, kDdsCapsTexture = 0x1000, kDdsCapsMipMap = 0x400000;
inline constexpr uint32_t kDdsCaps2CubemapAllFaces = 0x200 | 0x400 | 0x800 | 0x1000 | 0x2000 | 0x4000 | 0x8000;
inline constexpr uint32_t kFourCCDx10 = 0x30315844;  // "DX10"
inline constexpr uint32_t kD3dFmtA16B16G16R16F = 113;
inline constexpr uint32_t kD3dFmtA32B32G32R32F = 116;
inline constexpr uint32_t kDxgiR16G16B16A16Float = 10;
inline constexpr uint32_t kDxgiR32G32B32A32Float = 2;
inline constexpr uint32_t kD3d10ResourceDimensionTexture2d = 3;
inline constexpr uint32_t kDdsResourceMiscTextureCube = 0x4;

// The texels of a cube (every level) as RGBA half or float, little-endian, KTX order: level, face,
// row, texel.
std::vector<std::vector<uint8_t>> cube_level_bytes(const CubeLevels& cube, PixelType pixel);

std::vector<uint8_t> encode_ktx1_cube(const CubeLevels& cube, PixelType pixel,
                                      const std::vector<std::pair<std::string, std::string>>& key_values);
std::vector<uint8_t> encode_dds_cube(const CubeLevels& cube, PixelType pixel, bool dx10_header);

// The metadata as KTX key/value pairs: "brdfbake:KEY" plus KTXwriter.
std::vector<std::pair<std::string, std::string>> cube_key_values(const CubeLevels& cube);

}  // namespace brdfbake::io
