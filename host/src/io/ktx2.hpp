// KTX 2.0 containers (Khronos, "KTX File Format Specification", version 2.0, "KTX2" in the
// comments, with the spec's section names): a writer and a validating reader for uncompressed
// floating-point 1-D and 2-D textures and cubemaps, with mip levels, no supercompression, no arrays
// and no 3-D textures.
//
// Supported formats: VK_FORMAT_R16{,G16{,B16{,A16}}}_SFLOAT,
// VK_FORMAT_R32{,G32{,B32{,A32}}}_SFLOAT, and the ASTC HDR block formats
// VK_FORMAT_ASTC_{4x4,6x6}_SFLOAT_BLOCK. Each is described by one row of a small table (component
// count and size, or block size); the texel (block) size, the typeSize field, the mip alignment
// and the Data Format Descriptor all derive from that row.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace brdfbake::io {

inline constexpr uint32_t kVkFormatR16G16B16A16Sfloat = 97;
inline constexpr uint32_t kVkFormatR32G32B32A32Sfloat = 109;
inline constexpr uint32_t kVkFormatAstc4x4SfloatBlock = 1000066000;  // VK_FORMAT_ASTC_4x4_SFLOAT_BLOCK
inline constexpr uint32_t kVkFormatAstc6x6SfloatBlock = 1000066004;  // VK_FORMAT_ASTC_6x6_SFLOAT_BLOCK

struct Ktx2Image {
  uint32_t vk_format = kVkFormatR16G16B16A16Sfloat;
  uint32_t width = 0;   // pixelWidth of level 0
  uint32_t height = 0;  // pixelHeight of level 0; 0 for a 1-D texture
  uint32_t faces = 1;   // 1, or 6 for a cubemap
  uint32_t levels = 1;  // mip levels stored, level 0 the largest
  // level_data[p] holds mip level p (level 0 first): every face in the order +X, -X, +Y, -Y, +Z,
  // -Z, each face row after row (row 0 first, tightly packed), texels little-endian. Its size must
  // be ktx2_level_size(image, p).
  std::vector<std::vector<uint8_t>> level_data;
  // Metadata. Values are strings: the writer appends the NUL terminator the specification
  // recommends for string values, the reader removes one trailing NUL. The writer sorts entries by
  // key; keys must be unique and non-empty, and a key starting with "KTX"/"ktx" must be one the
  // specification defines (e.g. "KTXwriter", "KTXorientation").
  std::vector<std::pair<std::string, std::string>> key_values;
};

// Whether `vk_format` is one of the supported formats.
bool ktx2_format_supported(uint32_t vk_format);
// Bytes per texel of a supported format; throws brdfbake::Error otherwise.
uint32_t ktx2_texel_size(uint32_t vk_format);
// Bytes of mip level `level`: faces * max(1, width >> level) * max(1, height >> level) * texel
// size, in whole blocks for a block-compressed format.
uint64_t ktx2_level_size(const Ktx2Image& image, uint32_t level);
// The largest valid level count for a width and height: floor(log2(max(width, height))) + 1.
uint32_t ktx2_max_levels(uint32_t width, uint32_t height);

// The complete file. Throws brdfbake::Error when `image` is not a valid texture of this subset.
std::vector<uint8_t> encode_ktx2(const Ktx2Image& image);
// encode_ktx2, written atomically to `path`.
void write_ktx2(const Ktx2Image& image, const std::string& path);
// The same file with each level made as it is written, never whole in memory: `image.level_data`
// is empty and `levels(level, put)` hands level `level`'s bytes to `put` in pieces, in order,
// exactly ktx2_level_size(image, level) of them (else Error, and no file). Levels are asked for
// smallest first, as they lie in the file.
using Ktx2LevelSource =
    std::function<void(uint32_t level, const std::function<void(const uint8_t* data, size_t bytes)>& put)>;
void write_ktx2(const Ktx2Image& image, const std::string& path, const Ktx2LevelSource& levels);

// Parses and validates a file: identifier, header fields, index offsets and lengths, level index,
// mip layout and padding, Data Format Descriptor and key/value data. Throws brdfbake::Error with
// a precise message on anything malformed, truncated or outside the supported subset.
Ktx2Image decode_ktx2(const uint8_t* data, size_t size);
Ktx2Image decode_ktx2(const std::vector<uint8_t>& bytes);
Ktx2Image read_ktx2(const std::string& path);

// `file` (a valid KTX2 file of this subset) with `key_values` set: a key it has already takes the new
// value, the others are added; decoded and encoded again, so the levels are the same bytes (their
// offsets move with the key/value data). Throws brdfbake::Error as decode_ktx2 and encode_ktx2 do.
std::vector<uint8_t> ktx2_with_key_values(const std::vector<uint8_t>& file,
                                          const std::vector<std::pair<std::string, std::string>>& key_values);

}  // namespace brdfbake::io
