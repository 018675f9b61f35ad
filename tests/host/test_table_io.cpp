// Table output: the format lookup, what each writer puts in its file (read back through
// OpenImageIO, the KTX2 reader, nlohmann_json, the raw bytes or the text), the orientation
// convention (texel (i, j) = pixel x = i, y = j, row 0 first), and failures that leave no file.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "brdfbake/error.hpp"
#include "brdfbake/io.hpp"
#include "brdfbake/table.hpp"
#include "io/atomic_file.hpp"
#include "io/half.hpp"
#include "io/ktx2.hpp"
#include "support/temp_dir.hpp"
#include "support/tolerances.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;

using test::kRgbeStepOfLargest;

// Values exact in binary16 (multiples of 1/256 below 8): channel c of texel (i, j) is
// (i + width * j + 1 + c / 4) / 64, distinct for every texel and channel, all in (0, 1).
Table make_table(int width, int height, std::vector<std::string> channels) {
  Table table;
  table.width = width;
  table.height = height;
  table.channels = std::move(channels);
  table.x_name = "n_dot_v";
  for (int i = 0; i < width; ++i) table.x.push_back((i + 0.5) / width);
  if (height > 1) {
    table.y_name = "roughness";
    for (int j = 0; j < height; ++j) table.y.push_back((j + 0.5) / height);
  }
  for (int j = 0; j < height; ++j) {
    for (int i = 0; i < width; ++i) {
      for (int c = 0; c < table.channel_count(); ++c) {
        table.data.push_back(static_cast<float>(i + width * j + 1) / 64.0f + static_cast<float>(c) / 256.0f);
      }
    }
  }
  table.set_meta("kind", "dfg");
  table.set_meta("texel_centres", "x = (i + 0.5) / width");
  return table;
}

std::vector<std::string> channel_names(int count) {
  const std::vector<std::string> all = {"scale", "bias", "diffuse", "sheen"};
  return std::vector<std::string>(all.begin(), all.begin() + count);
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Opens an image as stored: without this, OpenImageIO premultiplies PNG colour by alpha on read.
std::unique_ptr<OIIO::ImageInput> open_image(const std::string& path) {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  return OIIO::ImageInput::open(path, &config);
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::string error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

class TableIo : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = brdfbake::test::test_temp_dir("table_io"); }  // removed when the test ends

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // The names in the test folder, sorted: shows leftovers such as temporaries.
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir_)) {
      names.push_back(entry.path().filename().string());
    }
    std::sort(names.begin(), names.end());
    return names;
  }

  fs::path dir_;
};

const std::pair<TableFormat, const char*> kAllFormats[] = {{TableFormat::Exr, "exr"}, {TableFormat::Png, "png"},
                                                           {TableFormat::Hdr, "hdr"}, {TableFormat::Ktx2, "ktx2"},
                                                           {TableFormat::Csv, "csv"}, {TableFormat::CHeader, "h"}};

// ---- Table metadata and format lookup ----------------------------------------------------------

TEST(TableMetadata, SetReplacesAndMetaReadsBack) {
  Table table;
  table.set_meta("a", "1");
  table.set_meta("b", "2");
  table.set_meta("a", "3");
  EXPECT_EQ(table.metadata, (Metadata{{"a", "3"}, {"b", "2"}}));
  EXPECT_EQ(table.meta("a"), "3");
  EXPECT_EQ(table.meta("missing"), "");
}

TEST(TableFormatLookup, ByExtensionCaseInsensitive) {
  for (const auto& [format, name] : kAllFormats) {
    EXPECT_EQ(table_format_from_path(std::string("out/lut.") + name), format) << name;
    std::string upper = name;
    std::transform(upper.begin(), upper.end(), upper.begin(), ::toupper);
    EXPECT_EQ(table_format_from_path("LUT." + upper), format) << upper;
  }
}

TEST(TableFormatLookup, ByName) {
  for (const auto& [format, name] : kAllFormats) EXPECT_EQ(table_format_from_name(name), format);
  EXPECT_EQ(table_format_from_name("KTX2"), TableFormat::Ktx2);
  EXPECT_EQ(table_format_from_name(".exr"), TableFormat::Exr);
}

