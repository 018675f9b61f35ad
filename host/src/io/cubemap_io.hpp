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
#include <functional>
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
inline constexpr uint32_t kGlRgb = 0x1907;
inline constexpr uint32_t kGlR11fG11fB10f = 0x8C3A;             // GL_R11F_G11F_B10F
inline constexpr uint32_t kGlUnsignedInt10f11f11fRev = 0x8C3B;  // GL_UNSIGNED_INT_10F_11F_11F_REV

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
inline constexpr uint32_t kDxgiR11G11B10Float = 26;
inline constexpr uint32_t kD3d10ResourceDimensionTexture2d = 3;
inline constexpr uint32_t kDdsResourceMiscTextureCube = 0x4;

// The texels of a cube (every level) as RGBA half or float, or packed R11F_G11F_B10F (RGB),
// little-endian, KTX order: level, face, row, texel. `saturated`, when given, counts the channels
// that R11F_G11F_B10F clamped to its largest finite value.
std::vector<std::vector<uint8_t>> cube_level_bytes(const CubeLevels& cube, PixelType pixel, int* saturated = nullptr);
// Level `level` of `cube` in the bytes cube_level_bytes gives it (f16 or f32; R11G11B10 without the
// saturation count), handed to `put` a piece at a time (64 Ki texels): a file streamed from it.
void put_cube_level_bytes(const CubeLevels& cube, int level, PixelType pixel,
                          const std::function<void(const uint8_t*, size_t)>& put);

struct Ktx1Options {
  // R11F_G11F_B10F only. KTX 1.1 wants glType GL_UNSIGNED_INT_10F_11F_11F_REV (0x8C3B); Filament's
  // image::KtxUtility (1.9 to today) maps glType GL_R11F_G11F_B10F (0x8C3A), the value cmgen
  // writes, and no other, to its packed pixel type. true writes Filament's value.
  bool filament_r11_gltype = false;
  int* saturated = nullptr;  // counts channels clamped by R11F_G11F_B10F
};
std::vector<uint8_t> encode_ktx1_cube(const CubeLevels& cube, PixelType pixel,
                                      const std::vector<std::pair<std::string, std::string>>& key_values,
                                      const Ktx1Options& options = {});
std::vector<uint8_t> encode_dds_cube(const CubeLevels& cube, PixelType pixel, bool dx10_header);

// The metadata as KTX key/value pairs: "brdfbake:KEY" for every entry, plus, for KTX 2.0
// (ktx_version 2), KTXwriter and KTXorientation "rd"; for KTX 1.1 (ktx_version 1) only keys KTX 1.1
// defines, KTXorientation "S=r,T=d", and the writer as "brdfbake:writer".
std::vector<std::pair<std::string, std::string>> cube_key_values(const CubeLevels& cube, int ktx_version);
// The same of any metadata.
std::vector<std::pair<std::string, std::string>> metadata_key_values(const Metadata& metadata, int ktx_version);

// write_cubemap with `metadata` written in place of the cube's own: a writer that adds to a cube's
// metadata copies the metadata, not the levels (a 1024^2 chain's are 128 MiB).
void write_cubemap_with_metadata(const CubeLevels& cube, const Metadata& metadata, const std::string& path,
                                 CubeFormat format, const CubeWriteOptions& options);

}  // namespace brdfbake::io
