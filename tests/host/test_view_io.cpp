// The readers behind `brdfbake view`: KTX 1.1 and DDS cubes against the bytes our writers produce
// (whose every field tests/host/test_cubemap_io.cpp checks against the specifications), malformed
// files refused with a message, the table reader against write_table in every format (values,
// channels, metadata, axes), the axis rules of the metadata, and PNG through libpng.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/io.hpp"
#include "io/atomic_file.hpp"
#include "io/cubemap_io.hpp"
#include "io/dds.hpp"
#include "io/half.hpp"
#include "io/ktx1.hpp"
#include "io/png_image.hpp"
#include "io/table_read.hpp"
#include "support/temp_dir.hpp"
#include "support/tolerances.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;

// A fresh, empty folder `name` in the test's temporary folder (removed when the test ends).
fs::path temp_dir(const std::string& name) { return brdfbake::test::test_temp_dir(name); }

// Every texel names its place (exact in binary16): R = level + face / 8, G = i, B = j, A = 1.
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
  c.set_meta("roughness_per_level", "0,0.5,1");
  return c;
}

template <typename Fn>
std::string error_of(Fn&& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(ViewIo, Ktx1CubeReadsBackEveryLevelAndKey) {
  const CubeLevels cube = labelled_cube(8, 3);
  for (PixelType px : {PixelType::F16, PixelType::F32}) {
    const auto bytes = io::encode_ktx1_cube(cube, px, io::cube_key_values(cube, 1));
    const io::Ktx1Image k = io::decode_ktx1(bytes.data(), bytes.size(), "cube.ktx");
    EXPECT_EQ(k.width, 8u);
    EXPECT_EQ(k.height, 8u);
    EXPECT_EQ(k.faces, 6u);
    EXPECT_EQ(k.levels, 3u);
    EXPECT_EQ(k.components(), 4u);
    EXPECT_EQ(k.component_bytes(), px == PixelType::F16 ? 2u : 4u);
    EXPECT_EQ(k.level_data, io::cube_level_bytes(cube, px));
    bool found = false;
    for (const auto& [key, value] : k.key_values) found |= key == "brdfbake:roughness_per_level" && value == "0,0.5,1";
    EXPECT_TRUE(found);
  }
}

TEST(ViewIo, Ktx1MalformedFilesAreRefused) {
  const CubeLevels cube = labelled_cube(4, 2);
  const auto good = io::encode_ktx1_cube(cube, PixelType::F16, io::cube_key_values(cube, 1));
  auto truncated = good;
  truncated.resize(good.size() - 10);
  EXPECT_NE(error_of([&] { io::decode_ktx1(truncated.data(), truncated.size(), "t.ktx"); }).find("truncated"),
            std::string::npos);
  auto bad_id = good;
  bad_id[5] = '2';  // "KTX 21"
  EXPECT_NE(error_of([&] { io::decode_ktx1(bad_id.data(), bad_id.size(), "t.ktx"); }).find("identifier"),
            std::string::npos);
  auto big_endian = good;
  std::swap(big_endian[12], big_endian[15]);
  std::swap(big_endian[13], big_endian[14]);
  EXPECT_NE(error_of([&] { io::decode_ktx1(big_endian.data(), big_endian.size(), "t.ktx"); }).find("big-endian"),
            std::string::npos);
  auto levels = good;
  levels[56] = 9;  // numberOfMipmapLevels beyond log2(4) + 1
  EXPECT_NE(error_of([&] { io::decode_ktx1(levels.data(), levels.size(), "t.ktx"); }).find("too large"),
            std::string::npos);
  auto image_size = good;
  const size_t first_level = 64 + (size_t(image_size[60]) | size_t(image_size[61]) << 8);
  image_size[first_level] ^= 0x10;
  EXPECT_NE(error_of([&] { io::decode_ktx1(image_size.data(), image_size.size(), "t.ktx"); }).find("imageSize"),
            std::string::npos);
}

TEST(ViewIo, DdsCubeReadsBackWithEitherHeader) {
  const CubeLevels cube = labelled_cube(8, 3);
  for (bool dx10 : {true, false})
    for (PixelType px : {PixelType::F16, PixelType::F32}) {
      const auto bytes = io::encode_dds_cube(cube, px, dx10);
      const io::DdsImage d = io::decode_dds(bytes.data(), bytes.size(), "cube.dds");
      EXPECT_EQ(d.width, 8u);
      EXPECT_EQ(d.faces, 6u);
      EXPECT_EQ(d.levels, 3u);
      EXPECT_EQ(d.dx10_header, dx10);
      EXPECT_EQ(d.component_bytes, px == PixelType::F16 ? 2u : 4u);
      // The file nests level inside face; the reader gives KTX order (face inside level).
      EXPECT_EQ(d.level_data, io::cube_level_bytes(cube, px)) << "dx10 " << dx10;
    }
}

TEST(ViewIo, DdsMalformedFilesAreRefused) {
  const CubeLevels cube = labelled_cube(4, 2);
  const auto good = io::encode_dds_cube(cube, PixelType::F32, true);
  auto truncated = good;
  truncated.resize(good.size() - 4);
  EXPECT_NE(error_of([&] { io::decode_dds(truncated.data(), truncated.size(), "t.dds"); }).find("truncated"),
            std::string::npos);
  auto magic = good;
  magic[0] = 'X';
  EXPECT_NE(error_of([&] { io::decode_dds(magic.data(), magic.size(), "t.dds"); }).find("magic"), std::string::npos);
  auto format = good;
  format[128] = 71;  // DXGI_FORMAT_BC1_UNORM
  EXPECT_NE(error_of([&] { io::decode_dds(format.data(), format.size(), "t.dds"); }).find("DXGI format 71"),
            std::string::npos);
}

// A table whose values are exact in binary16 and in 16-bit UNORM steps of 1/64 (all in (0, 1)).
Table known_table(int width, int height, std::vector<std::string> channels) {
  Table t;
  t.width = width;
  t.height = height;
  t.channels = std::move(channels);
  t.x_name = "n_dot_v";
  for (int i = 0; i < width; ++i) t.x.push_back((i + 0.5) / width);
  if (height > 1) {
    t.y_name = "roughness";
    for (int j = 0; j < height; ++j) t.y.push_back((j + 0.5) / height);
  }
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i)
      for (int c = 0; c < t.channel_count(); ++c)
        t.data.push_back(float(i + width * j + 1) / 64.0f + float(c) / 256.0f);
  t.set_meta("kind", "test");
  t.set_meta("x_axis", "n_dot_v = (i + 0.5) / width, the cell centre of column i");
  if (height > 1) t.set_meta("y_axis", "roughness = (j + 0.5) / height, perceptual, the cell centre of row j");
  return t;
}

