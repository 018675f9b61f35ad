// Writing cubemaps with all their levels: KTX2 (through io/ktx2), KTX1, DDS (DX10 or legacy
// header), and folders of per-face, cross or equirect images (EXR / HDR through io/image_file).
// Every file goes through io::TempFile: it appears complete or not at all.
#include "io/cubemap_io.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "brdfbake/error.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/math/equirect.hpp"
#include "io/atomic_file.hpp"
#include "io/half.hpp"
#include "io/image_file.hpp"
#include "io/ktx2.hpp"
#include "io/packed_float.hpp"
#include "io/rgbe.hpp"

#ifndef BRDFBAKE_VERSION
#define BRDFBAKE_VERSION "unknown"
#endif

namespace brdfbake {

void CubeLevels::set_meta(const std::string& key, const std::string& value) {
  auto it = std::find_if(metadata.begin(), metadata.end(), [&](const auto& e) { return e.first == key; });
  if (it != metadata.end())
    it->second = value;
  else
    metadata.emplace_back(key, value);
}

std::string CubeLevels::meta(const std::string& key) const {
  auto it = std::find_if(metadata.begin(), metadata.end(), [&](const auto& e) { return e.first == key; });
  return it != metadata.end() ? it->second : std::string();
}

namespace io {
namespace {

namespace fs = std::filesystem;
constexpr const char* kGenerator = "brdfbake " BRDFBAKE_VERSION;
constexpr const char* kKeyPrefix = "brdfbake:";
const char* const kFaceNames[6] = {"px", "nx", "py", "ny", "pz", "nz"};

void put_u32(std::vector<uint8_t>& out, size_t at, uint32_t v) {
  for (size_t i = 0; i < 4; ++i) out[at + i] = static_cast<uint8_t>(v >> (8 * i));
}
void append_u32(std::vector<uint8_t>& out, uint32_t v) {
  out.resize(out.size() + 4);
  put_u32(out, out.size() - 4, v);
}
void pad_to(std::vector<uint8_t>& out, size_t alignment) {
  while (out.size() % alignment != 0) out.push_back(0);
}

void check_cube(const CubeLevels& cube) {
  if (cube.size < 1 || cube.levels.empty()) throw Error("cube writer: empty cube");
  for (int l = 0; l < cube.level_count(); ++l) {
    const size_t s = static_cast<size_t>(cube.level_size(l));
    if (cube.levels[size_t(l)].size() != 24 * s * s)
      throw Error("cube writer: level " + std::to_string(l) + " holds " +
                  std::to_string(cube.levels[size_t(l)].size()) + " floats, expected " + std::to_string(24 * s * s));
  }
}

std::string_view as_view(const std::vector<uint8_t>& b) {
  return std::string_view(reinterpret_cast<const char*>(b.data()), b.size());
}

// ---- Image folders ------------------------------------------------------------------------------

// One image of a folder: float RGB OpenEXR (ZIP, the metadata as "brdfbake:KEY" attributes) or
// Radiance RGBE (no metadata: the folder's JSON has it; RGBE has no sign and no infinity, so a
// negative or NaN value, which the filters do not produce, would be written as 0 and one beyond
// kRgbeMax as kRgbeMax).
void write_image(const TempFile& temp, CubeImageFormat format, int w, int h, const std::vector<float>& rgb,
                 const Metadata& metadata) {
  if (format == CubeImageFormat::Hdr) {
    std::vector<float> clamped(rgb.size());
    for (size_t k = 0; k < rgb.size(); ++k) clamped[k] = rgb[k] >= 0.0f ? std::min(rgb[k], kRgbeMax) : 0.0f;
    write_rgbe(temp, w, h, clamped.data());
    return;
  }
  std::vector<std::pair<std::string, std::string>> attributes;
  for (const auto& [k, v] : metadata) attributes.emplace_back(kKeyPrefix + k, v);
  write_exr(temp, w, h, 3, rgb.data(), attributes);
}

// RGB of one face of a level, row 0 first.
std::vector<float> face_rgb(const CubeLevels& cube, int level, int face) {
  const int s = cube.level_size(level);
  std::vector<float> rgb;
  rgb.reserve(3u * size_t(s) * size_t(s));
  for (int j = 0; j < s; ++j)
    for (int i = 0; i < s; ++i) {
      const float* t = cube.texel(level, face, i, j);
      rgb.insert(rgb.end(), t, t + 3);
    }
  return rgb;
}

// A cross of one level (docs/CONVENTIONS.md; the same layouts load_environment reads).
std::vector<float> cross_rgb(const CubeLevels& cube, int level, bool horizontal, int* w, int* h) {
  struct Cell {
    int col, row;
    bool rotate;
  };
  static const Cell hz[6] = {{2, 1, false}, {0, 1, false}, {1, 0, false}, {1, 2, false}, {1, 1, false}, {3, 1, false}};
  static const Cell vt[6] = {{2, 1, false}, {0, 1, false}, {1, 0, false}, {1, 2, false}, {1, 1, false}, {1, 3, true}};
  const int s = cube.level_size(level);
  *w = horizontal ? 4 * s : 3 * s;
  *h = horizontal ? 3 * s : 4 * s;
  std::vector<float> rgb(3u * size_t(*w) * size_t(*h), 0.0f);
  for (int f = 0; f < 6; ++f) {
    const Cell c = horizontal ? hz[f] : vt[f];
    for (int j = 0; j < s; ++j)
      for (int i = 0; i < s; ++i) {
        const float* t = cube.texel(level, f, c.rotate ? s - 1 - i : i, c.rotate ? s - 1 - j : j);
        float* o = &rgb[3 * (size_t(c.row * s + j) * size_t(*w) + size_t(c.col * s + i))];
        std::copy(t, t + 3, o);
      }
  }
  return rgb;
}

// The texel (i, j) of `face` of a level for i, j in [-1, s]: inside the face, the texel; one index
// outside, the texel of the neighbouring face nearest to the extended texel centre; both outside
// (a corner), the mean of the three texels around it (docs/CONVENTIONS.md, "Environment maps": the
// seamless bilinear environment).
void fetch_extended(const CubeLevels& cube, int level, int face, int i, int j, double out[3]) {
  const int s = cube.level_size(level);
  const bool in_i = i >= 0 && i < s, in_j = j >= 0 && j < s;
  if (in_i && in_j) {
    const float* t = cube.texel(level, face, i, j);
    for (int c = 0; c < 3; ++c) out[c] = t[c];
    return;
  }
  if (!in_i && !in_j) {
    const int ci = std::clamp(i, 0, s - 1), cj = std::clamp(j, 0, s - 1);
    double p[3], q[3], r[3];
    fetch_extended(cube, level, face, ci, j, p);
    fetch_extended(cube, level, face, i, cj, q);
    fetch_extended(cube, level, face, ci, cj, r);
    for (int c = 0; c < 3; ++c) out[c] = (p[c] + q[c] + r[c]) / 3.0;
    return;
  }
  int f = 0;
  double a = 0, b = 0;
  math::cube_face_coords(math::cube_plane_point(face, 2.0 * (i + 0.5) / s - 1.0, 2.0 * (j + 0.5) / s - 1.0), f, a, b);
  const int ni = std::clamp(static_cast<int>(std::floor(0.5 * (a + 1.0) * s)), 0, s - 1);
  const int nj = std::clamp(static_cast<int>(std::floor(0.5 * (b + 1.0) * s)), 0, s - 1);
  const float* t = cube.texel(level, f, ni, nj);
  for (int c = 0; c < 3; ++c) out[c] = t[c];
}

// The seamless bilinear interpolation of a level's texels at direction d.
void cube_bilinear(const CubeLevels& cube, int level, const Vec3& d, double out[3]) {
  const int s = cube.level_size(level);
  int face = 0;
  double a = 0, b = 0;
  math::cube_face_coords(d, face, a, b);
  const double x = 0.5 * (a + 1.0) * s - 0.5, y = 0.5 * (b + 1.0) * s - 0.5;
  const double x0 = std::floor(x), y0 = std::floor(y), fx = x - x0, fy = y - y0;
  const int i0 = static_cast<int>(x0), j0 = static_cast<int>(y0);
  double t00[3], t10[3], t01[3], t11[3];
  fetch_extended(cube, level, face, i0, j0, t00);
  fetch_extended(cube, level, face, i0 + 1, j0, t10);
  fetch_extended(cube, level, face, i0, j0 + 1, t01);
  fetch_extended(cube, level, face, i0 + 1, j0 + 1, t11);
  for (int c = 0; c < 3; ++c)
    out[c] = (1.0 - fy) * ((1.0 - fx) * t00[c] + fx * t10[c]) + fy * ((1.0 - fx) * t01[c] + fx * t11[c]);
}

// An equirect of one level (4 s x 2 s): each pixel the seamless bilinear value at its centre.
std::vector<float> equirect_rgb(const CubeLevels& cube, int level, int* w, int* h) {
  const int s = cube.level_size(level);
  *w = std::max(4, 4 * s);
  *h = *w / 2;
  std::vector<float> rgb(3u * size_t(*w) * size_t(*h));
  for (int y = 0; y < *h; ++y)
    for (int x = 0; x < *w; ++x) {
      double v[3];
      cube_bilinear(cube, level, math::equirect_direction((x + 0.5) / *w, (y + 0.5) / *h), v);
      for (size_t c = 0; c < 3; ++c) rgb[3 * (size_t(y) * size_t(*w) + size_t(x)) + c] = static_cast<float>(v[c]);
    }
  return rgb;
}

std::string metadata_json(const Metadata& metadata, const std::vector<std::string>& files, const std::string& layout) {
  nlohmann::ordered_json j;
  j["generator"] = kGenerator;
  j["layout"] = layout;
  j["files"] = files;
  nlohmann::ordered_json meta = nlohmann::ordered_json::object();
  for (const auto& [k, v] : metadata) meta[k] = v;
  j["metadata"] = meta;
  return j.dump(2) + "\n";
}

void write_directory(const CubeLevels& cube, const Metadata& metadata, const std::string& path,
                     const CubeWriteOptions& o) {
  std::error_code ec;
  const bool existed = fs::is_directory(path, ec);
  if (!existed && fs::exists(path, ec)) throw_write_error(path, "exists and is not a folder");
  if (!existed && !fs::create_directories(path, ec)) throw_write_error(path, ec ? ec.message() : "cannot create");
  // All files go to temporaries first and are renamed only when every one is complete; a folder
  // we created is removed again on failure.
  try {
    std::vector<std::unique_ptr<TempFile>> temps;
    std::vector<std::string> names;
    const char* ext = o.image_format == CubeImageFormat::Exr ? ".exr" : ".hdr";
    auto write_one = [&](const std::string& name, int w, int h, const std::vector<float>& rgb) {
      const std::string file = (fs::path(path) / name).string();
      temps.push_back(std::make_unique<TempFile>(file));
      write_image(*temps.back(), o.image_format, w, h, rgb, metadata);
      names.push_back(name);
    };
    const std::string layout = o.layout == CubeImageLayout::Faces             ? "faces"
                               : o.layout == CubeImageLayout::HorizontalCross ? "horizontal-cross"
                               : o.layout == CubeImageLayout::VerticalCross   ? "vertical-cross"
                                                                              : "equirect";
    for (int l = 0; l < cube.level_count(); ++l) {
      const std::string base = o.stem + std::to_string(l);
      const int s = cube.level_size(l);
      if (o.layout == CubeImageLayout::Faces) {
        for (int f = 0; f < 6; ++f) write_one(base + "_" + kFaceNames[f] + ext, s, s, face_rgb(cube, l, f));
      } else if (o.layout == CubeImageLayout::Equirect) {
        int w = 0, h = 0;
        const auto rgb = equirect_rgb(cube, l, &w, &h);
        write_one(base + ext, w, h, rgb);
      } else {
        int w = 0, h = 0;
        const auto rgb = cross_rgb(cube, l, o.layout == CubeImageLayout::HorizontalCross, &w, &h);
        write_one(base + ext, w, h, rgb);
      }
    }
    const std::string json = (fs::path(path) / (o.stem + ".json")).string();
    temps.push_back(std::make_unique<TempFile>(json));
    write_bytes(*temps.back(), metadata_json(metadata, names, layout));
    for (auto& t : temps) t->commit();
  } catch (...) {
    if (!existed) fs::remove_all(path, ec);
    throw;
  }
}

}  // namespace

namespace {
bool is_little_endian() {
  const uint16_t one = 1;
  uint8_t first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

size_t texel_bytes(PixelType pixel) { return pixel == PixelType::R11G11B10 ? 4 : pixel == PixelType::F16 ? 8 : 16; }

void texels_to_bytes(const float* rgba, size_t texels, PixelType pixel, uint8_t* out, int* saturated) {
  const size_t n = 4 * texels;
  if (pixel == PixelType::R11G11B10) {  // RGB packed into one UInt32, alpha dropped
    for (size_t t = 0; t < texels; ++t) {
      const uint32_t p = pack_r11g11b10(rgba[4 * t], rgba[4 * t + 1], rgba[4 * t + 2], saturated);
      for (size_t i = 0; i < 4; ++i) out[4 * t + i] = static_cast<uint8_t>(p >> (8 * i));
    }
    return;
  }
  if (pixel == PixelType::F16) {
    // little-endian: where the host is, its uint16 are the file's bytes
    if (is_little_endian()) {
      floats_to_half_bits(rgba, n, reinterpret_cast<uint16_t*>(out));
    } else {
      std::vector<uint16_t> bits(n);
      floats_to_half_bits(rgba, n, bits.data());
      for (size_t k = 0; k < n; ++k) {
        out[2 * k] = static_cast<uint8_t>(bits[k]);
        out[2 * k + 1] = static_cast<uint8_t>(bits[k] >> 8);
      }
    }
    return;
  }
  for (size_t k = 0; k < n; ++k) {
    uint32_t b = 0;
    std::memcpy(&b, &rgba[k], 4);
    for (size_t i = 0; i < 4; ++i) out[4 * k + i] = static_cast<uint8_t>(b >> (8 * i));
  }
}

}  // namespace

std::vector<std::vector<uint8_t>> cube_level_bytes(const CubeLevels& cube, PixelType pixel, int* saturated) {
  check_cube(cube);
  std::vector<std::vector<uint8_t>> out;
  for (const auto& level : cube.levels) {
    std::vector<uint8_t> bytes(level.size() / 4 * texel_bytes(pixel));
    texels_to_bytes(level.data(), level.size() / 4, pixel, bytes.data(), saturated);
    out.push_back(std::move(bytes));
  }
  return out;
}

void put_cube_level_bytes(const CubeLevels& cube, int level, PixelType pixel,
                          const std::function<void(const uint8_t*, size_t)>& put) {
  const std::vector<float>& data = cube.levels.at(size_t(level));
  constexpr size_t kChunkTexels = size_t(1) << 16;  // 512 KiB of binary16, 1 MiB of float
  std::vector<uint8_t> bytes(std::min(kChunkTexels, data.size() / 4) * texel_bytes(pixel));
  for (size_t t = 0; t < data.size() / 4; t += kChunkTexels) {
    const size_t n = std::min(kChunkTexels, data.size() / 4 - t);
    texels_to_bytes(data.data() + 4 * t, n, pixel, bytes.data(), nullptr);
    put(bytes.data(), n * texel_bytes(pixel));
  }
}

std::vector<std::pair<std::string, std::string>> cube_key_values(const CubeLevels& cube, int ktx_version) {
  return metadata_key_values(cube.metadata, ktx_version);
}

std::vector<std::pair<std::string, std::string>> metadata_key_values(const Metadata& metadata, int ktx_version) {
  std::vector<std::pair<std::string, std::string>> kv;
  for (const auto& [k, v] : metadata) kv.emplace_back(kKeyPrefix + k, v);
  if (ktx_version == 2) {
    // KTX 2.0 "KTXwriter" and "KTXorientation": cubemap faces must be "rd" (row 0 at the top).
    kv.emplace_back("KTXwriter", kGenerator);
    kv.emplace_back("KTXorientation", "rd");
  } else {
    // KTX 1.1 defines KTXorientation (as "S=r,T=d") but no writer key: the writer goes under our
    // own prefix, so that KTX-Software's ktx2ktx2, which adds its own KTXwriter, makes no duplicate.
    kv.emplace_back("KTXorientation", "S=r,T=d");
    kv.emplace_back(std::string(kKeyPrefix) + "writer", kGenerator);
  }
  return kv;
}

// KTX 1.1 "File Structure". Every face row of RGBA16F/32F and of packed R11F_G11F_B10F is a
// multiple of 4 bytes, so rows need no GL_UNPACK_ALIGNMENT padding, and cubePadding and mipPadding
// are always empty.
std::vector<uint8_t> encode_ktx1_cube(const CubeLevels& cube, PixelType pixel,
                                      const std::vector<std::pair<std::string, std::string>>& key_values,
                                      const Ktx1Options& options) {
  const auto levels = cube_level_bytes(cube, pixel, options.saturated);
  static const uint8_t kId[12] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x31, 0x31, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
  std::vector<uint8_t> out(kId, kId + 12);
  const bool half = pixel == PixelType::F16;
  append_u32(out, 0x04030201);  // endianness
  if (pixel == PixelType::R11G11B10) {
    append_u32(out, options.filament_r11_gltype ? kGlR11fG11fB10f : kGlUnsignedInt10f11f11fRev);  // glType
    append_u32(out, 4);                // glTypeSize: the packed UInt32
    append_u32(out, kGlRgb);           // glFormat
    append_u32(out, kGlR11fG11fB10f);  // glInternalFormat
    append_u32(out, kGlRgb);           // glBaseInternalFormat
  } else {
    append_u32(out, half ? kGlHalfFloat : kGlFloat);  // glType
    append_u32(out, half ? 2 : 4);                    // glTypeSize
    append_u32(out, kGlRgba);                         // glFormat
    append_u32(out, half ? kGlRgba16f : kGlRgba32f);  // glInternalFormat
    append_u32(out, kGlRgba);                         // glBaseInternalFormat
  }
  append_u32(out, static_cast<uint32_t>(cube.size));      // pixelWidth
  append_u32(out, static_cast<uint32_t>(cube.size));      // pixelHeight
  append_u32(out, 0);                                     // pixelDepth
  append_u32(out, 0);                                     // numberOfArrayElements
  append_u32(out, 6);                                     // numberOfFaces
  append_u32(out, static_cast<uint32_t>(levels.size()));  // numberOfMipmapLevels
  const size_t kvd_at = out.size();
  append_u32(out, 0);  // bytesOfKeyValueData, patched below
  for (const auto& [k, v] : key_values) {
    append_u32(out, static_cast<uint32_t>(k.size() + 1 + v.size() + 1));  // keyAndValueByteSize
    out.insert(out.end(), k.begin(), k.end());
    out.push_back(0);
    out.insert(out.end(), v.begin(), v.end());
    out.push_back(0);
    pad_to(out, 4);  // valuePadding
  }
  put_u32(out, kvd_at, static_cast<uint32_t>(out.size() - kvd_at - 4));
  for (const auto& level : levels) {
    const size_t face_bytes = level.size() / 6;
    append_u32(out, static_cast<uint32_t>(face_bytes));  // imageSize: one face (non-array cube)
    for (size_t f = 0; f < 6; ++f) {
      out.insert(out.end(), level.begin() + static_cast<std::ptrdiff_t>(f * face_bytes),
                 level.begin() + static_cast<std::ptrdiff_t>((f + 1) * face_bytes));
      pad_to(out, 4);  // cubePadding
    }
    pad_to(out, 4);  // mipPadding
  }
  return out;
}

// DDS: magic, DDS_HEADER, [DDS_HEADER_DXT10], then faces in order, each with all its mip levels
// (the opposite nesting of KTX).
std::vector<uint8_t> encode_dds_cube(const CubeLevels& cube, PixelType pixel, bool dx10_header) {
  if (pixel == PixelType::R11G11B10 && !dx10_header)
    throw Error("DDS: R11F_G11F_B10F needs the DX10 header (the legacy header has no such format)");
  const auto levels = cube_level_bytes(cube, pixel);
  const bool half = pixel == PixelType::F16;
  const bool packed = pixel == PixelType::R11G11B10;
  const uint32_t texel_bytes = packed ? 4 : half ? 8 : 16;
  std::vector<uint8_t> out;
  append_u32(out, kDdsMagic);
  append_u32(out, 124);  // dwSize
  append_u32(out, kDdsdCaps | kDdsdHeight | kDdsdWidth | kDdsdPitch | kDdsdPixelFormat | kDdsdMipMapCount);
  append_u32(out, static_cast<uint32_t>(cube.size));                // dwHeight
  append_u32(out, static_cast<uint32_t>(cube.size));                // dwWidth
  append_u32(out, static_cast<uint32_t>(cube.size) * texel_bytes);  // dwPitchOrLinearSize: row pitch
  append_u32(out, 0);                                               // dwDepth
  append_u32(out, static_cast<uint32_t>(levels.size()));            // dwMipMapCount
  for (int k = 0; k < 11; ++k) append_u32(out, 0);                  // dwReserved1
  // DDS_PIXELFORMAT
  append_u32(out, 32);
  append_u32(out, kDdpfFourCC);
  append_u32(out, dx10_header ? kFourCCDx10 : (half ? kD3dFmtA16B16G16R16F : kD3dFmtA32B32G32R32F));
  for (int k = 0; k < 5; ++k) append_u32(out, 0);  // dwRGBBitCount and the four masks
  append_u32(out, kDdsCapsComplex | kDdsCapsTexture | (levels.size() > 1 ? kDdsCapsMipMap : 0u));
  append_u32(out, kDdsCaps2CubemapAllFaces);
  append_u32(out, 0);  // dwCaps3
  append_u32(out, 0);  // dwCaps4
  append_u32(out, 0);  // dwReserved2
  if (dx10_header) {
    append_u32(out, packed ? kDxgiR11G11B10Float : half ? kDxgiR16G16B16A16Float : kDxgiR32G32B32A32Float);
    append_u32(out, kD3d10ResourceDimensionTexture2d);
    append_u32(out, kDdsResourceMiscTextureCube);
    append_u32(out, 1);  // arraySize: one cube
    append_u32(out, 0);  // miscFlags2: DDS_ALPHA_MODE_UNKNOWN
  }
  for (size_t f = 0; f < 6; ++f)
    for (const auto& level : levels) {
      const size_t face_bytes = level.size() / 6;
      out.insert(out.end(), level.begin() + static_cast<std::ptrdiff_t>(f * face_bytes),
                 level.begin() + static_cast<std::ptrdiff_t>((f + 1) * face_bytes));
    }
  return out;
}

}  // namespace io

CubeFormat cube_format_from_path(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".ktx2") return CubeFormat::Ktx2;
  if (ext == ".ktx") return CubeFormat::Ktx1;
  if (ext == ".dds") return CubeFormat::Dds;
  std::error_code ec;
  if (!path.empty() && (path.back() == '/' || std::filesystem::is_directory(path, ec) || ext.empty()))
    return CubeFormat::Directory;
  throw Error("cannot tell the output format of '" + path +
              "' (expected .ktx2, .ktx, .dds, or a folder for per-level images)");
}

void write_cubemap(const CubeLevels& cube, const std::string& path, CubeFormat format, const CubeWriteOptions& o) {
  io::write_cubemap_with_metadata(cube, cube.metadata, path, format, o);
}

void io::write_cubemap_with_metadata(const CubeLevels& cube, const Metadata& metadata, const std::string& path,
                                     CubeFormat format, const CubeWriteOptions& o) {
  io::check_cube(cube);
  switch (format) {
    case CubeFormat::Ktx2: {
      if (o.pixel == PixelType::R11G11B10)
        io::throw_write_error(path,
                              "R11F_G11F_B10F is written to .ktx (KTX1) and .dds only; use f16 or f32 for "
                              ".ktx2, or an ASTC HDR KTX2 (write_astc_ktx2_cube) for a compressed one");
      io::Ktx2Image image;
      const bool half = o.pixel == PixelType::F16;
      image.vk_format = half ? io::kVkFormatR16G16B16A16Sfloat : io::kVkFormatR32G32B32A32Sfloat;
      image.width = image.height = static_cast<uint32_t>(cube.size);
      image.faces = 6;
      image.levels = static_cast<uint32_t>(cube.level_count());
      image.key_values = io::metadata_key_values(metadata, 2);
      try {
        // streamed: each level converted a piece at a time as it is written, never a second chain
        io::write_ktx2(image, path, [&](uint32_t level, const std::function<void(const uint8_t*, size_t)>& put) {
          io::put_cube_level_bytes(cube, int(level), o.pixel, put);
        });
      } catch (const IoError&) {
        throw;
      } catch (const Error& e) {
        io::throw_write_error(path, e.what());
      }
      return;
    }
    case CubeFormat::Ktx1:
      io::write_file_atomically(path,
                                io::as_view(io::encode_ktx1_cube(cube, o.pixel, io::metadata_key_values(metadata, 1))));
      return;
    case CubeFormat::Dds:
    case CubeFormat::DdsLegacy: {
      // DDS has no metadata: it goes to a sidecar FILE.json, committed with the image.
      std::vector<uint8_t> dds;
      try {
        dds = io::encode_dds_cube(cube, o.pixel, format == CubeFormat::Dds);
      } catch (const Error& e) {
        io::throw_write_error(path, e.what());
      }
      io::TempFile image(path), json(path + ".json");
      io::write_bytes(image, io::as_view(dds));
      io::write_bytes(json, io::metadata_json(metadata, {std::filesystem::path(path).filename().string()},
                                              format == CubeFormat::Dds ? "dds-dx10" : "dds-legacy"));
      image.commit();
      json.commit();
      return;
    }
    case CubeFormat::Directory:
      io::write_directory(cube, metadata, path, o);
      return;
  }
}

EnvImage read_ktx2_cube(const std::string& path, int level) {
  const io::Ktx2Image k = io::read_ktx2(path);
  if (k.faces != 6) throw Error("'" + path + "' is not a cubemap (faceCount " + std::to_string(k.faces) + ")");
  uint32_t components = 0, bytes = 0;
  switch (k.vk_format) {
    case 90:
      components = 3;
      bytes = 2;
      break;  // R16G16B16_SFLOAT
    case 97:
      components = 4;
      bytes = 2;
      break;  // R16G16B16A16_SFLOAT
    case 106:
      components = 3;
      bytes = 4;
      break;  // R32G32B32_SFLOAT
    case 109:
      components = 4;
      bytes = 4;
      break;  // R32G32B32A32_SFLOAT
    default:
      throw Error("KTX2 cube '" + path + "' has vkFormat " + std::to_string(k.vk_format) +
                  "; expected RGB or RGBA, 16- or 32-bit float");
  }
  if (level < 0 || level >= static_cast<int>(k.levels))
    throw Error("KTX2 cube '" + path + "' has no level " + std::to_string(level));
  const uint32_t s = std::max(1u, k.width >> level);
  EnvImage env;
  env.layout = EnvImage::Layout::Cube;
  env.width = env.height = static_cast<int>(s);
  env.source = path;
  env.description = "KTX2 cube " + std::to_string(k.width) + "x" + std::to_string(k.width) + ", " +
                    std::to_string(k.levels) + " level(s), level " + std::to_string(level) + " read";
  const auto& data = k.level_data[size_t(level)];
  const size_t texels = 6u * size_t(s) * size_t(s);
  env.rgb.resize(3 * texels);
  for (size_t t = 0; t < texels; ++t)
    for (size_t c = 0; c < 3; ++c) {
      const uint8_t* p = data.data() + (t * components + c) * bytes;
      if (bytes == 2) {
        env.rgb[3 * t + c] = io::half_bits_to_float(static_cast<uint16_t>(p[0] | p[1] << 8));
      } else {
        uint32_t b = static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 |
                     static_cast<uint32_t>(p[2]) << 16 | static_cast<uint32_t>(p[3]) << 24;
        float f;
        std::memcpy(&f, &b, 4);
        env.rgb[3 * t + c] = f;
      }
    }
  return env;
}

}  // namespace brdfbake
