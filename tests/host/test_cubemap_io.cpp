// Cubemap containers read back field by field from the raw bytes, at offsets worked out from the
// specifications (KTX 2.0, KTX 1.1, the DDS programming guide), never through our own readers;
// folders of EXR/HDR images read back through OpenImageIO; and atomicity.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "io/cubemap_io.hpp"
#include "io/half.hpp"
#include "io/ktx2.hpp"
#include "support/temp_dir.hpp"
#include "support/tolerances.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;

// A fresh, empty folder `name` in the test's temporary folder (removed when the test ends).
fs::path temp_dir(const std::string& name) { return brdfbake::test::test_temp_dir(name); }

std::vector<uint8_t> read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

uint32_t u32(const std::vector<uint8_t>& b, size_t at) {
  return uint32_t(b.at(at)) | uint32_t(b.at(at + 1)) << 8 | uint32_t(b.at(at + 2)) << 16 | uint32_t(b.at(at + 3)) << 24;
}
uint64_t u64(const std::vector<uint8_t>& b, size_t at) { return uint64_t(u32(b, at)) | uint64_t(u32(b, at + 4)) << 32; }
float f32(const std::vector<uint8_t>& b, size_t at) {
  const uint32_t bits = u32(b, at);
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}
float f16(const std::vector<uint8_t>& b, size_t at) {
  return io::half_bits_to_float(static_cast<uint16_t>(b.at(at) | b.at(at + 1) << 8));
}

// A cube whose every texel value names its place: R = level + face / 8, G = i, B = j (small
// integers and eighths, exact in half), A = 1.
CubeLevels labelled_cube(int size, int levels) {
  CubeLevels c;
  c.size = size;
  for (int l = 0; l < levels; ++l) {
    const int s = std::max(1, size >> l);
    std::vector<float> v;
    for (int f = 0; f < 6; ++f)
      for (int j = 0; j < s; ++j)
        for (int i = 0; i < s; ++i) v.insert(v.end(), {float(l) + float(f) / 8.0f, float(i), float(j), 1.0f});
    c.levels.push_back(v);
  }
  c.set_meta("roughness_schedule", "linear");
  c.set_meta("lod_from_roughness", "lod = (levels - 1) * roughness");
  return c;
}

void expect_texel(float r, float g, float b, int level, int face, int i, int j) {
  EXPECT_FLOAT_EQ(r, float(level) + float(face) / 8.0f) << "level " << level << " face " << face;
  EXPECT_FLOAT_EQ(g, float(i));
  EXPECT_FLOAT_EQ(b, float(j));
}

TEST(CubeIo, Ktx2FieldByField) {
  const fs::path dir = temp_dir("ktx2");
  const CubeLevels cube = labelled_cube(8, 3);
  for (PixelType px : {PixelType::F16, PixelType::F32}) {
    const fs::path path = dir / "c.ktx2";
    CubeWriteOptions o;
    o.pixel = px;
    write_cubemap(cube, path.string(), CubeFormat::Ktx2, o);
    const auto b = read_all(path);
    const bool half = px == PixelType::F16;
    const uint32_t texel = half ? 8 : 16;
    EXPECT_EQ(std::memcmp(b.data(), "\xABKTX 20\xBB\r\n\x1A\n", 12), 0);
    EXPECT_EQ(u32(b, 12), half ? 97u : 109u);  // vkFormat
    EXPECT_EQ(u32(b, 16), half ? 2u : 4u);     // typeSize
    EXPECT_EQ(u32(b, 20), 8u);                 // pixelWidth
    EXPECT_EQ(u32(b, 24), 8u);                 // pixelHeight
    EXPECT_EQ(u32(b, 28), 0u);                 // pixelDepth
    EXPECT_EQ(u32(b, 32), 0u);                 // layerCount
    EXPECT_EQ(u32(b, 36), 6u);                 // faceCount
    EXPECT_EQ(u32(b, 40), 3u);                 // levelCount
    EXPECT_EQ(u32(b, 44), 0u);                 // supercompressionScheme
    EXPECT_EQ(u32(b, 48), 80u + 3 * 24);       // dfdByteOffset: right after the level index
    for (uint32_t l = 0; l < 3; ++l) {
      const uint64_t offset = u64(b, 80 + 24 * l), length = u64(b, 88 + 24 * l);
      const uint64_t s = 8u >> l;
      EXPECT_EQ(length, 6 * s * s * texel) << l;
      EXPECT_EQ(u64(b, 96 + 24 * l), length);
      EXPECT_EQ(offset % (half ? 8 : 16), 0u);  // mipPadding: lcm(texel size, 4)
      // texel (i, j) = (3 >> l, 1 >> l) of face 5
      const int i = 3 >> l, j = 1 >> l;
      const uint64_t at = offset + ((5 * s + uint64_t(j)) * s + uint64_t(i)) * texel;
      if (half)
        expect_texel(f16(b, at), f16(b, at + 2), f16(b, at + 4), int(l), 5, i, j);
      else
        expect_texel(f32(b, at), f32(b, at + 4), f32(b, at + 8), int(l), 5, i, j);
    }
    // levels are stored smallest first; level 0 ends the file
    EXPECT_EQ(u64(b, 80) + u64(b, 88), b.size());
    EXPECT_LT(u64(b, 80 + 48), u64(b, 80 + 24));
    const io::Ktx2Image k = io::decode_ktx2(b);  // the key/values through the validated reader
    bool schedule = false;
    for (const auto& [key, value] : k.key_values)
      schedule |= key == "brdfbake:lod_from_roughness" && value == "lod = (levels - 1) * roughness";
    EXPECT_TRUE(schedule);
  }
  // and back in as an environment
  const EnvImage env = read_ktx2_cube((dir / "c.ktx2").string(), 1);
  EXPECT_EQ(env.layout, EnvImage::Layout::Cube);
  EXPECT_EQ(env.width, 4);
  expect_texel(env.rgb[3 * ((2 * 4 + 3) * 4 + 1)], env.rgb[3 * ((2 * 4 + 3) * 4 + 1) + 1],
               env.rgb[3 * ((2 * 4 + 3) * 4 + 1) + 2], 1, 2, 1, 3);
  fs::remove_all(dir);
}

