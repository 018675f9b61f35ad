// KTX 2.0 writer and reader. Quoted section names refer to the KTX File Format Specification 2.0
// ("KTX2") and to the Khronos Data Format Specification ("KDF"; 1.3 and 1.4 alike, descriptor
// versionNumber 2), which defines the Data Format Descriptor that KTX2 embeds.
//
// File layout written here (KTX2 "File Structure"), all integers little-endian:
//
//   0   identifier            12 bytes  «KTX 20»\r\n\x1A\n
//   12  header                 9 x UInt32  vkFormat typeSize pixelWidth pixelHeight pixelDepth
//                                          layerCount faceCount levelCount supercompressionScheme
//   48  index                  UInt32 dfdByteOffset dfdByteLength kvdByteOffset kvdByteLength,
//                              UInt64 sgdByteOffset sgdByteLength
//   80  level index            levelCount x UInt64 {byteOffset, byteLength,
//                              uncompressedByteLength}, level 0 (the largest) first
//       Data Format Descriptor UInt32 dfdTotalSize + one basic descriptor block
//       key/value data         sorted entries, each padded to 4 bytes
//       mip level array        smallest level first; each level preceded by mipPadding so that it
//                              starts at a multiple of lcm(texel block size, 4) (KTX2 "mipPadding")
//
// No supercompression means no supercompression global data: sgdByteOffset = sgdByteLength = 0,
// and byteLength = uncompressedByteLength for every level.
#include "io/ktx2.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <numeric>
#include <string_view>
#include <system_error>

#include "brdfbake/cancel.hpp"
#include "brdfbake/error.hpp"
#include "io/atomic_file.hpp"
#include "io/special_files.hpp"