TEST(TableFormatLookup, UnknownFormatsAreErrors) {
  EXPECT_EQ(error_of([] { table_format_from_path("lut.xyz"); }),
            "unknown output format '.xyz' (expected .exr, .png, .hdr, .ktx2, .csv or .h)");
  EXPECT_EQ(error_of([] { table_format_from_path("lut"); }),
            "output file 'lut' has no extension (expected .exr, .png, .hdr, .ktx2, .csv or .h)");
  EXPECT_EQ(error_of([] { table_format_from_name("tiff"); }),
            "unknown output format 'tiff' (expected exr, png, hdr, ktx2, csv or h)");
}

// ---- Half floats -------------------------------------------------------------------------------

TEST(HalfFloat, KnownValuesAndEveryValueRoundTrips) {
  EXPECT_EQ(io::float_to_half_bits(1.0f), 0x3C00);
  EXPECT_EQ(io::float_to_half_bits(-2.0f), 0xC000);
  EXPECT_EQ(io::float_to_half_bits(65504.0f), 0x7BFF);     // largest finite half
  EXPECT_EQ(io::float_to_half_bits(65520.0f), 0x7C00);     // rounds up to infinity
  EXPECT_EQ(io::float_to_half_bits(1.0f / 3.0f), 0x3555);  // round to nearest
  for (uint32_t bits = 0; bits <= 0xFFFF; ++bits) {
    const float value = io::half_bits_to_float(static_cast<uint16_t>(bits));
    if (std::isnan(value)) continue;
    ASSERT_EQ(io::float_to_half_bits(value), bits) << std::hex << bits;
  }
}

// The array conversions (F16C where the CPU has it) give the scalar conversion's bits: every 97th
// float bit pattern (44 million values: both signs, subnormals, the rounding boundaries around every
// half, overflow to infinity), and every half back to the same float.
TEST(HalfFloat, ArrayConversionsMatchTheScalarOnes) {
  constexpr uint64_t kStride = 97;
  std::vector<float> in;
  in.reserve((uint64_t(1) << 32) / kStride + 1);
  for (uint64_t b = 0; b <= 0xFFFFFFFFull; b += kStride) {
    float v;
    const uint32_t u = static_cast<uint32_t>(b);
    std::memcpy(&v, &u, 4);
    if (!std::isnan(v)) in.push_back(v);  // NaN payloads may differ; no NaN is ever written
  }
  for (float v : {65504.0f, 65519.99f, 65520.0f, 5.96e-8f, 2.98e-8f, 2.99e-8f, -0.0f}) in.push_back(v);
  std::vector<uint16_t> bits(in.size());
  io::floats_to_half_bits(in.data(), in.size(), bits.data());
  size_t mismatches = 0;
  for (size_t k = 0; k < in.size(); ++k) mismatches += bits[k] != io::float_to_half_bits(in[k]);
  EXPECT_EQ(mismatches, 0u);
  std::vector<uint16_t> every(0x10000);
  for (uint32_t h = 0; h <= 0xFFFF; ++h) every[h] = static_cast<uint16_t>(h);
  std::vector<float> back(every.size());
  io::half_bits_to_floats(every.data(), every.size(), back.data());
  for (uint32_t h = 0; h <= 0xFFFF; ++h) {
    const float want = io::half_bits_to_float(static_cast<uint16_t>(h));
    if (std::isnan(want))
      EXPECT_TRUE(std::isnan(back[h])) << std::hex << h;
    else
      ASSERT_EQ(std::memcmp(&back[h], &want, 4), 0) << std::hex << h;
  }
}

// ---- .exr --------------------------------------------------------------------------------------

TEST_F(TableIo, ExrHoldsFloat32ChannelsAndMetadata) {
  Table table = make_table(4, 3, channel_names(3));
  table.at(1, 0, 2) = 3.14159274f;  // any float survives, not only the convenient ones
  table.at(2, 1, 0) = -1e-7f;
  write_table(table, path("lut.exr"), TableFormat::Exr);
  EXPECT_EQ(entries(), std::vector<std::string>{"lut.exr"});

  auto in = open_image(path("lut.exr"));
  ASSERT_TRUE(in) << OIIO::geterror();
  const OIIO::ImageSpec spec = in->spec();
  EXPECT_EQ(spec.width, 4);
  EXPECT_EQ(spec.height, 3);
  EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
  EXPECT_EQ(spec.channelnames, (std::vector<std::string>{"R", "G", "B"}));
  EXPECT_EQ(spec.get_string_attribute("brdfbake:kind"), "dfg");
  EXPECT_EQ(spec.get_string_attribute("brdfbake:texel_centres"), "x = (i + 0.5) / width");
  EXPECT_EQ(spec.get_string_attribute("brdfbake:channels"), "scale,bias,diffuse");
  std::vector<float> pixels(4 * 3 * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, pixels.data())) << in->geterror();
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 4; ++i) {
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(pixels[static_cast<size_t>((j * 4 + i) * 3 + c)], table.at(i, j, c))
            << "pixel (" << i << ", " << j << ") channel " << c;
      }
    }
  }
}

