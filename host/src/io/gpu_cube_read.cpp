// Cube files decoded as a GPU samples them (gpu_cube_read.hpp).
#include "io/gpu_cube_read.hpp"

#include <astcenc.h>

#include <cmath>
#include <cstring>
#include <memory>

#include "brdfbake/error.hpp"
#include "io/atomic_file.hpp"
#include "io/cubemap_io.hpp"
#include "io/half.hpp"
#include "io/ktx1.hpp"
#include "io/ktx2.hpp"
#include "io/packed_float.hpp"
#include "io/png_image.hpp"
#include "io/png_rgbd.hpp"

namespace brdfbake::io {

namespace {

uint32_t u32(const uint8_t* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

float component(const uint8_t* p, uint32_t bytes) {
  if (bytes == 2) return half_bits_to_float(static_cast<uint16_t>(p[0] | p[1] << 8));
  const uint32_t b = u32(p);
  float f;
  std::memcpy(&f, &b, 4);
  return f;
}

// Levels of components x bytes texels (KTX order) to RGBA float.
CubeLevels from_components(uint32_t size, const std::vector<std::vector<uint8_t>>& levels, uint32_t components,
                           uint32_t bytes, const std::string& path) {
  CubeLevels cube;
  cube.size = int(size);
  for (size_t l = 0; l < levels.size(); ++l) {
    const size_t s = size_t(cube.level_size(int(l))), texels = 6 * s * s;
    if (levels[l].size() != texels * components * bytes)
      throw Error("cannot read '" + path + "': level " + std::to_string(l) + " has the wrong size");
    std::vector<float> rgba(4 * texels, 1.0f);
    for (size_t t = 0; t < texels; ++t)
      for (size_t c = 0; c < components && c < 4; ++c)
        rgba[4 * t + c] = component(levels[l].data() + (t * components + c) * bytes, bytes);
    cube.levels.push_back(std::move(rgba));
  }
  return cube;
}

struct ContextDeleter {
  void operator()(astcenc_context* c) const { astcenc_context_free(c); }
};

void astc_check(astcenc_error e, const char* call, const std::string& path) {
  if (e != ASTCENC_SUCCESS)
    throw Error("cannot decode '" + path + "': astcenc " + call + ": " + astcenc_get_error_string(e));
}

CubeLevels decode_astc(const Ktx2Image& k, int block, const std::string& path) {
  astcenc_config config;
  astc_check(astcenc_config_init(ASTCENC_PRF_HDR, unsigned(block), unsigned(block), 1, ASTCENC_PRE_FAST,
                                 ASTCENC_FLG_DECOMPRESS_ONLY, &config),
             "astcenc_config_init", path);
  astcenc_context* raw = nullptr;
  astc_check(astcenc_context_alloc(&config, 1, &raw), "astcenc_context_alloc", path);
  std::unique_ptr<astcenc_context, ContextDeleter> context(raw);
  const astcenc_swizzle swizzle{ASTCENC_SWZ_R, ASTCENC_SWZ_G, ASTCENC_SWZ_B, ASTCENC_SWZ_1};
  CubeLevels cube;
  cube.size = int(k.width);
  for (size_t l = 0; l < k.level_data.size(); ++l) {
    const unsigned s = unsigned(cube.level_size(int(l)));
    const size_t per_side = (s + unsigned(block) - 1) / unsigned(block);
    const size_t face_bytes = per_side * per_side * 16;
    if (k.level_data[l].size() != 6 * face_bytes)
      throw Error("cannot decode '" + path + "': level " + std::to_string(l) + " has the wrong size");
    std::vector<float> rgba(4 * 6 * size_t(s) * s);
    for (size_t f = 0; f < 6; ++f) {
      void* slices[1] = {rgba.data() + 4 * size_t(s) * s * f};
      astcenc_image image{s, s, 1, ASTCENC_TYPE_F32, slices};
      astc_check(astcenc_decompress_image(context.get(), k.level_data[l].data() + f * face_bytes, face_bytes, &image,
                                          &swizzle, 0),
                 "astcenc_decompress_image", path);
      astc_check(astcenc_decompress_reset(context.get()), "astcenc_decompress_reset", path);
    }
    cube.levels.push_back(std::move(rgba));
  }
  return cube;
}

// KTX 1.1 with packed R11F_G11F_B10F texels (io/ktx1.hpp reads only half and float): the same
// structure, 4 bytes a texel, rows already 4-byte aligned.
CubeLevels read_ktx1_packed(const std::vector<uint8_t>& b, const std::string& path,
                            std::vector<std::pair<std::string, std::string>>* key_values) {
  auto fail = [&](const std::string& why) { return Error("invalid KTX file '" + path + "': " + why); };
  if (b.size() < 64) throw fail("truncated header");
  const uint32_t width = u32(&b[36]), faces = u32(&b[52]), levels = std::max<uint32_t>(1, u32(&b[56]));
  const uint32_t kvd = u32(&b[60]);
  if (faces != 6 || width == 0 || width > 65536 || u32(&b[40]) != width) throw fail("not a cubemap");
  if (levels > 17) throw fail("too many levels");
  if (kvd > b.size() - 64) throw fail("the key/value data runs past the end of the file");
  for (size_t k = 64; k + 4 <= 64 + size_t(kvd);) {
    const size_t n = u32(&b[k]);
    if (n > 64 + size_t(kvd) - k - 4) throw fail("a key/value entry runs past the key/value data");
    const char* text = reinterpret_cast<const char*>(&b[k + 4]);
    const size_t key = strnlen(text, n);
    if (key_values && key < n) {
      std::string value(text + key + 1, n - key - 1);
      if (!value.empty() && value.back() == '\0') value.pop_back();
      key_values->emplace_back(std::string(text, key), value);
    }
    k += 4 + ((n + 3) & ~size_t(3));
  }
  size_t at = 64 + size_t(kvd);
  CubeLevels cube;
  cube.size = int(width);
  for (uint32_t l = 0; l < levels; ++l) {
    const size_t s = size_t(cube.level_size(int(l))), face_bytes = 4 * s * s;
    if (b.size() < at + 4) throw fail("level " + std::to_string(l) + " is missing");
    if (u32(&b[at]) != face_bytes) throw fail("level " + std::to_string(l) + " has the wrong imageSize");
    at += 4;
    if (b.size() < at + 6 * face_bytes) throw fail("level " + std::to_string(l) + " is truncated");
    std::vector<float> rgba(4 * 6 * s * s, 1.0f);
    for (size_t t = 0; t < 6 * s * s; ++t) unpack_r11g11b10(u32(&b[at + 4 * t]), &rgba[4 * t]);
    at += 6 * face_bytes;
    cube.levels.push_back(std::move(rgba));
  }
  return cube;
}

}  // namespace

CubeLevels read_gpu_cube(const std::string& path, std::string* format,
                         std::vector<std::pair<std::string, std::string>>* key_values) {
  return decode_gpu_cube(read_binary_file(path, "cube file"), path, format, key_values);
}

CubeLevels decode_gpu_cube(const std::vector<uint8_t>& bytes, const std::string& path, std::string* format,
                           std::vector<std::pair<std::string, std::string>>* key_values) {
  if (bytes.size() >= 12 && bytes[1] == 'K' && bytes[5] == '2' && bytes[6] == '0') {  // «KTX 20»
    const Ktx2Image k = decode_ktx2(bytes);
    if (key_values) *key_values = k.key_values;
    if (k.faces != 6) throw Error("'" + path + "' is not a cubemap (faceCount " + std::to_string(k.faces) + ")");
    if (k.vk_format == kVkFormatAstc4x4SfloatBlock || k.vk_format == kVkFormatAstc6x6SfloatBlock) {
      const int block = k.vk_format == kVkFormatAstc4x4SfloatBlock ? 4 : 6;
      if (format) *format = "ASTC " + std::to_string(block) + "x" + std::to_string(block) + " SFLOAT";
      return decode_astc(k, block, path);
    }
    uint32_t components = 0, size = 0;
    switch (k.vk_format) {
      case 90:
        components = 3, size = 2;
        break;  // R16G16B16_SFLOAT
      case 97:
        components = 4, size = 2;
        break;  // R16G16B16A16_SFLOAT
      case 106:
        components = 3, size = 4;
        break;  // R32G32B32_SFLOAT
      case 109:
        components = 4, size = 4;
        break;  // R32G32B32A32_SFLOAT
      default:
        throw Error("'" + path + "': vkFormat " + std::to_string(k.vk_format) + " is not a float RGB(A) cube format");
    }
    if (format) *format = std::string(components == 4 ? "RGBA" : "RGB") + (size == 2 ? "16F" : "32F");
    return from_components(k.width, k.level_data, components, size, path);
  }
  if (bytes.size() >= 64 && bytes[1] == 'K' && bytes[5] == '1' && bytes[6] == '1') {  // «KTX 11»
    const uint32_t gl_type = u32(&bytes[16]);
    if (gl_type == kGlR11fG11fB10f || gl_type == kGlUnsignedInt10f11f11fRev) {
      if (format) *format = "R11F_G11F_B10F";
      return read_ktx1_packed(bytes, path, key_values);
    }
    const Ktx1Image k = decode_ktx1(bytes.data(), bytes.size(), path);
    if (key_values) *key_values = k.key_values;
    if (k.faces != 6) throw Error("'" + path + "' is not a cubemap");
    if (format)
      *format = std::string(k.components() == 4 ? "RGBA" : "RGB") + (k.component_bytes() == 2 ? "16F" : "32F");
    return from_components(k.width, k.level_data, k.components(), k.component_bytes(), path);
  }
  throw Error("'" + path + "' is neither a KTX 2.0 nor a KTX 1.1 file");
}

std::vector<float> decode_rgbd_face(const std::vector<uint8_t>& png, int size, const std::string& origin) {
  int w = 0, h = 0;
  const std::vector<uint8_t> px = decode_png_rgba8(png.data(), png.size(), &w, &h);
  if (w != size || h != size)
    throw Error(origin + " is " + std::to_string(w) + "x" + std::to_string(h) + ", expected " + std::to_string(size) +
                "x" + std::to_string(size));
  const size_t s = size_t(size);
  std::vector<float> rgba(4 * s * s, 1.0f);
  for (size_t t = 0; t < s * s; ++t) {
    // fromRGBD in fp32, then stored as binary16; row 0 of the image is the face's last row
    const float a = float(px[4 * t + 3]) / 255.0f;
    const size_t row = t / s, column = t % s;
    float* out = &rgba[4 * ((s - 1 - row) * s + column)];
    for (int c = 0; c < 3; ++c) {
      const float v = a > 0.0f ? std::pow(float(px[4 * t + size_t(c)]) / 255.0f, 2.2f) / a : 0.0f;
      out[c] = half_bits_to_float(float_to_half_bits(v));
    }
  }
  return rgba;
}

CubeLevels decode_rgbd_cube(const std::vector<std::vector<std::vector<uint8_t>>>& levels, int size,
                            const std::string& origin) {
  CubeLevels cube;
  cube.size = size;
  for (size_t l = 0; l < levels.size(); ++l) {
    const int s = cube.level_size(int(l));
    if (levels[l].size() != 6) throw Error(origin + ": level " + std::to_string(l) + " does not have six faces");
    std::vector<float> rgba;
    rgba.reserve(4 * 6 * size_t(s) * size_t(s));
    for (size_t f = 0; f < 6; ++f) {
      const std::vector<float> face =
          decode_rgbd_face(levels[l][f], s, origin + ": face " + std::to_string(f) + " of level " + std::to_string(l));
      rgba.insert(rgba.end(), face.begin(), face.end());
    }
    cube.levels.push_back(std::move(rgba));
  }
  return cube;
}

}  // namespace brdfbake::io