// What each format keeps: float formats and binary16 exactly (the values are exact in half), 16-bit
// PNG within half a step, RGBE within its shared-exponent step (<= largest / 128), text to 9 digits.
double format_tolerance(const std::string& ext) {
  if (ext == ".png") return 0.5 / 65535.0;
  if (ext == ".hdr") return 1.0 / 128.0;
  return 0.0;
}

TEST(ViewIo, TableReaderReadsWhatEveryWriterWrote) {
  const fs::path dir = temp_dir("tables");
  for (const auto& channels :
       {std::vector<std::string>{"scale", "bias", "diffuse"}, std::vector<std::string>{"albedo"}}) {
    const Table t = known_table(5, 4, channels);
    for (const std::string ext : {".exr", ".png", ".hdr", ".ktx2", ".csv", ".h"})
      for (PixelType px : {PixelType::F16, PixelType::F32}) {
        if (px == PixelType::F32 && ext != ".ktx2" && ext != ".h") continue;
        const std::string path = (dir / ("t" + std::to_string(channels.size()) + ext)).string();
        TableWriteOptions o;
        o.pixel = px;
        write_table(t, path, table_format_from_path(path), o);
        const Table r = io::read_table(path);
        SCOPED_TRACE(path);
        ASSERT_EQ(r.width, t.width);
        ASSERT_EQ(r.height, t.height);
        EXPECT_EQ(r.channels, t.channels);
        EXPECT_EQ(r.meta("kind"), "test");
        EXPECT_EQ(r.x_name, "n_dot_v");
        EXPECT_EQ(r.y_name, "roughness");
        ASSERT_EQ(r.x.size(), t.x.size());
        for (size_t k = 0; k < t.x.size(); ++k) EXPECT_NEAR(r.x[k], t.x[k], test::kTextNineDigitsBelowOne);
        for (size_t k = 0; k < t.y.size(); ++k) EXPECT_NEAR(r.y[k], t.y[k], test::kTextNineDigitsBelowOne);
        ASSERT_EQ(r.data.size(), t.data.size());
        const double tol = format_tolerance(ext);
        for (size_t k = 0; k < t.data.size(); ++k)
          EXPECT_NEAR(r.data[k], t.data[k], tol + test::kTextNineDigitsBelowOne) << "value " << k;
      }
  }
}