TEST_F(TableIo, ExrChannelNamesFollowTheChannelCount) {
  const std::vector<std::vector<std::string>> expected = {{"R"}, {"R", "G"}, {"R", "G", "B"}, {"R", "G", "B", "A"}};
  for (int channels = 1; channels <= 4; ++channels) {
    const Table table = make_table(2, 2, channel_names(channels));
    write_table(table, path("lut.exr"), TableFormat::Exr);
    auto in = open_image(path("lut.exr"));
    ASSERT_TRUE(in) << OIIO::geterror();
    EXPECT_EQ(in->spec().channelnames, expected[static_cast<size_t>(channels - 1)]);
    std::vector<float> pixels(table.data.size());
    ASSERT_TRUE(in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, pixels.data()));
    EXPECT_EQ(pixels, table.data) << "no alpha (un)premultiplication";
  }
}

// ---- .png --------------------------------------------------------------------------------------

TEST_F(TableIo, PngQuantisesClampsAndPadsTwoChannelsToRgb) {
  Table table = make_table(4, 2, channel_names(2));
  table.at(0, 0, 0) = -0.5f;
  table.at(1, 0, 1) = 1.5f;
  table.at(2, 1, 0) = std::numeric_limits<float>::quiet_NaN();
  table.at(3, 1, 1) = 0.5f;  // round(32767.5) = 32768
  write_table(table, path("lut.png"), TableFormat::Png);

  auto in = open_image(path("lut.png"));
  ASSERT_TRUE(in) << OIIO::geterror();
  const OIIO::ImageSpec spec = in->spec();
  EXPECT_EQ(spec.nchannels, 3);
  EXPECT_EQ(spec.format, OIIO::TypeDesc::UINT16);
  EXPECT_EQ(spec.get_string_attribute("brdfbake:kind"), "dfg");
  EXPECT_EQ(spec.get_string_attribute("brdfbake:channels"), "scale,bias");
  EXPECT_EQ(spec.get_string_attribute("brdfbake:clamped_values"), "3");
  std::vector<uint16_t> pixels(4 * 2 * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT16, pixels.data()));
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 4; ++i) {
      for (int c = 0; c < 3; ++c) {
        const float value = c < 2 ? table.at(i, j, c) : 0.0f;
        const float unit = std::isnan(value) ? 0.0f : std::clamp(value, 0.0f, 1.0f);
        EXPECT_EQ(pixels[static_cast<size_t>((j * 4 + i) * 3 + c)], static_cast<uint16_t>(std::lround(unit * 65535.0f)))
            << "pixel (" << i << ", " << j << ") channel " << c;
      }
    }
  }
  EXPECT_EQ(pixels[(1 * 4 + 3) * 3 + 1], 32768);

  // The metadata is in tEXt chunks: length, "tEXt", keyword, NUL, text, CRC (PNG specification,
  // "tEXt").
  const std::string bytes = read_text(path("lut.png"));
  EXPECT_TRUE(contains(bytes, std::string("tEXtbrdfbake:kind\0dfg", 21)));
  EXPECT_TRUE(contains(bytes, std::string("tEXtbrdfbake:clamped_values\0"
                                          "3",
                                          29)));
}