TEST(CubeIo, Ktx1FieldByField) {
  const fs::path dir = temp_dir("ktx1");
  const CubeLevels cube = labelled_cube(4, 3);
  const fs::path path = dir / "c.ktx";
  write_cubemap(cube, path.string(), CubeFormat::Ktx1);
  const auto b = read_all(path);
  EXPECT_EQ(std::memcmp(b.data(), "\xABKTX 11\xBB\r\n\x1A\n", 12), 0);
  EXPECT_EQ(u32(b, 12), 0x04030201u);  // endianness
  EXPECT_EQ(u32(b, 16), 0x140Bu);      // glType GL_HALF_FLOAT
  EXPECT_EQ(u32(b, 20), 2u);           // glTypeSize
  EXPECT_EQ(u32(b, 24), 0x1908u);      // glFormat GL_RGBA
  EXPECT_EQ(u32(b, 28), 0x881Au);      // glInternalFormat GL_RGBA16F
  EXPECT_EQ(u32(b, 32), 0x1908u);      // glBaseInternalFormat
  EXPECT_EQ(u32(b, 36), 4u);           // pixelWidth
  EXPECT_EQ(u32(b, 40), 4u);           // pixelHeight
  EXPECT_EQ(u32(b, 44), 0u);           // pixelDepth
  EXPECT_EQ(u32(b, 48), 0u);           // numberOfArrayElements
  EXPECT_EQ(u32(b, 52), 6u);           // numberOfFaces
  EXPECT_EQ(u32(b, 56), 3u);           // numberOfMipmapLevels
  const uint32_t kvd = u32(b, 60);
  EXPECT_EQ(kvd % 4, 0u);
  // key/value pairs: keyAndValueByteSize, key NUL value NUL, padding to 4
  size_t at = 64;
  bool found = false;
  while (at < 64 + kvd) {
    const uint32_t n = u32(b, at);
    const std::string kv(reinterpret_cast<const char*>(&b[at + 4]), n);
    found |= kv == std::string("brdfbake:roughness_schedule\0linear\0", 35);
    at += 4 + (n + 3) / 4 * 4;
  }
  EXPECT_EQ(at, 64u + kvd);
  EXPECT_TRUE(found);
  // levels: imageSize (one face), six faces
  for (int l = 0; l < 3; ++l) {
    const uint32_t s = 4u >> l;
    EXPECT_EQ(u32(b, at), s * s * 8) << l;
    const size_t face3 = at + 4 + 3 * s * s * 8;
    const size_t t = face3 + ((s - 1) * s + 0) * 8;  // texel (0, s - 1) of face 3
    expect_texel(f16(b, t), f16(b, t + 2), f16(b, t + 4), l, 3, 0, int(s) - 1);
    at += 4 + 6 * s * s * 8;
  }
  EXPECT_EQ(at, b.size());
  fs::remove_all(dir);
}

