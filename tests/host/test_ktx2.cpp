// KTX2 writer and reader. The layout tests read every header, index, level index, DFD and
// key/value field from the raw bytes at offsets worked out by hand from the KTX 2.0 specification
// (never through the reader under test); the reader tests then corrupt or truncate such files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include "brdfbake/error.hpp"
#include "io/ktx2.hpp"
#include "support/temp_dir.hpp"

namespace brdfbake::io {
namespace {

namespace fs = std::filesystem;

const uint8_t kIdentifier[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, '\r', '\n', 0x1A, '\n'};

uint32_t u32(const std::vector<uint8_t>& bytes, size_t at) {
  return static_cast<uint32_t>(bytes.at(at)) | static_cast<uint32_t>(bytes.at(at + 1)) << 8 |
         static_cast<uint32_t>(bytes.at(at + 2)) << 16 | static_cast<uint32_t>(bytes.at(at + 3)) << 24;
}

uint64_t u64(const std::vector<uint8_t>& bytes, size_t at) {
  return static_cast<uint64_t>(u32(bytes, at)) | static_cast<uint64_t>(u32(bytes, at + 4)) << 32;
}

void set_u32(std::vector<uint8_t>& bytes, size_t at, uint32_t value) {
  for (size_t i = 0; i < 4; ++i) bytes.at(at + i) = static_cast<uint8_t>(value >> (8 * i));
}

void set_u64(std::vector<uint8_t>& bytes, size_t at, uint64_t value) {
  for (size_t i = 0; i < 8; ++i) bytes.at(at + i) = static_cast<uint8_t>(value >> (8 * i));
}

std::string text_at(const std::vector<uint8_t>& bytes, size_t at, size_t length) {
  return std::string(reinterpret_cast<const char*>(bytes.data() + at), length);
}

// An image whose level data is a recognisable byte pattern, distinct per level.
Ktx2Image make_image(uint32_t vk_format, uint32_t width, uint32_t height, uint32_t faces, uint32_t levels,
                     std::vector<std::pair<std::string, std::string>> kv) {
  Ktx2Image image;
  image.vk_format = vk_format;
  image.width = width;
  image.height = height;
  image.faces = faces;
  image.levels = levels;
  image.key_values = std::move(kv);
  for (uint32_t level = 0; level < levels; ++level) {
    std::vector<uint8_t> data(ktx2_level_size(image, level));
    for (size_t i = 0; i < data.size(); ++i) data[i] = static_cast<uint8_t>(i * 7 + level * 31 + 1);
    image.level_data.push_back(std::move(data));
  }
  return image;
}

// Every header and index field at its offset (KTX2 "File Structure").
struct Expected {
  uint32_t vk_format, type_size, width, height, faces, levels;
  uint32_t dfd_offset, dfd_length, kvd_offset, kvd_length;
};

void expect_header(const std::vector<uint8_t>& file, const Expected& e) {
  ASSERT_GE(file.size(), 80u);
  EXPECT_EQ(std::memcmp(file.data(), kIdentifier, 12), 0);
  EXPECT_EQ(u32(file, 12), e.vk_format) << "vkFormat";
  EXPECT_EQ(u32(file, 16), e.type_size) << "typeSize";
  EXPECT_EQ(u32(file, 20), e.width) << "pixelWidth";
  EXPECT_EQ(u32(file, 24), e.height) << "pixelHeight";
  EXPECT_EQ(u32(file, 28), 0u) << "pixelDepth";
  EXPECT_EQ(u32(file, 32), 0u) << "layerCount";
  EXPECT_EQ(u32(file, 36), e.faces) << "faceCount";
  EXPECT_EQ(u32(file, 40), e.levels) << "levelCount";
  EXPECT_EQ(u32(file, 44), 0u) << "supercompressionScheme";
  EXPECT_EQ(u32(file, 48), e.dfd_offset) << "dfdByteOffset";
  EXPECT_EQ(u32(file, 52), e.dfd_length) << "dfdByteLength";
  EXPECT_EQ(u32(file, 56), e.kvd_offset) << "kvdByteOffset";
  EXPECT_EQ(u32(file, 60), e.kvd_length) << "kvdByteLength";
  EXPECT_EQ(u64(file, 64), 0u) << "sgdByteOffset";
  EXPECT_EQ(u64(file, 72), 0u) << "sgdByteLength";
}

void expect_level(const std::vector<uint8_t>& file, uint32_t level, uint64_t offset, uint64_t length,
                  const std::vector<uint8_t>& data) {
  const size_t entry = 80 + 24 * static_cast<size_t>(level);
  EXPECT_EQ(u64(file, entry), offset) << "levels[" << level << "].byteOffset";
  EXPECT_EQ(u64(file, entry + 8), length) << "levels[" << level << "].byteLength";
  EXPECT_EQ(u64(file, entry + 16), length) << "levels[" << level << "].uncompressedByteLength";
  ASSERT_EQ(data.size(), length);
  ASSERT_LE(offset + length, file.size());
  EXPECT_TRUE(std::equal(data.begin(), data.end(), file.begin() + static_cast<long>(offset)))
      << "level " << level << " data";
}

// The basic descriptor block for an n-component SFLOAT format (KDF 1.3 "Khronos Basic Data Format
// Descriptor Block", KTX2 "Data Format Descriptor").
void expect_dfd(const std::vector<uint8_t>& file, size_t at, uint32_t components, uint32_t component_bits) {
  const uint32_t block_size = 24 + 16 * components;
  EXPECT_EQ(u32(file, at), 4 + block_size) << "dfdTotalSize";
  EXPECT_EQ(u32(file, at + 4), 0u) << "vendorId 0 (Khronos), descriptorType 0 (basic)";
  EXPECT_EQ(u32(file, at + 8), 2u | block_size << 16) << "versionNumber 2, descriptorBlockSize";
  // colorModel RGBSDA (1), colorPrimaries BT709 (1), transferFunction LINEAR (1), flags 0.
  EXPECT_EQ(u32(file, at + 12), 0x00010101u) << "model/primaries/transfer/flags";
  EXPECT_EQ(u32(file, at + 16), 0u) << "texelBlockDimension0..3 (1x1x1x1, stored minus one)";
  EXPECT_EQ(u32(file, at + 20), components * component_bits / 8) << "bytesPlane0..3";
  EXPECT_EQ(u32(file, at + 24), 0u) << "bytesPlane4..7";
  const uint32_t channel_ids[4] = {0, 1, 2, 15};  // R, G, B, A
  for (uint32_t c = 0; c < components; ++c) {
    const size_t sample = at + 28 + 16 * c;
    // bitOffset | (bitLength - 1) << 16 | (channelType | FLOAT 0x80 | SIGNED 0x40) << 24
    const uint32_t word0 = c * component_bits | (component_bits - 1) << 16 | (channel_ids[c] | 0xC0u) << 24;
    EXPECT_EQ(u32(file, sample), word0) << "sample " << c << " word 0";
    EXPECT_EQ(u32(file, sample + 4), 0u) << "sample " << c << " samplePosition0..3";
    EXPECT_EQ(u32(file, sample + 8), 0xBF800000u) << "sample " << c << " sampleLower -1.0f";
    EXPECT_EQ(u32(file, sample + 12), 0x3F800000u) << "sample " << c << " sampleUpper 1.0f";
  }
}

void expect_same(const Ktx2Image& decoded, const Ktx2Image& original) {
  EXPECT_EQ(decoded.vk_format, original.vk_format);
  EXPECT_EQ(decoded.width, original.width);
  EXPECT_EQ(decoded.height, original.height);
  EXPECT_EQ(decoded.faces, original.faces);
  EXPECT_EQ(decoded.levels, original.levels);
  EXPECT_EQ(decoded.level_data, original.level_data);
  auto sorted = original.key_values;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(decoded.key_values, sorted);
}

// ---- Layout ------------------------------------------------------------------------------------

// 4x2 RGBA16F, one level, two keys given out of order.
//   header + index 0..80, level index 80..104, DFD 104..196 (4 + 24 + 4 x 16 = 92),
//   KVD 196..248: "KTXorientation\0rd\0" (18 + 2 padding) and "KTXwriter\0brdfbake test\0" (24),
//   level 0 at 248 (already a multiple of lcm(8, 4) = 8), 4 x 2 x 8 = 64 bytes, file 312 bytes.
TEST(Ktx2Layout, TwoDimensionalHalfFloatFieldByField) {
  const Ktx2Image image =
      make_image(kVkFormatR16G16B16A16Sfloat, 4, 2, 1, 1, {{"KTXwriter", "brdfbake test"}, {"KTXorientation", "rd"}});
  const std::vector<uint8_t> file = encode_ktx2(image);
  ASSERT_EQ(file.size(), 312u);
  expect_header(file, {97, 2, 4, 2, 1, 1, 104, 92, 196, 52});
  expect_level(file, 0, 248, 64, image.level_data[0]);
  expect_dfd(file, 104, 4, 16);
  // Key/value data, sorted by key.
  EXPECT_EQ(u32(file, 196), 18u) << "keyAndValueByteLength of KTXorientation";
  EXPECT_EQ(text_at(file, 200, 18), std::string("KTXorientation\0rd\0", 18));
  EXPECT_EQ(text_at(file, 218, 2), std::string("\0\0", 2)) << "valuePadding";
  EXPECT_EQ(u32(file, 220), 24u) << "keyAndValueByteLength of KTXwriter";
  EXPECT_EQ(text_at(file, 224, 24), std::string("KTXwriter\0brdfbake test\0", 24));
}

// 8x8 cubemap, RGBA32F, 3 levels: level index 80..152, DFD 152..244, KVD 244..264 ("brdfbake:test"
// = "x": 13 + 1 + 1 + 1 = 16 bytes), then levels smallest first, each at a multiple of
// lcm(16, 4) = 16: level 2 (6 x 2 x 2 x 16 = 384) at 272 after 8 bytes of mipPadding, level 1
// (6 x 4 x 4 x 16 = 1536) at 656, level 0 (6 x 8 x 8 x 16 = 6144) at 2192; file 8336 bytes.
TEST(Ktx2Layout, CubemapWithThreeLevelsFieldByField) {
  const Ktx2Image image = make_image(kVkFormatR32G32B32A32Sfloat, 8, 8, 6, 3, {{"brdfbake:test", "x"}});
  const std::vector<uint8_t> file = encode_ktx2(image);
  ASSERT_EQ(file.size(), 8336u);
  expect_header(file, {109, 4, 8, 8, 6, 3, 152, 92, 244, 20});
  expect_level(file, 0, 2192, 6144, image.level_data[0]);
  expect_level(file, 1, 656, 1536, image.level_data[1]);
  expect_level(file, 2, 272, 384, image.level_data[2]);
  expect_dfd(file, 152, 4, 32);
  EXPECT_EQ(u32(file, 244), 16u);
  EXPECT_EQ(text_at(file, 248, 16), std::string("brdfbake:test\0x\0", 16));
  for (size_t at = 264; at < 272; ++at) EXPECT_EQ(file[at], 0) << "mipPadding at " << at;
  // Faces are consecutive within a level: face 1 (-X) of level 1 starts 4 x 4 x 16 bytes in.
  EXPECT_EQ(file[656 + 256], image.level_data[1][256]);
}

// RGB16F has a 6-byte texel, so levels align to lcm(6, 4) = 12 and mipPadding appears between
// sections: DFD 128..204 (4 + 24 + 3 x 16 = 76), KVD 204..212 ("a\0b\0"), level 1 (2 x 2 x 6 = 24)
// at 216 after 4 padding bytes, level 0 (4 x 4 x 6 = 96) at 240; file 336 bytes.
TEST(Ktx2Layout, MipPaddingForSixByteTexels) {
  const Ktx2Image image = make_image(90, 4, 4, 1, 2, {{"a", "b"}});
  const std::vector<uint8_t> file = encode_ktx2(image);
  ASSERT_EQ(file.size(), 336u);
  expect_header(file, {90, 2, 4, 4, 1, 2, 128, 76, 204, 8});
  expect_dfd(file, 128, 3, 16);
  expect_level(file, 0, 240, 96, image.level_data[0]);
  expect_level(file, 1, 216, 24, image.level_data[1]);
  for (size_t at = 212; at < 216; ++at) EXPECT_EQ(file[at], 0) << "mipPadding at " << at;
}

// Without key/value data both kvd fields are 0 (KTX2 "kvdByteOffset"), and level 0 follows the DFD
// (ending at 196) at the next multiple of 8.
TEST(Ktx2Layout, NoKeyValueData) {
  const Ktx2Image image = make_image(kVkFormatR16G16B16A16Sfloat, 2, 2, 1, 1, {});
  const std::vector<uint8_t> file = encode_ktx2(image);
  ASSERT_EQ(file.size(), 232u);
  expect_header(file, {97, 2, 2, 2, 1, 1, 104, 92, 0, 0});
  expect_level(file, 0, 200, 32, image.level_data[0]);
}

TEST(Ktx2Layout, FormatTable) {
  EXPECT_EQ(ktx2_texel_size(76), 2u);
  EXPECT_EQ(ktx2_texel_size(83), 4u);
  EXPECT_EQ(ktx2_texel_size(90), 6u);
  EXPECT_EQ(ktx2_texel_size(97), 8u);
  EXPECT_EQ(ktx2_texel_size(100), 4u);
  EXPECT_EQ(ktx2_texel_size(103), 8u);
  EXPECT_EQ(ktx2_texel_size(106), 12u);
  EXPECT_EQ(ktx2_texel_size(109), 16u);
  EXPECT_THROW(ktx2_texel_size(37), Error);  // VK_FORMAT_R8G8B8A8_UNORM: not supported
  EXPECT_EQ(ktx2_max_levels(1, 1), 1u);
  EXPECT_EQ(ktx2_max_levels(8, 8), 4u);
  EXPECT_EQ(ktx2_max_levels(5, 3), 3u);  // 5, 2, 1
  EXPECT_EQ(ktx2_max_levels(8, 0), 4u);  // 1-D
}

// ---- Round trips -------------------------------------------------------------------------------

TEST(Ktx2RoundTrip, EveryFormatAndShape) {
  for (uint32_t format : {76u, 83u, 90u, 97u, 100u, 103u, 106u, 109u}) {
    SCOPED_TRACE("vkFormat " + std::to_string(format));
    const Ktx2Image flat = make_image(format, 5, 3, 1, 3, {{"brdfbake:kind", "dfg"}});
    expect_same(decode_ktx2(encode_ktx2(flat)), flat);
    const Ktx2Image cube = make_image(format, 4, 4, 6, 3, {{"KTXorientation", "rd"}});
    expect_same(decode_ktx2(encode_ktx2(cube)), cube);
    const Ktx2Image line = make_image(format, 8, 0, 1, 4, {{"KTXorientation", "r"}});
    expect_same(decode_ktx2(encode_ktx2(line)), line);
  }
}

TEST(Ktx2RoundTrip, ThroughAFile) {
  const fs::path path = brdfbake::test::test_temp_root() / "round_trip.ktx2";
  const Ktx2Image image =
      make_image(kVkFormatR32G32B32A32Sfloat, 16, 16, 6, 5, {{"KTXwriter", "brdfbake test"}, {"a", ""}, {"b", "é"}});
  write_ktx2(image, path.string());
  expect_same(read_ktx2(path.string()), image);
  fs::remove(path);
}

// A value without a NUL terminator (allowed for readers, KTX2 "keyAndValueByteLength") comes back
// unchanged.
TEST(Ktx2RoundTrip, ValueWithoutTerminator) {
  std::vector<uint8_t> file = encode_ktx2(make_image(97, 2, 2, 1, 1, {{"a", "bc"}}));
  // Entry at 196: length 5 ("a\0bc\0") -> 4 drops the terminator, which becomes padding, and
  // the key/value data shrinks from 12 to 8 bytes; level 0 stays at 208 = align(204, 8).
  set_u32(file, 196, 4);
  set_u32(file, 60, 8);
  EXPECT_EQ(decode_ktx2(file).key_values.at(0).second, "bc");
}

TEST(Ktx2RoundTrip, LevelCountZeroMeansBaseLevelOnly) {
  std::vector<uint8_t> file = encode_ktx2(make_image(97, 2, 2, 1, 1, {}));
  set_u32(file, 40, 0);
  EXPECT_EQ(decode_ktx2(file).levels, 1u);
}

TEST(Ktx2RoundTrip, LinearQualifierIsAccepted) {
  std::vector<uint8_t> file = encode_ktx2(make_image(97, 2, 2, 1, 1, {}));
  // KHR_DF_SAMPLE_DATATYPE_LINEAR on sample 0, which KTX2 DFD "Restrictions" allow.
  file[104 + 28 + 3] |= 0x10;
  EXPECT_NO_THROW(decode_ktx2(file));
}

// ---- Writer validation -------------------------------------------------------------------------

void expect_write_error(const Ktx2Image& image, const std::string& fragment) {
  try {
    encode_ktx2(image);
    ADD_FAILURE() << "no error; expected one containing \"" << fragment << "\"";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(Ktx2Writer, RejectsInvalidImages) {
  Ktx2Image image = make_image(97, 4, 4, 1, 1, {});
  image.vk_format = 37;
  expect_write_error(image, "unsupported vkFormat 37");

  image = make_image(97, 4, 4, 1, 1, {});
  image.width = 0;
  expect_write_error(image, "pixelWidth");

  image = make_image(97, 4, 4, 1, 1, {});
  image.faces = 3;
  expect_write_error(image, "faceCount must be 1 or 6");

  image = make_image(97, 4, 2, 1, 1, {});
  image.faces = 6;
  expect_write_error(image, "square");

  image = make_image(97, 4, 4, 1, 1, {});
  image.levels = 4;  // 4, 2, 1 is the most
  expect_write_error(image, "levelCount 4 is outside 1..3");

  image = make_image(97, 4, 4, 1, 1, {});
  image.levels = 0;
  expect_write_error(image, "levelCount 0");

  image = make_image(97, 4, 4, 1, 2, {});
  image.level_data.pop_back();
  expect_write_error(image, "1 level buffers for levelCount 2");

  image = make_image(97, 4, 4, 1, 2, {});
  image.level_data[1].push_back(0);
  expect_write_error(image, "level 1 holds 33 bytes, expected 32");
}

TEST(Ktx2Writer, RejectsInvalidKeys) {
  expect_write_error(make_image(97, 2, 2, 1, 1, {{"", "x"}}), "empty metadata key");
  expect_write_error(make_image(97, 2, 2, 1, 1, {{std::string("a\0b", 3), "x"}}), "key 'a\\0b' contains a NUL byte");
  expect_write_error(make_image(97, 2, 2, 1, 1, {{"k", "1"}, {"k", "2"}}), "duplicate");
  expect_write_error(make_image(97, 2, 2, 1, 1, {{"KTXglFormat", "x"}}), "reserved");
  expect_write_error(make_image(97, 2, 2, 1, 1, {{"ktxmine", "x"}}), "reserved");
  expect_write_error(make_image(97, 2, 2, 1, 1, {{"KTXorientation", "ru?"}}), "KTXorientation");
  expect_write_error(make_image(97, 8, 0, 1, 1, {{"KTXorientation", "rd"}}), "1-D");
  expect_write_error(make_image(97, 2, 2, 1, 1, {{"KTXswizzle", "rgbx"}}), "KTXswizzle");
  expect_write_error(make_image(97, 2, 2, 1, 1, {{"KTXwriterScParams", "-q"}}), "requires KTXwriter");
}

TEST(Ktx2Writer, UnwritablePathThrowsAndLeavesNothing) {
  const fs::path folder = brdfbake::test::test_temp_root() / "missing_folder";
  fs::remove_all(folder);
  try {
    write_ktx2(make_image(97, 2, 2, 1, 1, {}), (folder / "x.ktx2").string());
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("x.ktx2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("No such file or directory"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(folder));
}

// The streamed writer (write_ktx2 with a level source, what cube outputs use so that a chain is never
// held twice) writes the very bytes encode_ktx2 gives for the same levels, whatever the pieces'
// sizes; a source that gives too few or too many bytes is an error and leaves no file.
TEST(Ktx2Writer, StreamedLevelsAreTheBytesOfTheWholeImage) {
  const fs::path path = brdfbake::test::test_temp_root() / "streamed.ktx2";
  for (const uint32_t format : {kVkFormatR32G32B32A32Sfloat, kVkFormatR16G16B16A16Sfloat, 90u}) {
    const Ktx2Image whole = make_image(format, 16, 16, 6, 5, {{"KTXwriter", "brdfbake test"}, {"a", "b"}});
    Ktx2Image header = whole;
    header.level_data.clear();
    std::vector<uint32_t> asked;
    write_ktx2(header, path.string(), [&](uint32_t level, const std::function<void(const uint8_t*, size_t)>& put) {
      asked.push_back(level);
      const std::vector<uint8_t>& data = whole.level_data.at(level);
      for (size_t at = 0, piece = 1; at < data.size(); at += piece, piece = piece * 3 + 1)
        put(data.data() + at, std::min(piece, data.size() - at));  // pieces of 1, 4, 13, ... bytes
    });
    std::ifstream in(path, std::ios::binary);
    const std::vector<uint8_t> file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(file, encode_ktx2(whole)) << "format " << format;
    EXPECT_EQ(asked, (std::vector<uint32_t>{4, 3, 2, 1, 0})) << "smallest level first, as in the file";
  }
  fs::remove(path);
  const Ktx2Image whole = make_image(kVkFormatR32G32B32A32Sfloat, 4, 4, 6, 2, {});
  Ktx2Image header = whole;
  header.level_data.clear();
  for (const long extra : {-1L, 1L}) {
    try {
      write_ktx2(header, path.string(), [&](uint32_t level, const std::function<void(const uint8_t*, size_t)>& put) {
        std::vector<uint8_t> data = whole.level_data.at(level);
        if (level == 0) data.resize(size_t(long(data.size()) + extra));
        put(data.data(), data.size());
      });
      ADD_FAILURE() << "no error for a level " << extra << " byte(s) off";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("level 0"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(path)) << "a failed write leaves no file";
  }
  EXPECT_THROW(write_ktx2(whole, path.string(), [](uint32_t, const std::function<void(const uint8_t*, size_t)>&) {}),
               Error)
      << "levels both as buffers and as a source";
}

// ---- Reader validation -------------------------------------------------------------------------

// A valid file to corrupt: the 4x2 RGBA16F file of TwoDimensionalHalfFloatFieldByField.
std::vector<uint8_t> valid_file() {
  return encode_ktx2(
      make_image(kVkFormatR16G16B16A16Sfloat, 4, 2, 1, 1, {{"KTXwriter", "brdfbake test"}, {"KTXorientation", "rd"}}));
}

void expect_read_error(const std::vector<uint8_t>& file, const std::string& fragment) {
  try {
    decode_ktx2(file);
    ADD_FAILURE() << "no error; expected one containing \"" << fragment << "\"";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("invalid KTX2 data: ", 0), 0u) << message;
    EXPECT_NE(message.find(fragment), std::string::npos) << message;
  }
}

TEST(Ktx2Reader, ValidFileDecodes) {
  const Ktx2Image image = decode_ktx2(valid_file());
  EXPECT_EQ(image.width, 4u);
  ASSERT_EQ(image.key_values.size(), 2u);
  EXPECT_EQ(image.key_values[0], (std::pair<std::string, std::string>{"KTXorientation", "rd"}));
}

TEST(Ktx2Reader, EveryTruncationIsRejected) {
  for (const std::vector<uint8_t>& file : {valid_file(), encode_ktx2(make_image(90, 4, 4, 1, 2, {{"a", "b"}})),
                                           encode_ktx2(make_image(109, 4, 4, 6, 3, {}))}) {
    for (size_t size = 0; size < file.size(); ++size) {
      SCOPED_TRACE("truncated to " + std::to_string(size) + " of " + std::to_string(file.size()));
      expect_read_error(std::vector<uint8_t>(file.begin(), file.begin() + static_cast<long>(size)), "truncated");
    }
  }
}

TEST(Ktx2Reader, RejectsTrailingBytes) {
  std::vector<uint8_t> file = valid_file();
  file.push_back(0);
  expect_read_error(file, "1 unexpected bytes after level 0");
}

TEST(Ktx2Reader, RejectsBadIdentifier) {
  std::vector<uint8_t> file = valid_file();
  file[5] = '3';
  expect_read_error(file, "bad identifier");
  file[5] = '1';
  file[6] = '1';
  expect_read_error(file, "a KTX 1 file");
}

TEST(Ktx2Reader, RejectsBadHeaderFields) {
  struct Case {
    size_t offset;
    uint32_t value;
    const char* fragment;
  };
  const Case cases[] = {
      {12, 37, "unsupported vkFormat 37"},
      {16, 4, "typeSize is 4, expected 2"},
      {20, 0, "pixelWidth is 0"},
      {28, 1, "pixelDepth is 1"},
      {32, 2, "layerCount is 2"},
      {36, 2, "faceCount is 2"},
      {36, 6, "faces must be square"},
      {40, 4, "levelCount 4 exceeds the 3 levels"},
      {44, 2, "supercompressionScheme 2"},
      {48, 108, "dfdByteOffset is 108, expected 104"},
      {52, 96, "dfdTotalSize 92 differs from dfdByteLength 96"},
      {52, 16, "dfdByteLength 16 is too small"},
      {56, 200, "kvdByteOffset is 200, expected 196"},
      {60, 0, "kvdByteOffset is 196 with kvdByteLength 0"},
      {64, 8, "sgdByteOffset/sgdByteLength are 8/0"},
      {72, 8, "sgdByteOffset/sgdByteLength are 0/8"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE("offset " + std::to_string(c.offset));
    std::vector<uint8_t> file = valid_file();
    set_u32(file, c.offset, c.value);
    expect_read_error(file, c.fragment);
  }
}

TEST(Ktx2Reader, RejectsBadDataFormatDescriptor) {
  struct Case {
    size_t offset;  // from the start of the DFD at 104
    uint32_t value;
    const char* fragment;
  };
  const Case cases[] = {
      {0, 96, "dfdTotalSize 96 differs"},
      {4, 1, "not a Khronos basic descriptor"},
      {8, 1u | 88u << 16, "versionNumber is 1"},
      {8, 2u | 72u << 16, "descriptorBlockSize is 72, expected 88"},
      {12, 0x00010102u, "colorModel is 2"},
      {12, 0x00020101u, "transferFunction is 2"},
      {12, 0x02010101u, "flags 2"},
      {16, 0x00000303u, "texelBlockDimension"},
      {20, 16, "bytesPlane0..7"},
      {24, 1, "bytesPlane0..7"},
      {28, 0xC00F0010u, "DFD sample 0 covers bits 16+16, expected 0+16"},
      {28, 0xC01F0000u, "DFD sample 0 covers bits 0+32"},
      {28, 0xC30F0000u, "DFD sample 0 has channelType 3, expected 0"},
      {28, 0x400F0000u, "DFD sample 0 has qualifiers"},
      {76, 0xCE0F0030u, "DFD sample 3 has channelType 14, expected 15"},  // 28 + 3 x 16
      {32, 1, "DFD sample 0 has samplePosition"},
      {36, 0, "sampleLower/sampleUpper"},
      {40, 0x7F800000u, "sampleLower/sampleUpper"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE("DFD offset " + std::to_string(c.offset));
    std::vector<uint8_t> file = valid_file();
    set_u32(file, 104 + c.offset, c.value);
    expect_read_error(file, c.fragment);
  }
}

TEST(Ktx2Reader, RejectsBadKeyValueData) {
  // Entries of valid_file(): 196: length 18, "KTXorientation\0rd\0", 2 padding bytes;
  // 220: length 24, "KTXwriter\0brdfbake test\0".
  std::vector<uint8_t> file = valid_file();
  file[200] = 'Z';  // "ZTXorientation" now sorts after "KTXwriter"
  expect_read_error(file, "keys are not sorted: 'ZTXorientation' before 'KTXwriter'");

  file = encode_ktx2(make_image(97, 2, 2, 1, 1, {{"a", "1"}, {"b", "2"}}));
  file[196 + 8 + 4] = 'a';  // second key "b" -> "a"
  expect_read_error(file, "duplicate key 'a'");

  file = valid_file();
  set_u32(file, 196, 60);
  expect_read_error(file, "key/value entry at offset 196 (60 bytes) runs past kvdByteLength");

  file = valid_file();
  set_u32(file, 196, 1);
  expect_read_error(file, "keyAndValueByteLength 1");

  file = valid_file();
  file[214] = 'x';  // the key's NUL
  file[217] = 'x';  // the value's NUL
  expect_read_error(file, "no NUL-terminated key");

  file = valid_file();
  file[200] = 0;
  expect_read_error(file, "empty key");

  file = valid_file();
  file[219] = 1;
  expect_read_error(file, "non-zero valuePadding");

  file = valid_file();
  set_u32(file, 220, 26);  // 24 -> 26: the padded entry would end past the KVD
  expect_read_error(file, "runs past kvdByteLength");
}

TEST(Ktx2Reader, RejectsBadLevelIndex) {
  std::vector<uint8_t> file = valid_file();
  set_u64(file, 88, 72);
  expect_read_error(file, "level 0 byteLength is 72, expected 64");

  file = valid_file();
  set_u64(file, 96, 32);
  expect_read_error(file, "level 0 uncompressedByteLength 32 differs from byteLength 64");

  file = valid_file();
  set_u64(file, 80, 252);
  expect_read_error(file, "level 0 byteOffset is 252, expected 248");

  // Levels stored largest first are rejected: swap the offsets of a two-level RGB16F file.
  file = encode_ktx2(make_image(90, 4, 4, 1, 2, {{"a", "b"}}));
  set_u64(file, 80, 216);
  set_u64(file, 104, 312);
  expect_read_error(file, "level 1 byteOffset is 312, expected 216");

  file = encode_ktx2(make_image(90, 4, 4, 1, 2, {{"a", "b"}}));
  file[213] = 1;
  expect_read_error(file, "non-zero mipPadding before level 1");
}

// Random byte corruption (a fixed generator, so the run is reproducible): every result is a
// decoded image or an Error, never a crash or another exception (run under ASan to see reads).
TEST(Ktx2Reader, RandomCorruptionIsDecodedOrRejected) {
  const std::vector<uint8_t> original = encode_ktx2(make_image(90, 4, 4, 6, 3, {{"KTXorientation", "rd"}, {"a", "b"}}));
  uint32_t state = 2024;
  auto next = [&state] { return state = state * 1664525u + 1013904223u; };
  int rejected = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    std::vector<uint8_t> file = original;
    const uint32_t flips = 1 + next() % 4;
    for (uint32_t k = 0; k < flips; ++k) {
      // Mostly the metadata (the first 256 bytes), where the structure is.
      const size_t at = next() % 4 == 0 ? next() % file.size() : next() % 256;
      file[at] = static_cast<uint8_t>(next() >> 24);
    }
    try {
      decode_ktx2(file);
    } catch (const Error&) {
      ++rejected;
    }
  }
  EXPECT_GT(rejected, 1000);
}

TEST(Ktx2Reader, FileErrorsNameThePath) {
  const std::string missing = (brdfbake::test::test_temp_root() / "no_such_file.ktx2").string();
  try {
    read_ktx2(missing);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "cannot read '" + missing + "': No such file or directory");
  }
  const fs::path path = brdfbake::test::test_temp_root() / "corrupt.ktx2";
  { std::ofstream(path, std::ios::binary) << "not a texture"; }
  try {
    read_ktx2(path.string());
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "invalid KTX2 file '" + path.string() + "': truncated: 13 bytes, but the header and index take 80");
  }
  fs::remove(path);
}

}  // namespace
}  // namespace brdfbake::io