TEST_F(TableIo, PngGreyAndRgbaWithoutClamping) {
  for (int channels : {1, 3, 4}) {
    const Table table = make_table(3, 2, channel_names(channels));
    write_table(table, path("lut.png"), TableFormat::Png);
    auto in = open_image(path("lut.png"));
    ASSERT_TRUE(in) << OIIO::geterror();
    EXPECT_EQ(in->spec().nchannels, channels);
    EXPECT_EQ(in->spec().find_attribute("brdfbake:clamped_values"), nullptr);
    std::vector<uint16_t> pixels(static_cast<size_t>(3 * 2 * channels));
    ASSERT_TRUE(in->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT16, pixels.data()));
    for (size_t k = 0; k < pixels.size(); ++k) {
      EXPECT_EQ(pixels[k], static_cast<uint16_t>(std::lround(table.data[k] * 65535.0f)));
    }
  }
}

// ---- .hdr --------------------------------------------------------------------------------------

TEST_F(TableIo, HdrWritesRgbeAndAJsonSidecar) {
  Table table = make_table(4, 2, channel_names(2));
  table.at(3, 1, 0) = -0.25f;                                  // RGBE has no sign: written as 0 and counted
  table.at(0, 1, 1) = std::numeric_limits<float>::infinity();  // no infinity: the largest value
  const float rgbe_max = std::ldexp(255.0f / 256.0f, 127);
  write_table(table, path("lut.hdr"), TableFormat::Hdr);
  EXPECT_EQ(entries(), (std::vector<std::string>{"lut.hdr", "lut.hdr.json"}));

  auto in = open_image(path("lut.hdr"));
  ASSERT_TRUE(in) << OIIO::geterror();
  ASSERT_EQ(in->spec().nchannels, 3);
  std::vector<float> pixels(4 * 2 * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, pixels.data()));
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 4; ++i) {
      const float* rgb = &pixels[static_cast<size_t>((j * 4 + i) * 3)];
      const double largest = static_cast<double>(std::min(std::max(table.at(i, j, 0), table.at(i, j, 1)), rgbe_max));
      for (int c = 0; c < 2; ++c) {
        const double expected = static_cast<double>(std::clamp(table.at(i, j, c), 0.0f, rgbe_max));
        EXPECT_NEAR(rgb[c], expected, largest * kRgbeStepOfLargest) << "pixel (" << i << ", " << j << ") channel " << c;
      }
      EXPECT_EQ(rgb[2], 0.0f) << "padding";
    }
  }

  const nlohmann::json sidecar = nlohmann::json::parse(read_text(path("lut.hdr.json")));
  EXPECT_EQ(sidecar.at("generator").get<std::string>().rfind("brdfbake ", 0), 0u);
  EXPECT_EQ(sidecar.at("image"), "lut.hdr");
  EXPECT_EQ(sidecar.at("width"), 4);
  EXPECT_EQ(sidecar.at("height"), 2);
  EXPECT_EQ(sidecar.at("channels"), nlohmann::json({"scale", "bias"}));
  EXPECT_EQ(sidecar.at("layout").at("rgb"), nlohmann::json({"scale", "bias", nullptr}));
  EXPECT_TRUE(contains(sidecar.at("layout").at("orientation"), "row j = 0"));
  EXPECT_EQ(sidecar.at("x").at("name"), "n_dot_v");
  EXPECT_EQ(sidecar.at("x").at("values").get<std::vector<double>>(), table.x);
  EXPECT_EQ(sidecar.at("y").at("name"), "roughness");
  EXPECT_EQ(sidecar.at("y").at("values").get<std::vector<double>>(), table.y);
  EXPECT_EQ(sidecar.at("metadata").at("kind"), "dfg");
  EXPECT_EQ(sidecar.at("metadata").at("clamped_values"), "2");
}

// ---- .ktx2 -------------------------------------------------------------------------------------