namespace brdfbake::io {
namespace {

// KTX2 "identifier".
constexpr uint8_t kIdentifier[12] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
// The KTX 1.1 identifier, only to name the problem when a reader is handed such a file.
constexpr uint8_t kIdentifierKtx1[12] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x31, 0x31, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};

// Byte offsets of the header and index fields (KTX2 "File Structure").
constexpr size_t kOffsetVkFormat = 12;
constexpr size_t kOffsetTypeSize = 16;
constexpr size_t kOffsetPixelWidth = 20;
constexpr size_t kOffsetPixelHeight = 24;
constexpr size_t kOffsetPixelDepth = 28;
constexpr size_t kOffsetLayerCount = 32;
constexpr size_t kOffsetFaceCount = 36;
constexpr size_t kOffsetLevelCount = 40;
constexpr size_t kOffsetSupercompressionScheme = 44;
constexpr size_t kOffsetDfdByteOffset = 48;
constexpr size_t kOffsetDfdByteLength = 52;
constexpr size_t kOffsetKvdByteOffset = 56;
constexpr size_t kOffsetKvdByteLength = 60;
constexpr size_t kOffsetSgdByteOffset = 64;
constexpr size_t kOffsetSgdByteLength = 72;
constexpr size_t kLevelIndexOffset = 80;
constexpr size_t kLevelIndexEntrySize = 24;

// One row per supported format; everything format-specific derives from it.
struct Format {
  uint32_t vk_format;
  const char* name;
  uint32_t components;       // R, G, B, A in this order, tightly packed; 0: block-compressed
  uint32_t component_bytes;  // 2: IEEE binary16, 4: IEEE binary32; 0: block-compressed
  uint32_t block_width = 1;  // texel block (KDF texelBlockDimension); 1 x 1 when uncompressed
  uint32_t block_height = 1;
  uint32_t block_bytes = 0;  // bytes of one compressed block (ASTC: 16)
};

// ASTC HDR (VK_EXT_texture_compression_astc_hdr, core in Vulkan 1.3): 128-bit blocks.
constexpr Format kFormats[] = {
    {76, "VK_FORMAT_R16_SFLOAT", 1, 2},
    {83, "VK_FORMAT_R16G16_SFLOAT", 2, 2},
    {90, "VK_FORMAT_R16G16B16_SFLOAT", 3, 2},
    {97, "VK_FORMAT_R16G16B16A16_SFLOAT", 4, 2},
    {100, "VK_FORMAT_R32_SFLOAT", 1, 4},
    {103, "VK_FORMAT_R32G32_SFLOAT", 2, 4},
    {106, "VK_FORMAT_R32G32B32_SFLOAT", 3, 4},
    {109, "VK_FORMAT_R32G32B32A32_SFLOAT", 4, 4},
    {kVkFormatAstc4x4SfloatBlock, "VK_FORMAT_ASTC_4x4_SFLOAT_BLOCK", 0, 0, 4, 4, 16},
    {kVkFormatAstc6x6SfloatBlock, "VK_FORMAT_ASTC_6x6_SFLOAT_BLOCK", 0, 0, 6, 6, 16},
};

bool compressed(const Format& format) { return format.block_bytes != 0; }

// KTX2 "typeSize": the component size of an unpacked format, 1 for block-compressed formats.
uint32_t type_size(const Format& format) { return compressed(format) ? 1 : format.component_bytes; }

const Format* find_format(uint32_t vk_format) {
  for (const Format& format : kFormats) {
    if (format.vk_format == vk_format) return &format;
  }
  return nullptr;
}

std::string supported_formats_list() {
  std::string list;
  for (const Format& format : kFormats) {
    if (!list.empty()) list += ", ";
    list += std::to_string(format.vk_format);
  }
  return list;
}

// Bytes of one texel block (one texel when uncompressed).
uint32_t texel_size(const Format& format) {
  return compressed(format) ? format.block_bytes : format.components * format.component_bytes;
}

// KTX2 "mipPadding": levels start at multiples of lcm(texel block size, 4) when not
// supercompressed.
uint64_t level_alignment(const Format& format) {
  return std::lcm(static_cast<uint64_t>(texel_size(format)), uint64_t{4});
}

uint64_t align_up(uint64_t value, uint64_t alignment) { return (value + alignment - 1) / alignment * alignment; }

// Level byte size (KTX2 "levelImages": faces x rows x texels, no row or face padding), or false
// on overflow. A 1-D texture (height 0) has one row.
bool level_byte_size(const Format& format, uint32_t width, uint32_t height, uint32_t faces, uint32_t level,
                     uint64_t* size) {
  const uint64_t texel_width = std::max<uint64_t>(1, level < 32 ? width >> level : 0);
  const uint64_t texel_height = std::max<uint64_t>(1, level < 32 ? height >> level : 0);
  // KTX2 "levelImages": whole blocks, ceil(width / blockWidth) x ceil(height / blockHeight).
  const uint64_t level_width = (texel_width + format.block_width - 1) / format.block_width;
  const uint64_t level_height = (texel_height + format.block_height - 1) / format.block_height;
  uint64_t bytes = 0;
  return !__builtin_mul_overflow(level_width, level_height, &bytes) &&
         !__builtin_mul_overflow(bytes, uint64_t{faces}, &bytes) &&
         !__builtin_mul_overflow(bytes, uint64_t{texel_size(format)}, size);
}

// ---- Data Format Descriptor (KDF "Khronos Basic Data Format Descriptor Block") ----------------

constexpr uint32_t kDfdBlockHeaderBytes = 24;  // six words before the samples
constexpr uint32_t kDfdSampleBytes = 16;       // four words per sample
constexpr uint32_t kDfVendorKhronos = 0;
constexpr uint32_t kDfDescriptorTypeBasic = 0;
constexpr uint32_t kDfVersion13 = 2;  // KHR_DF_VERSIONNUMBER_1_3
constexpr uint32_t kDfModelRgbsda = 1;
constexpr uint32_t kDfModelAstc = 162;      // KHR_DF_MODEL_ASTC
constexpr uint32_t kDfChannelAstcData = 0;  // KHR_DF_CHANNEL_ASTC_DATA
constexpr uint32_t kDfPrimariesBt709 = 1;
constexpr uint32_t kDfTransferLinear = 1;
constexpr uint32_t kDfFlagAlphaPremultiplied = 1;  // the only flag; 0 is ALPHA_STRAIGHT
constexpr uint32_t kDfChannelAlpha = 15;           // RGBSDA channel ids: R 0, G 1, B 2, A 15
// Qualifier bits, in the byte that also holds the 4-bit channel id (KDF "channelType").
constexpr uint32_t kDfQualifierLinear = 0x10;
constexpr uint32_t kDfQualifierSigned = 0x40;
constexpr uint32_t kDfQualifierFloat = 0x80;
// KDF "sampleLower and sampleUpper": for floating-point samples, sampleLower/sampleUpper are
// floats; -1.0f and 1.0f for signed floating-point formats.
constexpr uint32_t kFloatMinusOneBits = 0xBF800000u;
constexpr uint32_t kFloatOneBits = 0x3F800000u;

uint32_t channel_id(uint32_t component) { return component < 3 ? component : kDfChannelAlpha; }

uint32_t dfd_sample_count(const Format& format) { return compressed(format) ? 1 : format.components; }

uint32_t dfd_block_size(const Format& format) {
  return kDfdBlockHeaderBytes + kDfdSampleBytes * dfd_sample_count(format);
}

// The whole descriptor as words: dfdTotalSize, then the basic block.
std::vector<uint32_t> dfd_words(const Format& format) {
  const uint32_t block_size = dfd_block_size(format);
  if (compressed(format)) {
    // KDF "ASTC" model: one sample covering the 128-bit block, channel ASTC_DATA, qualified
    // FLOAT | SIGNED with sampleLower/Upper -1.0f/1.0f for the SFLOAT (HDR) formats; the block
    // dimensions minus one in texelBlockDimension0/1 (as KTX-Software's createDFDCompressed).
    return {
        4 + block_size,
        kDfVendorKhronos | kDfDescriptorTypeBasic << 17,
        kDfVersion13 | block_size << 16,
        kDfModelAstc | kDfPrimariesBt709 << 8 | kDfTransferLinear << 16 | 0u << 24,
        (format.block_width - 1) | (format.block_height - 1) << 8,
        format.block_bytes,
        0,
        0u | (format.block_bytes * 8 - 1) << 16 | (kDfChannelAstcData | kDfQualifierFloat | kDfQualifierSigned) << 24,
        0,
        kFloatMinusOneBits,
        kFloatOneBits,
    };
  }
  std::vector<uint32_t> words = {
      4 + block_size,                                   // dfdTotalSize
      kDfVendorKhronos | kDfDescriptorTypeBasic << 17,  // vendorId (17 bits), descriptorType
      kDfVersion13 | block_size << 16,                  // versionNumber, descriptorBlockSize
      kDfModelRgbsda | kDfPrimariesBt709 << 8 | kDfTransferLinear << 16 | 0u << 24,  // flags 0
      0,                   // texelBlockDimension0..3, each stored minus one: a 1x1x1x1 block
      texel_size(format),  // bytesPlane0; bytesPlane1..3 = 0
      0,                   // bytesPlane4..7
  };
  const uint32_t bits = format.component_bytes * 8;
  for (uint32_t c = 0; c < format.components; ++c) {
    const uint32_t type = channel_id(c) | kDfQualifierFloat | kDfQualifierSigned;
    words.push_back(c * bits | (bits - 1) << 16 | type << 24);  // bitOffset, bitLength - 1, type
    words.push_back(0);                                         // samplePosition0..3
    words.push_back(kFloatMinusOneBits);                        // sampleLower
    words.push_back(kFloatOneBits);                             // sampleUpper
  }
  return words;
}

// ---- Little-endian access ---------------------------------------------------------------------

void put_u32(std::vector<uint8_t>& out, size_t at, uint32_t value) {
  for (size_t i = 0; i < 4; ++i) out[at + i] = static_cast<uint8_t>(value >> (8 * i));
}

void put_u64(std::vector<uint8_t>& out, size_t at, uint64_t value) {
  for (size_t i = 0; i < 8; ++i) out[at + i] = static_cast<uint8_t>(value >> (8 * i));
}

uint32_t get_u32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 | static_cast<uint32_t>(p[2]) << 16 |
         static_cast<uint32_t>(p[3]) << 24;
}