TEST(CubeIo, DdsDx10AndLegacyFieldByField) {
  const fs::path dir = temp_dir("dds");
  const CubeLevels cube = labelled_cube(4, 3);
  for (bool dx10 : {true, false}) {
    const fs::path path = dir / (dx10 ? "c.dds" : "legacy.dds");
    CubeWriteOptions o;
    o.pixel = PixelType::F32;
    write_cubemap(cube, path.string(), dx10 ? CubeFormat::Dds : CubeFormat::DdsLegacy, o);
    const auto b = read_all(path);
    EXPECT_EQ(u32(b, 0), 0x20534444u);  // "DDS "
    EXPECT_EQ(u32(b, 4), 124u);         // dwSize
    EXPECT_EQ(u32(b, 8),
              0x1u | 0x2u | 0x4u | 0x8u | 0x1000u | 0x20000u);  // caps height width pitch pixelformat mipmapcount
    EXPECT_EQ(u32(b, 12), 4u);                                  // dwHeight
    EXPECT_EQ(u32(b, 16), 4u);                                  // dwWidth
    EXPECT_EQ(u32(b, 20), 4u * 16);                             // dwPitchOrLinearSize
    EXPECT_EQ(u32(b, 24), 0u);                                  // dwDepth
    EXPECT_EQ(u32(b, 28), 3u);                                  // dwMipMapCount
    for (size_t r = 32; r < 76; r += 4) EXPECT_EQ(u32(b, r), 0u) << "dwReserved1 at " << r;
    EXPECT_EQ(u32(b, 76), 32u);                        // ddspf.dwSize
    EXPECT_EQ(u32(b, 80), 0x4u);                       // DDPF_FOURCC
    EXPECT_EQ(u32(b, 84), dx10 ? 0x30315844u : 116u);  // "DX10" / D3DFMT_A32B32G32R32F
    for (size_t r = 88; r < 108; r += 4) EXPECT_EQ(u32(b, r), 0u);
    EXPECT_EQ(u32(b, 108), 0x8u | 0x1000u | 0x400000u);  // COMPLEX TEXTURE MIPMAP
    EXPECT_EQ(u32(b, 112), 0xFE00u);                     // CUBEMAP + all six faces
    EXPECT_EQ(u32(b, 116), 0u);
    EXPECT_EQ(u32(b, 120), 0u);
    EXPECT_EQ(u32(b, 124), 0u);
    size_t data = 128;
    if (dx10) {
      EXPECT_EQ(u32(b, 128), 2u);    // DXGI_FORMAT_R32G32B32A32_FLOAT
      EXPECT_EQ(u32(b, 132), 3u);    // D3D10_RESOURCE_DIMENSION_TEXTURE2D
      EXPECT_EQ(u32(b, 136), 0x4u);  // DDS_RESOURCE_MISC_TEXTURECUBE
      EXPECT_EQ(u32(b, 140), 1u);    // arraySize
      EXPECT_EQ(u32(b, 144), 0u);    // miscFlags2
      data = 148;
    }
    // faces outer, levels inner: 16 + 4 + 1 texels a face
    EXPECT_EQ(b.size(), data + 6 * 21 * 16);
    const size_t face2_level1 = data + 2 * 21 * 16 + 16 * 16;
    const size_t t = face2_level1 + (1 * 2 + 1) * 16;  // texel (1, 1)
    expect_texel(f32(b, t), f32(b, t + 4), f32(b, t + 8), 1, 2, 1, 1);
    EXPECT_TRUE(fs::exists(path.string() + ".json")) << "DDS metadata sidecar";
  }
  fs::remove_all(dir);
}