float texel_component(const io::Ktx2Image& image, size_t texel, size_t c) {
  const std::vector<uint8_t>& data = image.level_data.at(0);
  if (image.vk_format == io::kVkFormatR16G16B16A16Sfloat) {
    const size_t at = (texel * 4 + c) * 2;
    return io::half_bits_to_float(static_cast<uint16_t>(data.at(at) | data.at(at + 1) << 8));
  }
  const size_t at = (texel * 4 + c) * 4;
  const uint32_t bits = static_cast<uint32_t>(data.at(at)) | static_cast<uint32_t>(data.at(at + 1)) << 8 |
                        static_cast<uint32_t>(data.at(at + 2)) << 16 | static_cast<uint32_t>(data.at(at + 3)) << 24;
  float value = 0;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

std::string key_value(const io::Ktx2Image& image, const std::string& key) {
  for (const auto& [k, v] : image.key_values) {
    if (k == key) return v;
  }
  return "(absent)";
}

TEST_F(TableIo, Ktx2HalfFloatRgbaWithPaddedChannels) {
  for (int channels = 1; channels <= 4; ++channels) {
    SCOPED_TRACE(std::to_string(channels) + " channel(s)");
    const Table table = make_table(3, 2, channel_names(channels));
    write_table(table, path("lut.ktx2"), TableFormat::Ktx2, {PixelType::F16, ""});
    const io::Ktx2Image image = io::read_ktx2(path("lut.ktx2"));
    EXPECT_EQ(image.vk_format, io::kVkFormatR16G16B16A16Sfloat);
    EXPECT_EQ(image.width, 3u);
    EXPECT_EQ(image.height, 2u);
    EXPECT_EQ(image.faces, 1u);
    EXPECT_EQ(image.levels, 1u);
    for (int j = 0; j < 2; ++j) {
      for (int i = 0; i < 3; ++i) {
        for (int c = 0; c < 4; ++c) {
          const float expected = c < channels ? table.at(i, j, c) : (c == 3 ? 1.0f : 0.0f);
          EXPECT_EQ(texel_component(image, static_cast<size_t>(j * 3 + i), static_cast<size_t>(c)), expected)
              << "texel (" << i << ", " << j << ") channel " << c;
        }
      }
    }
    EXPECT_EQ(key_value(image, "KTXorientation"), "rd");
    EXPECT_EQ(key_value(image, "KTXwriter").rfind("brdfbake ", 0), 0u);
    EXPECT_EQ(key_value(image, "brdfbake:kind"), "dfg");
    EXPECT_EQ(key_value(image, "brdfbake:texel_centres"), "x = (i + 0.5) / width");
    std::string names;
    for (const std::string& name : channel_names(channels)) names += (names.empty() ? "" : ",") + name;
    EXPECT_EQ(key_value(image, "brdfbake:channels"), names);
  }
}

TEST_F(TableIo, Ktx2Float32IsExact) {
  Table table = make_table(3, 2, channel_names(3));
  table.at(2, 1, 1) = 3.14159274f;
  write_table(table, path("lut.ktx2"), TableFormat::Ktx2, {PixelType::F32, ""});
  const io::Ktx2Image image = io::read_ktx2(path("lut.ktx2"));
  EXPECT_EQ(image.vk_format, io::kVkFormatR32G32B32A32Sfloat);
  for (size_t texel = 0; texel < 6; ++texel) {
    for (size_t c = 0; c < 3; ++c) EXPECT_EQ(texel_component(image, texel, c), table.data[texel * 3 + c]);
    EXPECT_EQ(texel_component(image, texel, 3), 1.0f);
  }
}

// ---- .csv --------------------------------------------------------------------------------------

TEST_F(TableIo, CsvTextIsExact) {
  Table table;
  table.width = 2;
  table.height = 2;
  table.channels = {"scale", "bias"};
  table.x_name = "n_dot_v";
  table.y_name = "roughness";
  table.x = {0.25, 0.75};
  table.y = {0.1, 0.9};
  table.data = {0.5f, 1.0f / 3.0f, 0.1f, 2.0f, -0.25f, 1e-10f, 100.0f, 0.0f};
  table.set_meta("kind", "dfg");
  table.set_meta("note", "two\nlines");
  const std::string expected =
      "# kind: dfg\n"
      "# note: two lines\n"
      "n_dot_v,roughness,scale,bias\n"
      "0.25,0.1,0.5,0.333333343\n"
      "0.75,0.1,0.100000001,2\n"
      "0.25,0.9,-0.25,1.00000001e-10\n"
      "0.75,0.9,100,0\n";
  write_table(table, path("lut.csv"), TableFormat::Csv);
  EXPECT_EQ(read_text(path("lut.csv")), expected);
  std::ostringstream stream;
  write_table_csv(table, stream);
  EXPECT_EQ(stream.str(), expected);
}

TEST_F(TableIo, CsvOneDimensionalRoundTripsEveryFloat) {
  Table table;
  table.width = 1000;
  table.height = 1;
  table.channels = {"fresnel"};
  table.x_name = "cos_theta";
  uint32_t state = 12345;  // a fixed LCG: arbitrary bit patterns across many exponents
  for (int i = 0; i < table.width; ++i) {
    table.x.push_back(i / 999.0);
    state = state * 1664525u + 1013904223u;
    const float value = std::ldexp(static_cast<float>(state >> 8) / 16777216.0f, i % 40 - 20);
    table.data.push_back(i % 2 == 0 ? value : -value);
  }
  std::ostringstream stream;
  write_table_csv(table, stream);
  std::istringstream lines(stream.str());
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "cos_theta,fresnel");  // no y column
  for (int i = 0; i < table.width; ++i) {
    ASSERT_TRUE(std::getline(lines, line));
    const size_t comma = line.find(',');
    ASSERT_NE(comma, std::string::npos);
    const float value = std::strtof(line.c_str() + comma + 1, nullptr);
    EXPECT_EQ(value, table.data[static_cast<size_t>(i)]) << line;
  }
  EXPECT_FALSE(std::getline(lines, line));
}