uint64_t get_u64(const uint8_t* p) {
  return static_cast<uint64_t>(get_u32(p)) | static_cast<uint64_t>(get_u32(p + 4)) << 32;
}

std::string hex32(uint32_t value) {
  char text[11];
  std::snprintf(text, sizeof text, "0x%08X", value);
  return text;
}

// ---- Key/value data (KTX2 "Key/Value Data") ---------------------------------------------------

// The KTX-prefixed keys this writer accepts: the string-valued ones of KTX2 "Predefined Key/Value
// Pairs" (binary-valued keys such as KTXglFormat would be corrupted by the string NUL terminator).
constexpr std::string_view kStringKtxKeys[] = {"KTXorientation", "KTXswizzle", "KTXwriter", "KTXwriterScParams"};

bool is_reserved_key(const std::string& key) { return key.compare(0, 3, "KTX") == 0 || key.compare(0, 3, "ktx") == 0; }

// One entry: keyAndValueByteLength counts the key, its NUL, the value and the value's NUL.
uint32_t key_value_byte_length(const std::pair<std::string, std::string>& entry) {
  return static_cast<uint32_t>(entry.first.size() + 1 + entry.second.size() + 1);
}

void check_orientation(const std::string& value, const Ktx2Image& image) {
  // KTX2 "KTXorientation": /^[rl]$/ for 1-D, /^[rl][du]$/ for 2-D and cubemaps.
  const bool one_d = image.height == 0;
  const bool valid = value.size() == (one_d ? 1u : 2u) && (value[0] == 'r' || value[0] == 'l') &&
                     (one_d || value[1] == 'd' || value[1] == 'u');
  if (!valid) {
    throw Error("KTX2 writer: KTXorientation '" + value + "' is invalid for a " +
                (one_d ? "1-D texture (expected r or l)" : "2-D texture (expected [rl][du])"));
  }
}

void check_key_values(const Ktx2Image& image, const std::vector<std::pair<std::string, std::string>>& sorted) {
  for (size_t i = 0; i < sorted.size(); ++i) {
    const std::string& key = sorted[i].first;
    if (key.empty()) throw Error("KTX2 writer: empty metadata key");
    if (key.find('\0') != std::string::npos) {
      std::string shown = key;
      for (size_t at = shown.find('\0'); at != std::string::npos; at = shown.find('\0', at)) {
        shown.replace(at, 1, "\\0");
      }
      throw Error("KTX2 writer: metadata key '" + shown + "' contains a NUL byte");
    }
    if (i > 0 && sorted[i - 1].first == key) {
      throw Error("KTX2 writer: duplicate metadata key '" + key + "'");
    }
    if (is_reserved_key(key) &&
        std::find(std::begin(kStringKtxKeys), std::end(kStringKtxKeys), key) == std::end(kStringKtxKeys)) {
      throw Error("KTX2 writer: metadata key '" + key +
                  "' is reserved by the KTX specification and not supported here");
    }
    if (key == "KTXorientation") check_orientation(sorted[i].second, image);
    if (key == "KTXswizzle") {
      const std::string& value = sorted[i].second;
      const bool valid = value.size() == 4 && value.find_first_not_of("rgba01") == std::string::npos;
      if (!valid) throw Error("KTX2 writer: KTXswizzle '" + value + "' is not /^[rgba01]{4}$/");
    }
    if (key == "KTXwriterScParams" &&
        std::none_of(sorted.begin(), sorted.end(), [](const auto& entry) { return entry.first == "KTXwriter"; })) {
      throw Error("KTX2 writer: KTXwriterScParams requires KTXwriter");
    }
  }
}

// ---- Writer -------------------------------------------------------------------------------------