TEST(CubeIo, FoldersOfImages) {
  const fs::path dir = temp_dir("folders");
  const CubeLevels cube = labelled_cube(4, 2);
  auto read_image = [](const fs::path& p, int& w, int& h) {
    auto in = OIIO::ImageInput::open(p.string());
    EXPECT_TRUE(in) << p;
    if (!in) return std::vector<float>{};
    w = in->spec().width;
    h = in->spec().height;
    std::vector<float> px(size_t(w) * size_t(h) * 3);
    in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, px.data());
    return px;
  };
  {
    CubeWriteOptions o;
    write_cubemap(cube, (dir / "faces").string(), CubeFormat::Directory, o);
    int w = 0, h = 0;
    const auto px = read_image(dir / "faces" / "level1_nz.exr", w, h);
    EXPECT_EQ(w, 2);
    EXPECT_EQ(h, 2);
    expect_texel(px[3 * 3], px[3 * 3 + 1], px[3 * 3 + 2], 1, 5, 1, 1);
    const auto j = nlohmann::json::parse(std::ifstream(dir / "faces" / "level.json"));
    EXPECT_EQ(j["layout"], "faces");
    EXPECT_EQ(j["files"].size(), 12u);
    EXPECT_EQ(j["metadata"]["roughness_schedule"], "linear");
  }
  {
    CubeWriteOptions o;
    o.layout = CubeImageLayout::HorizontalCross;
    o.image_format = CubeImageFormat::Hdr;
    write_cubemap(cube, (dir / "cross").string(), CubeFormat::Directory, o);
    int w = 0, h = 0;
    const auto px = read_image(dir / "cross" / "level0.hdr", w, h);
    EXPECT_EQ(w, 16);
    EXPECT_EQ(h, 12);
    // -Z is the fourth cell of the middle row; RGBE keeps these values to ~1%
    const size_t at = 3 * (size_t(4 + 2) * 16 + 12 + 3);
    EXPECT_NEAR(px[at], 5.0 / 8.0, test::kRgbeStepOfLargest * 3.0);
    EXPECT_NEAR(px[at + 1], 3.0, test::kRgbeStepOfLargest * 3.0);
    EXPECT_NEAR(px[at + 2], 2.0, test::kRgbeStepOfLargest * 3.0);
  }
  {
    CubeWriteOptions o;
    o.layout = CubeImageLayout::VerticalCross;
    write_cubemap(cube, (dir / "vcross").string(), CubeFormat::Directory, o);
    int w = 0, h = 0;
    const auto px = read_image(dir / "vcross" / "level0.exr", w, h);
    EXPECT_EQ(w, 12);
    EXPECT_EQ(h, 16);
    // -Z is the bottom cell, turned by 180 degrees: its top-left pixel is texel (3, 3)
    const size_t at = 3 * (size_t(12) * 12 + 4);
    expect_texel(px[at], px[at + 1], px[at + 2], 0, 5, 3, 3);
  }
  {
    CubeWriteOptions o;
    o.layout = CubeImageLayout::Equirect;
    write_cubemap(cube, (dir / "equirect").string(), CubeFormat::Directory, o);
    int w = 0, h = 0;
    const auto px = read_image(dir / "equirect" / "level0.exr", w, h);
    EXPECT_EQ(w, 16);
    EXPECT_EQ(h, 8);
    // the centre of the image looks along +Z (face 4)
    const size_t at = 3 * (size_t(4) * 16 + 8);
    EXPECT_NEAR(px[at], 4.0 / 8.0, test::kFloatResampling);
  }
  fs::remove_all(dir);
}

TEST(CubeIo, FailuresLeaveNothing) {
  const fs::path dir = temp_dir("atomic");
  const CubeLevels cube = labelled_cube(4, 2);
  std::ofstream(dir / "plain") << "x";
  EXPECT_THROW(write_cubemap(cube, (dir / "plain" / "c.ktx2").string(), CubeFormat::Ktx2), Error);
  EXPECT_THROW(write_cubemap(cube, (dir / "plain" / "c.dds").string(), CubeFormat::Dds), Error);
  EXPECT_THROW(write_cubemap(cube, (dir / "plain" / "sub").string(), CubeFormat::Directory), Error);
  CubeLevels broken = cube;
  broken.levels[1].pop_back();
  EXPECT_THROW(write_cubemap(broken, (dir / "b.ktx").string(), CubeFormat::Ktx1), Error);
  EXPECT_THROW(write_cubemap(broken, (dir / "newdir").string(), CubeFormat::Directory), Error);
  int entries = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    (void)e;
    ++entries;
  }
  EXPECT_EQ(entries, 1) << "only 'plain' may remain";
  EXPECT_EQ(cube_format_from_path("a.KTX2"), CubeFormat::Ktx2);
  EXPECT_EQ(cube_format_from_path("a.ktx"), CubeFormat::Ktx1);
  EXPECT_EQ(cube_format_from_path("a.dds"), CubeFormat::Dds);
  EXPECT_EQ(cube_format_from_path((dir / "out/").string()), CubeFormat::Directory);
  EXPECT_THROW(cube_format_from_path("a.png"), Error);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace brdfbake
