// KTX 1.1 reader. File structure (KTX 1.1, "File Structure"), all UInt32 in the writer's byte order
// (only 0x04030201, little-endian, is accepted here):
//   identifier (12 bytes), endianness, glType, glTypeSize, glFormat, glInternalFormat,
//   glBaseInternalFormat, pixelWidth, pixelHeight, pixelDepth, numberOfArrayElements,
//   numberOfFaces, numberOfMipmapLevels, bytesOfKeyValueData,
//   key/value data: { UInt32 keyAndValueByteSize, key NUL value, valuePadding to 4 },
//   per level: UInt32 imageSize (one face's bytes for a non-array cube, else the level's), then
//   each face (rows padded to 4 bytes: GL_UNPACK_ALIGNMENT), cubePadding and mipPadding to 4.
#include "io/ktx1.hpp"

#include <algorithm>
#include <cstring>

#include "brdfbake/error.hpp"
#include "io/cubemap_io.hpp"
#include "io/png_image.hpp"

namespace brdfbake::io {

namespace {

constexpr uint8_t kIdentifier[12] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x31, 0x31, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
constexpr size_t kHeaderBytes = 64;

size_t pad4(size_t n) { return (n + 3) & ~size_t(3); }

}  // namespace

uint32_t Ktx1Image::components() const { return gl_format == kGlRgb ? 3 : 4; }
uint32_t Ktx1Image::component_bytes() const { return gl_type == kGlHalfFloat ? 2 : 4; }

Ktx1Image decode_ktx1(const uint8_t* data, size_t size, const std::string& origin) {
  auto fail = [&](const std::string& why) -> Error { return Error("invalid KTX file '" + origin + "': " + why); };
  if (size < kHeaderBytes || std::memcmp(data, kIdentifier, 12) != 0) throw fail("not a KTX 1.1 file (bad identifier)");
  auto u32 = [&](size_t at) {
    return uint32_t(data[at]) | uint32_t(data[at + 1]) << 8 | uint32_t(data[at + 2]) << 16 |
           uint32_t(data[at + 3]) << 24;
  };
  if (u32(12) != 0x04030201) throw fail("big-endian files are not supported");
  Ktx1Image k;
  k.gl_type = u32(16);
  const uint32_t type_size = u32(20);
  k.gl_format = u32(24);
  k.gl_internal_format = u32(28);
  k.width = u32(36);
  k.height = std::max<uint32_t>(1, u32(40));
  const uint32_t depth = u32(44), array_elements = u32(48);
  k.faces = u32(52);
  k.levels = std::max<uint32_t>(1, u32(56));
  const uint32_t kvd_bytes = u32(60);
  if (k.gl_type != kGlHalfFloat && k.gl_type != kGlFloat)
    throw fail("glType " + std::to_string(k.gl_type) + " is not supported (expected GL_HALF_FLOAT or GL_FLOAT)");
  if (k.gl_format != kGlRgb && k.gl_format != kGlRgba) throw fail("glFormat is not GL_RGB or GL_RGBA");
  if (type_size != k.component_bytes())
    throw fail("glTypeSize " + std::to_string(type_size) + " does not match glType");
  if (depth > 1 || array_elements != 0) throw fail("3-D textures and arrays are not supported");
  if (k.faces != 1 && k.faces != 6) throw fail("numberOfFaces " + std::to_string(k.faces) + " (expected 1 or 6)");
  if (k.width == 0 || k.width > 65536 || k.height > 65536) throw fail("unsupported size");
  if (k.faces == 6 && k.width != k.height) throw fail("cube faces are not square");
  uint32_t max_levels = 1;
  while ((std::max(k.width, k.height) >> max_levels) > 0) ++max_levels;
  if (k.levels > max_levels)
    throw fail("numberOfMipmapLevels " + std::to_string(k.levels) + " is too large for " + std::to_string(k.width) +
               "x" + std::to_string(k.height));
  if (kvd_bytes > size - kHeaderBytes) throw fail("the key/value data runs past the end of the file");

  size_t at = kHeaderBytes;
  const size_t kvd_end = kHeaderBytes + kvd_bytes;
  while (at < kvd_end) {
    if (kvd_end - at < 4) throw fail("truncated key/value entry");
    const uint32_t n = u32(at);
    at += 4;
    if (n > kvd_end - at) throw fail("a key/value entry runs past the key/value data");
    const char* kv = reinterpret_cast<const char*>(data + at);
    const size_t key_len = strnlen(kv, n);
    if (key_len == n) throw fail("a key without its NUL terminator");
    std::string value(kv + key_len + 1, n - key_len - 1);
    if (!value.empty() && value.back() == '\0') value.pop_back();
    k.key_values.emplace_back(std::string(kv, key_len), value);
    at += pad4(n);
  }
  at = kvd_end;

  const size_t texel = size_t(k.components()) * k.component_bytes();
  for (uint32_t l = 0; l < k.levels; ++l) {
    const size_t w = std::max<uint32_t>(1, k.width >> l), h = std::max<uint32_t>(1, k.height >> l);
    const size_t row = w * texel, padded_row = pad4(row);
    const size_t face_bytes = padded_row * h;
    if (size - at < 4) throw fail("level " + std::to_string(l) + " is missing");
    const uint32_t image_size = u32(at);
    at += 4;
    if (image_size != face_bytes * (k.faces == 6 ? 1 : k.faces))
      throw fail("level " + std::to_string(l) + " has imageSize " + std::to_string(image_size) + ", expected " +
                 std::to_string(face_bytes));
    // every face of the level in the file before its bytes are reserved (a header is not a promise)
    if (face_bytes > (size - at) / k.faces) throw fail("level " + std::to_string(l) + " is truncated");
    std::vector<uint8_t> level;
    level.reserve(k.faces * row * h);
    for (uint32_t f = 0; f < k.faces; ++f) {
      if (size - at < face_bytes) throw fail("level " + std::to_string(l) + " is truncated");
      for (size_t y = 0; y < h; ++y)
        level.insert(level.end(), data + at + y * padded_row, data + at + y * padded_row + row);
      at += pad4(face_bytes);  // cubePadding
    }
    at = pad4(at);  // mipPadding
    k.level_data.push_back(std::move(level));
  }
  return k;
}

std::vector<uint8_t> ktx1_with_key_values(const std::vector<uint8_t>& file,
                                          const std::vector<std::pair<std::string, std::string>>& key_values,
                                          const std::string& origin) {
  auto fail = [&](const std::string& why) -> Error { return Error("invalid KTX file '" + origin + "': " + why); };
  const uint8_t* data = file.data();
  const size_t size = file.size();
  if (size < kHeaderBytes || std::memcmp(data, kIdentifier, 12) != 0) throw fail("not a KTX 1.1 file (bad identifier)");
  auto u32 = [&](size_t at) {
    return uint32_t(data[at]) | uint32_t(data[at + 1]) << 8 | uint32_t(data[at + 2]) << 16 |
           uint32_t(data[at + 3]) << 24;
  };
  if (u32(12) != 0x04030201) throw fail("big-endian files are not supported");
  const uint32_t kvd_bytes = u32(60);
  if (kvd_bytes > size - kHeaderBytes) throw fail("the key/value data runs past the end of the file");
  // The entries as they are (values with their NUL), then the new ones set.
  std::vector<std::pair<std::string, std::string>> entries;
  size_t at = kHeaderBytes;
  const size_t kvd_end = kHeaderBytes + kvd_bytes;
  while (at < kvd_end) {
    if (kvd_end - at < 4) throw fail("truncated key/value entry");
    const uint32_t n = u32(at);
    at += 4;
    if (n > kvd_end - at) throw fail("a key/value entry runs past the key/value data");
    const char* kv = reinterpret_cast<const char*>(data + at);
    const size_t key_len = strnlen(kv, n);
    if (key_len == n) throw fail("a key without its NUL terminator");
    entries.emplace_back(std::string(kv, key_len), std::string(kv + key_len + 1, n - key_len - 1));
    at += pad4(n);
  }
  for (const auto& [key, value] : key_values) {
    if (key.empty() || key.find('\0') != std::string::npos) throw fail("a key must be non-empty text without NUL");
    std::string v = value + std::string(1, '\0');
    auto it = std::find_if(entries.begin(), entries.end(), [&](const auto& e) { return e.first == key; });
    if (it != entries.end())
      it->second = std::move(v);
    else
      entries.emplace_back(key, std::move(v));
  }
  std::vector<uint8_t> out(data, data + kHeaderBytes);
  for (const auto& [key, value] : entries) {
    const uint32_t n = uint32_t(key.size() + 1 + value.size());  // keyAndValueByteSize
    for (int b = 0; b < 4; ++b) out.push_back(uint8_t(n >> (8 * b)));
    out.insert(out.end(), key.begin(), key.end());
    out.push_back(0);
    out.insert(out.end(), value.begin(), value.end());
    out.resize(pad4(out.size()), 0);  // valuePadding
  }
  const uint32_t kvd = uint32_t(out.size() - kHeaderBytes);
  for (int b = 0; b < 4; ++b) out[60 + size_t(b)] = uint8_t(kvd >> (8 * b));
  out.insert(out.end(), data + kvd_end, data + size);  // the levels, unchanged
  return out;
}

Ktx1Image read_ktx1(const std::string& path) {
  const std::vector<uint8_t> bytes = read_binary_file(path, "KTX file");
  return decode_ktx1(bytes.data(), bytes.size(), path);
}

}  // namespace brdfbake::io