// `streamed`: the levels come from a Ktx2LevelSource (level_data empty). `level_sizes`: each level's
// bytes, when asked for.
const Format& check_image(const Ktx2Image& image, bool streamed = false, std::vector<uint64_t>* level_sizes = nullptr) {
  const Format* format = find_format(image.vk_format);
  if (format == nullptr) {
    throw Error("KTX2 writer: unsupported vkFormat " + std::to_string(image.vk_format) +
                " (supported: " + supported_formats_list() + ")");
  }
  if (image.width == 0) throw Error("KTX2 writer: pixelWidth must not be 0");
  if (image.faces != 1 && image.faces != 6) {
    throw Error("KTX2 writer: faceCount must be 1 or 6, not " + std::to_string(image.faces));
  }
  if (image.faces == 6 && image.height != image.width) {
    throw Error("KTX2 writer: cubemap faces must be square, not " + std::to_string(image.width) + "x" +
                std::to_string(image.height));
  }
  const uint32_t max_levels = ktx2_max_levels(image.width, image.height);
  if (image.levels == 0 || image.levels > max_levels) {
    throw Error("KTX2 writer: levelCount " + std::to_string(image.levels) + " is outside 1.." +
                std::to_string(max_levels) + " for " + std::to_string(image.width) + "x" +
                std::to_string(image.height));
  }
  if (!streamed && image.level_data.size() != image.levels) {
    throw Error("KTX2 writer: " + std::to_string(image.level_data.size()) + " level buffers for levelCount " +
                std::to_string(image.levels));
  }
  if (streamed && !image.level_data.empty()) throw Error("KTX2 writer: levels given both as buffers and as a source");
  if (level_sizes) level_sizes->assign(image.levels, 0);
  for (uint32_t level = 0; level < image.levels; ++level) {
    uint64_t expected = 0;
    if (!level_byte_size(*format, image.width, image.height, image.faces, level, &expected)) {
      throw Error("KTX2 writer: level " + std::to_string(level) + " is too large");
    }
    if (level_sizes) (*level_sizes)[level] = expected;
    if (streamed) continue;
    if (image.level_data[level].size() != expected) {
      throw Error("KTX2 writer: level " + std::to_string(level) + " holds " +
                  std::to_string(image.level_data[level].size()) + " bytes, expected " + std::to_string(expected) +
                  " for " + format->name);
    }
  }
  return *format;
}

// ---- Reader -------------------------------------------------------------------------------------

class Decoder {
 public:
  Decoder(const uint8_t* data, size_t size, std::string context)
      : data_(data), size_(size), context_(std::move(context)) {}

  Ktx2Image decode() {
    if (size_ < kLevelIndexOffset) {
      fail("truncated: " + std::to_string(size_) + " bytes, but the header and index take " +
           std::to_string(kLevelIndexOffset));
    }
    if (std::memcmp(data_, kIdentifier, sizeof kIdentifier) != 0) {
      if (std::memcmp(data_, kIdentifierKtx1, sizeof kIdentifierKtx1) == 0) {
        fail("a KTX 1 file; only KTX 2 is supported");
      }
      fail("bad identifier (not a KTX 2 file)");
    }
    Ktx2Image image;
    const Format& format = decode_header(image);
    const uint32_t level_count = u32(kOffsetLevelCount);
    // KTX2 "levelCount": levelCount 0 means that only the base level is stored.
    image.levels = std::max(level_count, 1u);
    require(kLevelIndexOffset, uint64_t{kLevelIndexEntrySize} * image.levels, "the level index");

    const uint64_t dfd_offset = u32(kOffsetDfdByteOffset);
    const uint64_t dfd_length = u32(kOffsetDfdByteLength);
    const uint64_t kvd_offset = u32(kOffsetKvdByteOffset);
    const uint64_t kvd_length = u32(kOffsetKvdByteLength);
    const uint64_t sgd_offset = u64(kOffsetSgdByteOffset);
    const uint64_t sgd_length = u64(kOffsetSgdByteLength);
    const uint64_t level_index_end = kLevelIndexOffset + uint64_t{kLevelIndexEntrySize} * image.levels;
    if (dfd_offset != level_index_end) {
      fail("dfdByteOffset is " + std::to_string(dfd_offset) + ", expected " + std::to_string(level_index_end) +
           " (right after the level index)");
    }
    if (dfd_length < 4 + kDfdBlockHeaderBytes) {
      fail("dfdByteLength " + std::to_string(dfd_length) + " is too small for a descriptor block");
    }
    require(dfd_offset, dfd_length, "the Data Format Descriptor");
    if (u32(dfd_offset) != dfd_length) {
      fail("dfdTotalSize " + std::to_string(u32(dfd_offset)) + " differs from dfdByteLength " +
           std::to_string(dfd_length));
    }
    if (kvd_length == 0 && kvd_offset != 0) {
      fail("kvdByteOffset is " + std::to_string(kvd_offset) + " with kvdByteLength 0 (must be 0)");
    }
    if (kvd_length != 0) {
      if (kvd_offset != dfd_offset + dfd_length) {
        fail("kvdByteOffset is " + std::to_string(kvd_offset) + ", expected " +
             std::to_string(dfd_offset + dfd_length) + " (dfdByteOffset + dfdTotalSize)");
      }
      require(kvd_offset, kvd_length, "the key/value data");
    }
    if (sgd_offset != 0 || sgd_length != 0) {
      fail("sgdByteOffset/sgdByteLength are " + std::to_string(sgd_offset) + "/" + std::to_string(sgd_length) +
           "; both must be 0 without supercompression");
    }
    decode_dfd(format, dfd_offset, dfd_length);
    if (kvd_length != 0) decode_key_values(kvd_offset, kvd_length, image);
    decode_levels(format, kvd_length != 0 ? kvd_offset + kvd_length : dfd_offset + dfd_length, image);
    return image;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw Error(context_ + ": " + what); }