TEST_F(TableIo, CsvQuotesNamesThatNeedIt) {
  Table table = make_table(1, 1, {"a,b", "say \"hi\""});
  std::ostringstream stream;
  write_table_csv(table, stream);
  EXPECT_TRUE(contains(stream.str(), "\nn_dot_v,\"a,b\",\"say \"\"hi\"\"\"\n")) << stream.str();
}

TEST_F(TableIo, CsvNeedsCoordinates) {
  Table table = make_table(3, 2, channel_names(1));
  table.x.pop_back();
  EXPECT_TRUE(contains(error_of([&] { write_table(table, path("lut.csv"), TableFormat::Csv); }),
                       "2 x coordinates for width 3"));
  EXPECT_TRUE(entries().empty());
}

// ---- .h ----------------------------------------------------------------------------------------

// The values between "= {" and "};", checking 8 per line (the last line may have fewer).
std::vector<std::string> header_values(const std::string& text) {
  const size_t begin = text.find("= {\n");
  const size_t end = text.find("};\n");
  EXPECT_NE(begin, std::string::npos);
  EXPECT_NE(end, std::string::npos);
  std::istringstream lines(text.substr(begin + 4, end - begin - 4));
  std::vector<std::string> values;
  std::string line;
  std::vector<size_t> counts;
  while (std::getline(lines, line)) {
    std::istringstream tokens(line);
    std::string token;
    size_t count = 0;
    while (tokens >> token) {
      if (token.back() == ',') token.pop_back();
      values.push_back(token);
      ++count;
    }
    counts.push_back(count);
  }
  for (size_t k = 0; k + 1 < counts.size(); ++k) EXPECT_EQ(counts[k], 8u) << "line " << k;
  EXPECT_GE(counts.back(), 1u);
  EXPECT_LE(counts.back(), 8u);
  return values;
}

TEST_F(TableIo, CHeaderFloat32) {
  Table table = make_table(3, 3, channel_names(2));  // 18 values: lines of 8, 8, 2
  table.at(0, 0, 0) = 1.0f;                          // needs ".0f" to be a float literal
  table.at(1, 0, 0) = 1e-5f;
  write_table(table, path("dfg_lut.h"), TableFormat::CHeader, {PixelType::F32, ""});
  const std::string text = read_text(path("dfg_lut.h"));
  EXPECT_LT(text.find("//   kind: dfg\n"), text.find("#pragma once\n"));
  EXPECT_TRUE(contains(text, "//   texel_centres: x = (i + 0.5) / width\n"));
  EXPECT_TRUE(contains(text, "#include <stdint.h>\n"));
  EXPECT_TRUE(contains(text, "#define DFG_LUT_WIDTH 3\n"));
  EXPECT_TRUE(contains(text, "#define DFG_LUT_HEIGHT 3\n"));
  EXPECT_TRUE(contains(text, "#define DFG_LUT_CHANNELS 2\n"));
  EXPECT_TRUE(contains(text, "static const float dfg_lut[DFG_LUT_WIDTH * DFG_LUT_HEIGHT * DFG_LUT_CHANNELS] = {\n"));
  EXPECT_TRUE(contains(text, " 1.0f, 0.01953125f, 9.99999975e-06f,"));
  const std::vector<std::string> values = header_values(text);
  ASSERT_EQ(values.size(), table.data.size());
  for (size_t k = 0; k < values.size(); ++k) {
    EXPECT_EQ(values[k].back(), 'f') << values[k];
    EXPECT_EQ(std::strtof(values[k].c_str(), nullptr), table.data[k]) << values[k];
  }
}