TEST(ViewIo, CsvWithoutMetadataIsEvalOutput) {
  const fs::path p = temp_dir("eval") / "f.csv";
  io::write_file_atomically(p.string(), "r,g,b\n0.5,0.25,0.125\n1,2,3\n");
  const Table t = io::read_table(p.string());
  EXPECT_EQ(t.channels, (std::vector<std::string>{"r", "g", "b"}));
  EXPECT_EQ(t.width, 2);
  EXPECT_EQ(t.height, 1);
  EXPECT_EQ(t.x_name, "pair");
  EXPECT_EQ(t.data, (std::vector<float>{0.5f, 0.25f, 0.125f, 1, 2, 3}));
  io::write_file_atomically(p.string(), "r,g,b\n0.5,zero,1\n");
  EXPECT_NE(error_of([&] { io::read_table(p.string()); }).find("'zero' is not a number"), std::string::npos);
}

TEST(ViewIo, AxisRulesOfTheMetadata) {
  std::string name;
  std::vector<double> v;
  ASSERT_TRUE(io::axis_from_rule("n_dot_v = (i + 0.5) / width, the cell centre of column i", 4, &name, &v));
  EXPECT_EQ(name, "n_dot_v");
  EXPECT_EQ(v, (std::vector<double>{0.125, 0.375, 0.625, 0.875}));
  ASSERT_TRUE(io::axis_from_rule("cos_theta = i / (width - 1): 0 and 1 are cells", 3, &name, &v));
  EXPECT_EQ(v, (std::vector<double>{0.0, 0.5, 1.0}));
  ASSERT_TRUE(io::axis_from_rule("ior = lo + (hi - lo) (j + 0.5) / height, [lo, hi] = [1, 3], linear in the index", 2,
                                 &name, &v));
  EXPECT_EQ(name, "ior");
  EXPECT_EQ(v, (std::vector<double>{1.5, 2.5}));
  ASSERT_TRUE(
      io::axis_from_rule("thickness_nm = min + (max - min) (j + 0.5) / height, min 100, max 500", 2, &name, &v));
  EXPECT_EQ(v, (std::vector<double>{200.0, 400.0}));
  ASSERT_TRUE(io::axis_from_rule("column j: theta_o = (j + 0.5) / 2 pi/2", 2, &name, &v));
  EXPECT_EQ(name, "theta_o");
  EXPECT_NEAR(v[1], 0.75 * 1.5707963267948966, test::kUlpsOfOne);
  EXPECT_FALSE(io::axis_from_rule("cos_theta at explicit points (the x column)", 2, &name, &v));
  EXPECT_FALSE(io::axis_from_rule("row k * 16 + i: theta_i = (i + 0.5) / 16 pi/2, phi_d = ...", 2, &name, &v) &&
               name != "theta_i");
}

TEST(ViewIo, PngRgb8RoundTripWithText) {
  const fs::path p = temp_dir("png") / "s.png";
  std::vector<uint8_t> rgb(3 * 7 * 5);
  for (size_t k = 0; k < rgb.size(); ++k) rgb[k] = static_cast<uint8_t>(k * 7);
  io::write_png_rgb8(p.string(), 7, 5, rgb, {{"Description", "a test"}, {"brdfbake:files", "a\nb"}});
  const io::PngImage im = io::read_png(p.string());
  EXPECT_EQ(im.width, 7);
  EXPECT_EQ(im.height, 5);
  EXPECT_EQ(im.channels, 3);
  EXPECT_EQ(im.bit_depth, 8);
  for (size_t k = 0; k < rgb.size(); ++k) EXPECT_EQ(im.samples[k], rgb[k]);
  ASSERT_EQ(im.text.size(), 2u);
  EXPECT_EQ(im.text[1].second, "a\nb");
  EXPECT_NE(error_of([&] { io::write_png_rgb8(p.string(), 7, 4, rgb, {}); }).find("bytes for a 7x4"),
            std::string::npos);
  io::write_file_atomically(p.string(), "\x89PNG\r\n\x1a\n" + std::string("broken"));
  EXPECT_NE(error_of([&] { io::read_png(p.string()); }).find("cannot read"), std::string::npos);
}

}  // namespace
}  // namespace brdfbake