  // Bounds are checked by require() before any access.
  uint32_t u32(uint64_t at) const { return get_u32(data_ + at); }
  uint64_t u64(uint64_t at) const { return get_u64(data_ + at); }

  void require(uint64_t offset, uint64_t length, const std::string& what) const {
    if (offset > size_ || length > size_ - offset) {
      fail("truncated: " + what + " needs bytes " + std::to_string(offset) + ".." + std::to_string(offset + length) +
           " but the file has " + std::to_string(size_));
    }
  }

  const Format& decode_header(Ktx2Image& image) const {
    image.vk_format = u32(kOffsetVkFormat);
    const Format* format = find_format(image.vk_format);
    if (format == nullptr) {
      fail("unsupported vkFormat " + std::to_string(image.vk_format) + " (supported: " + supported_formats_list() +
           ")");
    }
    // KTX2 "typeSize": for unpacked formats the size of one component, 1 for block formats.
    if (u32(kOffsetTypeSize) != type_size(*format)) {
      fail("typeSize is " + std::to_string(u32(kOffsetTypeSize)) + ", expected " + std::to_string(type_size(*format)) +
           " for " + format->name);
    }
    image.width = u32(kOffsetPixelWidth);
    image.height = u32(kOffsetPixelHeight);
    image.faces = u32(kOffsetFaceCount);
    if (image.width == 0) fail("pixelWidth is 0");
    if (u32(kOffsetPixelDepth) != 0) {
      fail("pixelDepth is " + std::to_string(u32(kOffsetPixelDepth)) + "; 3-D textures are not supported");
    }
    if (u32(kOffsetLayerCount) != 0) {
      fail("layerCount is " + std::to_string(u32(kOffsetLayerCount)) + "; array textures are not supported");
    }
    if (image.faces != 1 && image.faces != 6) {
      fail("faceCount is " + std::to_string(image.faces) + ", expected 1 or 6");
    }
    if (image.faces == 6 && image.height != image.width) {
      fail("a cubemap with pixelWidth " + std::to_string(image.width) + " and pixelHeight " +
           std::to_string(image.height) + " (faces must be square)");
    }
    const uint32_t max_levels = ktx2_max_levels(image.width, image.height);
    if (u32(kOffsetLevelCount) > max_levels) {
      fail("levelCount " + std::to_string(u32(kOffsetLevelCount)) + " exceeds the " + std::to_string(max_levels) +
           " levels of a " + std::to_string(image.width) + "x" + std::to_string(image.height) + " texture");
    }
    if (u32(kOffsetSupercompressionScheme) != 0) {
      fail("supercompressionScheme " + std::to_string(u32(kOffsetSupercompressionScheme)) + " is not supported");
    }
    return *format;
  }