TEST_F(TableIo, CHeaderHalfBits) {
  const Table table = make_table(4, 3, channel_names(3));
  write_table(table, path("dfg_lut.h"), TableFormat::CHeader, {PixelType::F16, ""});
  const std::string text = read_text(path("dfg_lut.h"));
  EXPECT_TRUE(contains(text, "static const uint16_t dfg_lut[DFG_LUT_WIDTH * DFG_LUT_HEIGHT * DFG_LUT_CHANNELS] = {\n"));
  const std::vector<std::string> values = header_values(text);
  ASSERT_EQ(values.size(), table.data.size());
  for (size_t k = 0; k < values.size(); ++k) {
    EXPECT_EQ(std::strtoul(values[k].c_str(), nullptr, 16), io::float_to_half_bits(table.data[k])) << values[k];
  }
}

TEST_F(TableIo, CHeaderSymbols) {
  const Table table = make_table(2, 2, channel_names(1));
  write_table(table, path("2x-lut.v1.h"), TableFormat::CHeader);
  EXPECT_TRUE(contains(read_text(path("2x-lut.v1.h")), " lut_2x_lut_v1[LUT_2X_LUT_V1_WIDTH *"));
  write_table(table, path("float.h"), TableFormat::CHeader);
  EXPECT_TRUE(contains(read_text(path("float.h")), " float_[FLOAT__WIDTH *"));
  write_table(table, path("any.h"), TableFormat::CHeader, {PixelType::F16, "brdf_dfg"});
  EXPECT_TRUE(contains(read_text(path("any.h")), " brdf_dfg[BRDF_DFG_WIDTH *"));
  EXPECT_EQ(error_of([&] {
              write_table(table, path("bad.h"), TableFormat::CHeader, {PixelType::F16, "9lives"});
            }),
            "cannot write '" + path("bad.h") + "': symbol '9lives' is not a C identifier");
}

// The generated headers compile as C99 and C++17, warnings as errors, where a compiler is on PATH.
TEST_F(TableIo, CHeaderCompiles) {
  if (std::system("command -v cc > /dev/null 2>&1 && command -v c++ > /dev/null 2>&1") != 0) {
    GTEST_SKIP() << "no cc/c++ on PATH";
  }
  const Table table = make_table(5, 3, channel_names(3));
  write_table(table, path("lut32.h"), TableFormat::CHeader, {PixelType::F32, ""});
  write_table(table, path("lut16.h"), TableFormat::CHeader, {PixelType::F16, ""});
  {
    std::ofstream source(path("use.c"));
    source << "#include \"lut32.h\"\n#include \"lut16.h\"\n"
              "int main(void) { return (int)(lut32[LUT32_WIDTH - 1] + (float)lut16[0]); }\n";
  }
  const std::string flags = " -Wall -Wextra -Werror -fsyntax-only " + path("use.c") + " 2>&1";
  EXPECT_EQ(std::system(("cc -std=c99 -pedantic" + flags).c_str()), 0);
  EXPECT_EQ(std::system(("c++ -x c++ -std=c++17 -pedantic" + flags).c_str()), 0);
}

TEST_F(TableIo, CHeaderRejectsNonFiniteFloat32) {
  write_table(make_table(2, 1, channel_names(1)), path("lut.h"), TableFormat::CHeader);
  const std::string before = read_text(path("lut.h"));
  Table table = make_table(2, 1, channel_names(1));
  table.data[1] = std::numeric_limits<float>::infinity();
  EXPECT_TRUE(contains(error_of([&] {
                         write_table(table, path("lut.h"), TableFormat::CHeader, {PixelType::F32, ""});
                       }),
                       "value inf at index 1 has no C float literal"));
  EXPECT_EQ(read_text(path("lut.h")), before) << "the previous file is kept";
  EXPECT_EQ(entries(), std::vector<std::string>{"lut.h"});
}

// ---- Errors and atomicity ----------------------------------------------------------------------

