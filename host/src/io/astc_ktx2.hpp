// ASTC HDR compression of cubemaps through ARM's astcenc (libastcenc, Debian libastcenc-dev), into
// KTX 2.0 files of VK_FORMAT_ASTC_{4x4,6x6}_SFLOAT_BLOCK (no supercompression). Every face of every
// level is compressed as its own image (blocks never straddle faces), then decompressed again with
// the same codec, so that the error of the stored values is measured, not estimated: it goes into
// the file's key/value data with the rest of the metadata.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "brdfbake/environment.hpp"

namespace brdfbake::io {

// ASTC HDR can hold magnitudes up to the largest half, 65504; larger values are clamped to it
// first (and counted).
inline constexpr double kAstcHdrMax = 65504.0;

struct AstcCube {
  int block = 4;  // 4 or 6 (square blocks)
  uint32_t vk_format = 0;
  std::vector<std::vector<uint8_t>> level_data;  // per level: faces +X..-Z, blocks row-major
  std::vector<std::vector<float>> decoded;       // per level: what a GPU decodes, RGBA float, KTX order
  // Measured on the decoded values against the input, over R, G, B of every texel of the level:
  std::vector<double> max_abs_error;  // max |decoded - input|
  std::vector<double> max_rel_error;  // max |decoded - input| / max(|input|, 1e-6 max|input|)
  std::vector<double> rms_rel_error;  // RMS of the relative error, over texels with input > 0
  size_t clamped = 0;                 // channels beyond kAstcHdrMax, clamped before encoding
};

// Compresses every level of `cube` (alpha ignored; stored as 1). `quality` is astcenc's effort,
// 0..100 (ASTCENC_PRE_FAST 10, MEDIUM 60, THOROUGH 98). Throws Error naming astcenc's message.
AstcCube compress_astc_cube(const CubeLevels& cube, int block, double quality);

// The cube's metadata (as cube_key_values for KTX 2.0) plus the compression's delivered error:
// brdfbake:astc_block, brdfbake:astc_quality, brdfbake:astc_max_abs_error_per_level,
// brdfbake:astc_max_rel_error_per_level, brdfbake:astc_rms_rel_error_per_level,
// brdfbake:astc_clamped_channels.
std::vector<std::pair<std::string, std::string>> astc_key_values(const CubeLevels& cube, const AstcCube& astc,
                                                                 double quality);

// The KTX2 file of a compressed cube, in memory: `astc`'s levels (faces +X..-Z), 6 faces of
// cube.size, and astc_key_values(cube, astc, quality) as its key/value data. `cube` gives the size
// and the metadata only (its levels may be empty: the file's levels are astc.level_data). The one
// assembly of an ASTC KTX2 cube: write_astc_ktx2_cube, the cube delivery (families/delivery.cpp)
// and the engines' KTX2 files (engines/write_common.cpp) all use it.
std::vector<uint8_t> astc_ktx2_bytes(const CubeLevels& cube, const AstcCube& astc, double quality);

// compress_astc_cube + the KTX2 file (astc_ktx2_bytes), written atomically. Returns what was stored and measured.
AstcCube write_astc_ktx2_cube(const CubeLevels& cube, const std::string& path, int block, double quality);

}  // namespace brdfbake::io