  void decode_dfd(const Format& format, uint64_t dfd_offset, uint64_t dfd_length) const {
    const uint64_t end = dfd_offset + dfd_length;
    const uint64_t block = dfd_offset + 4;
    const uint32_t word0 = u32(block);
    if ((word0 & 0x1FFFFu) != kDfVendorKhronos || (word0 >> 17) != kDfDescriptorTypeBasic) {
      fail("the first descriptor block is not a Khronos basic descriptor (vendorId " +
           std::to_string(word0 & 0x1FFFFu) + ", descriptorType " + std::to_string(word0 >> 17) + ")");
    }
    const uint32_t word1 = u32(block + 4);
    const uint32_t block_size = word1 >> 16;
    if ((word1 & 0xFFFFu) != kDfVersion13) {
      fail("DFD versionNumber is " + std::to_string(word1 & 0xFFFFu) + ", expected 2");
    }
    if (block_size != dfd_block_size(format)) {
      fail("DFD descriptorBlockSize is " + std::to_string(block_size) + ", expected " +
           std::to_string(dfd_block_size(format)) + " for " + format.name);
    }
    if (block + block_size > end) {
      fail("the DFD basic block (" + std::to_string(block_size) + " bytes) runs past dfdTotalSize");
    }
    const uint32_t word2 = u32(block + 8);
    const uint32_t model = word2 & 0xFFu;
    const uint32_t transfer = (word2 >> 16) & 0xFFu;
    const uint32_t flags = word2 >> 24;
    const uint32_t expected_model = compressed(format) ? kDfModelAstc : kDfModelRgbsda;
    if (model != expected_model) {
      fail("DFD colorModel is " + std::to_string(model) + ", expected " + std::to_string(expected_model) +
           (compressed(format) ? " (ASTC)" : " (RGBSDA)"));
    }
    if (transfer != kDfTransferLinear) {
      fail("DFD transferFunction is " + std::to_string(transfer) + ", expected 1 (LINEAR)");
    }
    if ((flags & ~kDfFlagAlphaPremultiplied) != 0) {
      fail("DFD flags " + std::to_string(flags) + " has undefined bits");
    }
    const uint32_t dimension = (format.block_width - 1) | (format.block_height - 1) << 8;
    if (u32(block + 12) != dimension) {
      fail("DFD texelBlockDimension is " + hex32(u32(block + 12)) + ", expected " + std::to_string(format.block_width) +
           "x" + std::to_string(format.block_height) + "x1x1 (" + hex32(dimension) + ")");
    }
    if (u32(block + 16) != texel_size(format) || u32(block + 20) != 0) {
      fail("DFD bytesPlane0..7 are " + hex32(u32(block + 16)) + " " + hex32(u32(block + 20)) +
           ", expected bytesPlane0 = " + std::to_string(texel_size(format)) + " and the rest 0");
    }
    const uint32_t bits = compressed(format) ? format.block_bytes * 8 : format.component_bytes * 8;
    for (uint32_t c = 0; c < dfd_sample_count(format); ++c) {
      const uint64_t sample = block + kDfdBlockHeaderBytes + uint64_t{kDfdSampleBytes} * c;
      const std::string name = "DFD sample " + std::to_string(c);
      const uint32_t word = u32(sample);
      const uint32_t bit_offset = word & 0xFFFFu;
      const uint32_t bit_length = ((word >> 16) & 0xFFu) + 1;
      const uint32_t channel = (word >> 24) & 0x0Fu;
      const uint32_t qualifiers = (word >> 24) & 0xF0u;
      if (bit_offset != c * bits || bit_length != bits) {
        fail(name + " covers bits " + std::to_string(bit_offset) + "+" + std::to_string(bit_length) + ", expected " +
             std::to_string(c * bits) + "+" + std::to_string(bits));
      }
      if (channel != (compressed(format) ? kDfChannelAstcData : channel_id(c))) {
        fail(name + " has channelType " + std::to_string(channel) + ", expected " +
             std::to_string(compressed(format) ? kDfChannelAstcData : channel_id(c)));
      }
      // KTX2 "Restrictions" (of the DFD): the LINEAR qualifier may differ from the format's
      // definition.
      if ((qualifiers & ~kDfQualifierLinear) != (kDfQualifierFloat | kDfQualifierSigned)) {
        fail(name + " has qualifiers " + hex32(qualifiers) + ", expected FLOAT|SIGNED (0xC0)");
      }
      if (u32(sample + 4) != 0) fail(name + " has samplePosition " + hex32(u32(sample + 4)));
      if (u32(sample + 8) != kFloatMinusOneBits || u32(sample + 12) != kFloatOneBits) {
        fail(name + " has sampleLower/sampleUpper " + hex32(u32(sample + 8)) + "/" + hex32(u32(sample + 12)) +
             ", expected -1.0f/1.0f (0xBF800000/0x3F800000)");
      }
    }
    // Further descriptor blocks (vendor extensions) may follow; skip them if well formed.
    uint64_t cursor = block + block_size;
    while (cursor < end) {
      if (end - cursor < 8) fail("truncated descriptor block at offset " + std::to_string(cursor));
      const uint32_t size = u32(cursor + 4) >> 16;
      if (size < 8 || size % 4 != 0 || size > end - cursor) {
        fail("descriptor block at offset " + std::to_string(cursor) + " has invalid size " + std::to_string(size));
      }
      cursor += size;
    }
  }

  void decode_key_values(uint64_t kvd_offset, uint64_t kvd_length, Ktx2Image& image) const {
    const uint64_t end = kvd_offset + kvd_length;
    uint64_t cursor = kvd_offset;
    while (cursor < end) {
      const std::string where = "key/value entry at offset " + std::to_string(cursor);
      if (end - cursor < 4) fail("truncated " + where + " (no room for keyAndValueByteLength)");
      const uint64_t length = u32(cursor);
      if (length < 2) fail(where + " has keyAndValueByteLength " + std::to_string(length));
      if (length > end - cursor - 4) {
        fail(where + " (" + std::to_string(length) + " bytes) runs past kvdByteLength");
      }
      const char* text = reinterpret_cast<const char*>(data_ + cursor + 4);
      const std::string_view entry(text, length);
      const size_t nul = entry.find('\0');
      if (nul == std::string_view::npos) fail(where + " has no NUL-terminated key");
      if (nul == 0) fail(where + " has an empty key");
      std::string key(entry.substr(0, nul));
      std::string_view value = entry.substr(nul + 1);
      if (!value.empty() && value.back() == '\0') value.remove_suffix(1);
      if (!image.key_values.empty() && !(image.key_values.back().first < key)) {
        fail(image.key_values.back().first == key
                 ? "duplicate key '" + key + "'"
                 : "keys are not sorted: '" + image.key_values.back().first + "' before '" + key + "'");
      }
      const uint64_t padded_end = align_up(cursor + 4 + length, 4);
      if (padded_end > end) fail(where + ": valuePadding runs past kvdByteLength");
      for (uint64_t at = cursor + 4 + length; at < padded_end; ++at) {
        if (data_[at] != 0) fail(where + " has non-zero valuePadding");
      }
      image.key_values.emplace_back(std::move(key), std::string(value));
      cursor = padded_end;
    }
  }