TEST_F(TableIo, MissingFolderNamesPathAndReason) {
  const Table table = make_table(2, 2, channel_names(2));
  for (const auto& entry : kAllFormats) {
    const std::string target = path(std::string("missing/lut.") + entry.second);
    EXPECT_EQ(error_of([&] { write_table(table, target, entry.first); }),
              "cannot write '" + target + "': No such file or directory");
  }
  EXPECT_TRUE(entries().empty());
}

// A path through a regular file fails for root too (unlike a read-only folder).
TEST_F(TableIo, PathThroughARegularFileNamesPathAndReason) {
  { std::ofstream(path("somefile")) << "x"; }
  const Table table = make_table(2, 2, channel_names(2));
  for (const auto& entry : kAllFormats) {
    const std::string target = path(std::string("somefile/lut.") + entry.second);
    EXPECT_EQ(error_of([&] { write_table(table, target, entry.first); }),
              "cannot write '" + target + "': Not a directory");
  }
  EXPECT_EQ(entries(), std::vector<std::string>{"somefile"});
}

TEST_F(TableIo, TemporaryIsRemovedUnlessCommitted) {
  std::string temporary;
  try {
    io::TempFile temp(path("lut.exr"));
    temporary = temp.path();
    EXPECT_TRUE(fs::exists(temporary));
    const std::string prefix = ".lut.exr.tmp-" + std::to_string(::getpid()) + "-";
    EXPECT_EQ(fs::path(temporary).filename().string().rfind(prefix, 0), 0u) << temporary;
    EXPECT_EQ(fs::path(temporary).parent_path(), dir_);
    throw std::runtime_error("writer failed");
  } catch (const std::runtime_error&) {
  }
  EXPECT_FALSE(fs::exists(temporary));
  EXPECT_TRUE(entries().empty());
}

TEST_F(TableIo, ReplacesAnExistingFile) {
  write_table(make_table(2, 1, channel_names(1)), path("lut.csv"), TableFormat::Csv);
  const Table second = make_table(3, 1, channel_names(2));
  write_table(second, path("lut.csv"), TableFormat::Csv);
  std::ostringstream expected;
  write_table_csv(second, expected);
  EXPECT_EQ(read_text(path("lut.csv")), expected.str());
  EXPECT_EQ(entries(), std::vector<std::string>{"lut.csv"});
}

TEST_F(TableIo, FailedSidecarLeavesNoTemporaries) {
  fs::create_directory(path("lut.hdr.json"));  // renaming the sidecar onto a folder fails
  EXPECT_TRUE(
      contains(error_of([&] { write_table(make_table(2, 2, channel_names(3)), path("lut.hdr"), TableFormat::Hdr); }),
               "cannot write '" + path("lut.hdr.json") + "'"));
  for (const std::string& name : entries()) EXPECT_FALSE(contains(name, ".tmp-")) << name;
}

TEST_F(TableIo, InvalidTablesAreErrors) {
  Table table = make_table(4, 3, channel_names(3));
  table.data.pop_back();
  EXPECT_EQ(error_of([&] { write_table(table, path("a.exr"), TableFormat::Exr); }),
            "cannot write '" + path("a.exr") + "': the table holds 35 values, expected 4 x 3 x 3");
  table = make_table(2, 2, {"a", "b", "c", "d", "e"});
  EXPECT_EQ(error_of([&] { write_table(table, path("a.png"), TableFormat::Png); }),
            "cannot write '" + path("a.png") + "': the .png format holds at most 4 channels; the table has 5");
  table = make_table(2, 2, channel_names(4));
  EXPECT_TRUE(contains(error_of([&] { write_table(table, path("a.hdr"), TableFormat::Hdr); }),
                       "the .hdr format holds at most 3 channels; the table has 4"));
  table = make_table(2, 2, channel_names(1));
  table.set_meta(std::string(80, 'k'), "v");
  EXPECT_TRUE(contains(error_of([&] { write_table(table, path("a.png"), TableFormat::Png); }),
                       "too long for a PNG text chunk"));
  table = Table{};
  EXPECT_TRUE(contains(error_of([&] { write_table(table, path("a.csv"), TableFormat::Csv); }), "the table is empty"));
  EXPECT_TRUE(entries().empty());
}

}  // namespace
}  // namespace brdfbake