  void decode_levels(const Format& format, uint64_t metadata_end, Ktx2Image& image) const {
    const uint64_t alignment = level_alignment(format);
    image.level_data.resize(image.levels);
    uint64_t cursor = metadata_end;
    for (uint32_t level = image.levels; level-- > 0;) {  // stored smallest first
      const uint64_t entry = kLevelIndexOffset + uint64_t{kLevelIndexEntrySize} * level;
      const uint64_t offset = u64(entry);
      const uint64_t length = u64(entry + 8);
      const uint64_t uncompressed = u64(entry + 16);
      const std::string name = "level " + std::to_string(level);
      uint64_t expected = 0;
      if (!level_byte_size(format, image.width, image.height, image.faces, level, &expected)) {
        fail(name + " is too large");
      }
      if (length != expected) {
        fail(name + " byteLength is " + std::to_string(length) + ", expected " + std::to_string(expected) + " for " +
             std::to_string(image.faces) + " face(s) of " + std::to_string(std::max(1u, image.width >> level)) + "x" +
             std::to_string(std::max(1u, image.height >> level)) + " " + format.name);
      }
      if (uncompressed != length) {
        fail(name + " uncompressedByteLength " + std::to_string(uncompressed) + " differs from byteLength " +
             std::to_string(length) + " (no supercompression)");
      }
      const uint64_t aligned = align_up(cursor, alignment);
      if (offset != aligned) {
        fail(name + " byteOffset is " + std::to_string(offset) + ", expected " + std::to_string(aligned) +
             " (levels are stored smallest first, each at a multiple of " + std::to_string(alignment) + ")");
      }
      require(cursor, aligned - cursor, "the mip padding before " + name);
      for (uint64_t at = cursor; at < aligned; ++at) {
        if (data_[at] != 0) fail("non-zero mipPadding before " + name);
      }
      require(offset, length, name);
      image.level_data[level].assign(data_ + offset, data_ + offset + length);
      cursor = offset + length;
    }
    if (cursor != size_) {
      fail(std::to_string(size_ - cursor) + " unexpected bytes after level 0, which ends at " + std::to_string(cursor));
    }
  }

  const uint8_t* data_;
  uint64_t size_;
  std::string context_;
};

}  // namespace

bool ktx2_format_supported(uint32_t vk_format) { return find_format(vk_format) != nullptr; }

uint32_t ktx2_texel_size(uint32_t vk_format) {
  const Format* format = find_format(vk_format);
  if (format == nullptr) {
    throw Error("KTX2: unsupported vkFormat " + std::to_string(vk_format) + " (supported: " + supported_formats_list() +
                ")");
  }
  return texel_size(*format);
}

uint64_t ktx2_level_size(const Ktx2Image& image, uint32_t level) {
  ktx2_texel_size(image.vk_format);  // throws for an unsupported format
  const Format& format = *find_format(image.vk_format);
  uint64_t size = 0;
  if (!level_byte_size(format, image.width, image.height, image.faces, level, &size)) {
    throw Error("KTX2: level " + std::to_string(level) + " is too large");
  }
  return size;
}

uint32_t ktx2_max_levels(uint32_t width, uint32_t height) {
  uint32_t extent = std::max(width, height);
  uint32_t levels = 0;
  for (; extent != 0; extent >>= 1) ++levels;
  return levels;
}

namespace {

// Everything before the level data (header, level index, DFD, key/value data: the bytes up to the
// smallest level's offset, padding included), each level's offset and, when asked, its bytes.
std::vector<uint8_t> encode_prefix(const Ktx2Image& image, std::vector<uint64_t>& level_offsets, uint64_t& total,
                                   bool streamed = false, std::vector<uint64_t>* sizes = nullptr) {
  std::vector<uint64_t> level_sizes;
  const Format& format = check_image(image, streamed, &level_sizes);
  if (sizes) *sizes = level_sizes;
  auto entries = image.key_values;
  std::sort(entries.begin(), entries.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });  // code point order
  check_key_values(image, entries);

  const std::vector<uint32_t> dfd = dfd_words(format);
  const uint64_t dfd_offset = kLevelIndexOffset + uint64_t{kLevelIndexEntrySize} * image.levels;
  const uint64_t dfd_length = dfd.size() * 4;
  uint64_t kvd_length = 0;
  for (const auto& entry : entries) kvd_length += 4 + align_up(key_value_byte_length(entry), 4);
  if (kvd_length > std::numeric_limits<uint32_t>::max() - dfd_offset - dfd_length) {
    throw Error("KTX2 writer: the key/value data is too large");
  }
  const uint64_t kvd_offset = kvd_length != 0 ? dfd_offset + dfd_length : 0;

  level_offsets.assign(image.levels, 0);
  uint64_t cursor = dfd_offset + dfd_length + kvd_length;
  for (uint32_t level = image.levels; level-- > 0;) {  // smallest level first
    cursor = align_up(cursor, level_alignment(format));
    level_offsets[level] = cursor;
    cursor += level_sizes[level];
  }
  total = cursor;

  std::vector<uint8_t> out(level_offsets.empty() ? cursor : level_offsets.back(), 0);
  std::memcpy(out.data(), kIdentifier, sizeof kIdentifier);
  put_u32(out, kOffsetVkFormat, format.vk_format);
  put_u32(out, kOffsetTypeSize, type_size(format));
  put_u32(out, kOffsetPixelWidth, image.width);
  put_u32(out, kOffsetPixelHeight, image.height);
  put_u32(out, kOffsetPixelDepth, 0);
  put_u32(out, kOffsetLayerCount, 0);
  put_u32(out, kOffsetFaceCount, image.faces);
  put_u32(out, kOffsetLevelCount, image.levels);
  put_u32(out, kOffsetSupercompressionScheme, 0);
  put_u32(out, kOffsetDfdByteOffset, static_cast<uint32_t>(dfd_offset));
  put_u32(out, kOffsetDfdByteLength, static_cast<uint32_t>(dfd_length));
  put_u32(out, kOffsetKvdByteOffset, static_cast<uint32_t>(kvd_offset));
  put_u32(out, kOffsetKvdByteLength, static_cast<uint32_t>(kvd_length));
  put_u64(out, kOffsetSgdByteOffset, 0);
  put_u64(out, kOffsetSgdByteLength, 0);
  for (uint32_t level = 0; level < image.levels; ++level) {
    const size_t entry = kLevelIndexOffset + kLevelIndexEntrySize * level;
    put_u64(out, entry, level_offsets[level]);
    put_u64(out, entry + 8, level_sizes[level]);
    put_u64(out, entry + 16, level_sizes[level]);
  }
  for (size_t i = 0; i < dfd.size(); ++i) put_u32(out, dfd_offset + 4 * i, dfd[i]);
  size_t at = dfd_offset + dfd_length;
  for (const auto& [key, value] : entries) {
    put_u32(out, at, key_value_byte_length({key, value}));
    std::memcpy(out.data() + at + 4, key.data(), key.size());                       // NUL terminators and
    std::memcpy(out.data() + at + 4 + key.size() + 1, value.data(), value.size());  // padding
    at += 4 + align_up(key_value_byte_length({key, value}), 4);                     // are the vector's zeros
  }
  return out;
}

}  // namespace

std::vector<uint8_t> encode_ktx2(const Ktx2Image& image) {
  std::vector<uint64_t> level_offsets;
  uint64_t total = 0;
  std::vector<uint8_t> out = encode_prefix(image, level_offsets, total);
  out.resize(total, 0);
  for (uint32_t level = 0; level < image.levels; ++level) {
    std::copy(image.level_data[level].begin(), image.level_data[level].end(),
              out.begin() + static_cast<std::ptrdiff_t>(level_offsets[level]));
  }
  return out;
}

void write_ktx2(const Ktx2Image& image, const std::string& path) { write_ktx2(image, path, {}); }

void write_ktx2(const Ktx2Image& image, const std::string& path, const Ktx2LevelSource& levels) {
  const bool streamed = static_cast<bool>(levels);
  std::vector<uint64_t> level_offsets;
  uint64_t total = 0;
  std::vector<uint64_t> level_sizes;
  const std::vector<uint8_t> prefix = encode_prefix(image, level_offsets, total, streamed, &level_sizes);
  // the levels are written from where they are (or as their source makes them), smallest first as
  // they lie in the file: no second copy of a chain (a 1024^2 chain in binary16 is 64 MiB)
  OutputStream out(path);
  out.write(prefix.data(), prefix.size());
  uint64_t at = prefix.size();
  static const uint8_t kZeros[16] = {};
  for (uint32_t level = image.levels; level-- > 0;) {
    while (at < level_offsets[level]) {  // alignment padding (under 16 bytes)
      const uint64_t n = std::min<uint64_t>(sizeof kZeros, level_offsets[level] - at);
      out.write(kZeros, n);
      at += n;
    }
    if (!streamed) {
      out.write(image.level_data[level].data(), image.level_data[level].size());
      at += image.level_data[level].size();
      continue;
    }
    const uint64_t expected = level_sizes[level];
    uint64_t written = 0;
    levels(level, [&](const uint8_t* data, size_t bytes) {
      if (written + bytes > expected)
        throw Error("KTX2 writer: level " + std::to_string(level) + "'s source gave more than its " +
                    std::to_string(expected) + " bytes");
      out.write(data, bytes);
      written += bytes;
    });
    if (written != expected)
      throw Error("KTX2 writer: level " + std::to_string(level) + "'s source gave " + std::to_string(written) +
                  " bytes, expected " + std::to_string(expected));
    at += written;
  }
  out.commit();
}

Ktx2Image decode_ktx2(const uint8_t* data, size_t size) { return Decoder(data, size, "invalid KTX2 data").decode(); }

Ktx2Image decode_ktx2(const std::vector<uint8_t>& bytes) { return decode_ktx2(bytes.data(), bytes.size()); }

std::vector<uint8_t> ktx2_with_key_values(const std::vector<uint8_t>& file,
                                          const std::vector<std::pair<std::string, std::string>>& key_values) {
  Ktx2Image image = decode_ktx2(file);
  for (const auto& [key, value] : key_values) {
    auto it =
        std::find_if(image.key_values.begin(), image.key_values.end(), [&](const auto& e) { return e.first == key; });
    if (it != image.key_values.end())
      it->second = value;
    else
      image.key_values.emplace_back(key, value);
  }
  return encode_ktx2(image);
}

Ktx2Image read_ktx2(const std::string& path) {
  // A regular file of at most 4 GiB (io/special_files.hpp); every size inside is checked against it.
  if (file_type(path) == FileType::Missing)
    throw Error("cannot read '" + path + "': " + std::error_code(ENOENT, std::system_category()).message());
  std::string bytes;
  try {
    bytes = read_input(path, "KTX2 file", std::uint64_t(4) << 30, "4 GiB", Streams::No);
  } catch (const Cancelled&) {
    throw;
  } catch (const IoError&) {
    throw;
  } catch (const Error& e) {
    // "cannot read KTX2 file 'p': it is a folder" keeps the words callers and users know
    const std::string what = e.what(), head = "cannot read KTX2 file '" + path + "': ";
    throw Error("cannot read '" + path + "': " + (what.rfind(head, 0) == 0 ? what.substr(head.size()) : what));
  }
  return Decoder(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), "invalid KTX2 file '" + path + "'")
      .decode();
}

}  // namespace brdfbake::io
