// Image files (host/src/io/image_file.hpp): the Radiance RGBE codec against the format's definition
// (hand-built byte sequences, every truncation, the eight scanline orders) and against OpenImageIO
// as an independent reader; the OpenEXR reader on files OpenImageIO writes (half, float, tiled,
// mip-mapped, offset data windows, extra channels); the OpenImageIO module for other formats.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "brdfbake/error.hpp"
#include "io/atomic_file.hpp"
#include "io/image_file.hpp"
#include "io/oiio_module.hpp"
#include "io/rgbe.hpp"
#include "support/temp_dir.hpp"
#include "support/tolerances.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;

using test::kRgbeStepOfLargest;
const io::ImageLimits kMaxPixels{uint64_t(1) << 28, 0};

// The test's temporary folder, removed when the test ends.
fs::path temp_root() { return brdfbake::test::test_temp_root(); }

fs::path temp_dir(const std::string& name) {
  const fs::path d = temp_root() / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string bytes(std::initializer_list<int> values) {
  std::string s;
  for (int v : values) s.push_back(static_cast<char>(v));
  return s;
}

std::string error_of_decode(const std::string& data) {
  try {
    io::decode_rgbe(data);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

void write_file(const fs::path& p, const std::string& data) { std::ofstream(p, std::ios::binary) << data; }

// ---- RGBE pixels ---------------------------------------------------------------------------------

TEST(Rgbe, PixelsFollowTheDefinition) {
  struct Case {
    float rgb[3];
    uint8_t want[4];
  };
  // frexp(largest) = m 2^e with m in [0.5, 1): exponent byte e + 128, mantissas floor(c 2^(8 - e)).
  const Case cases[] = {
      {{1.0f, 1.0f, 1.0f}, {128, 128, 128, 129}}, {{1.0f, 0.25f, 0.0f}, {128, 32, 0, 129}},
      {{0.5f, 0.5f, 0.5f}, {128, 128, 128, 128}}, {{17.0f, 0.0f, 3.0f}, {136, 0, 24, 133}},
      {{0.0f, 0.0f, 0.0f}, {0, 0, 0, 0}},         {{io::kRgbeMax, 0.0f, 0.0f}, {255, 0, 0, 255}},
      {{0.999f, 0.0f, 0.0f}, {255, 0, 0, 128}},  // floor(0.999 * 256) = 255
  };
  for (const Case& c : cases) {
    uint8_t got[4];
    io::float_to_rgbe(c.rgb, got);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(got[k], c.want[k]) << c.rgb[0] << " byte " << k;
  }
  // (R, G, B, E) -> mantissa 2^(E - 136), and E = 0 is black whatever the mantissas.
  float out[3];
  io::rgbe_to_float(std::array<uint8_t, 4>{136, 0, 24, 133}.data(), out);
  EXPECT_EQ(out[0], 17.0f);
  EXPECT_EQ(out[1], 0.0f);
  EXPECT_EQ(out[2], 3.0f);
  io::rgbe_to_float(std::array<uint8_t, 4>{200, 7, 9, 0}.data(), out);
  EXPECT_EQ(out[0], 0.0f);
  io::rgbe_to_float(std::array<uint8_t, 4>{255, 0, 0, 255}.data(), out);
  EXPECT_EQ(out[0], io::kRgbeMax);
}

TEST(Rgbe, RoundTripTruncatesWithinOneStepOfTheLargest) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::uniform_int_distribution<int> exponent(-60, 60);
  for (int n = 0; n < 20000; ++n) {
    const float scale = std::ldexp(1.0f, exponent(rng));
    const float rgb[3] = {unit(rng) * scale, unit(rng) * scale, n % 7 == 0 ? 0.0f : unit(rng) * scale};
    uint8_t e[4];
    float back[3];
    io::float_to_rgbe(rgb, e);
    io::rgbe_to_float(e, back);
    const double largest = std::max({double(rgb[0]), double(rgb[1]), double(rgb[2])});
    for (int c = 0; c < 3; ++c) {
      ASSERT_LE(double(back[c]), double(rgb[c])) << "truncation never rounds up";
      ASSERT_LE(double(rgb[c]) - double(back[c]), largest * kRgbeStepOfLargest) << rgb[c];
    }
  }
}

// ---- RGBE files ----------------------------------------------------------------------------------

TEST(Rgbe, EncodesRunsAndDumpsByteForByte) {
  // 8 pixels wide (the shortest run-length encoded scanline), one row: R = G = B = 1 (bytes 128,
  // exponent 129) for all but the last pixel, which is 0.5 in red only (128, 0, 0, 128).
  std::vector<float> rgb(8 * 3, 1.0f);
  rgb[21] = 0.5f;
  rgb[22] = rgb[23] = 0.0f;
  const std::string file = io::encode_rgbe(8, 1, rgb.data());
  const std::string header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 8\n";
  ASSERT_EQ(file.substr(0, header.size()), header);
  const std::string want = bytes({2, 2, 0, 8, 128 + 8, 128,  // red: a run of 8
                                  128 + 7, 128, 1, 0,        // green: a run of 7, a dump of 1
                                  128 + 7, 128, 1, 0,        // blue
                                  128 + 7, 129, 1, 128});    // exponents
  EXPECT_EQ(file.substr(header.size()), want);
  const io::RgbeImage back = io::decode_rgbe(file);
  EXPECT_TRUE(back.run_length_encoded);
  EXPECT_EQ(back.rgb, rgb);
}

TEST(Rgbe, LongRunsAndDumpsSplitAtTheirLimits) {
  // 300 pixels: 200 equal (runs of at most 127) then 100 all different (dumps of at most 128).
  std::vector<float> rgb;
  for (int x = 0; x < 300; ++x) {
    const float v = x < 200 ? 2.0f : 1.0f + float(x - 199) / 128.0f;  // mantissas 129 .. 228
    rgb.insert(rgb.end(), {v, v, v});
  }
  const std::string file = io::encode_rgbe(300, 1, rgb.data());
  const io::RgbeImage back = io::decode_rgbe(file);
  ASSERT_EQ(back.width, 300);
  for (size_t k = 0; k < rgb.size(); ++k) EXPECT_EQ(back.rgb[k], rgb[k]) << k;  // all exact in RGBE
  // red: runs 127 + 73 (4 bytes), a dump of 100 (101 bytes); and the same for G, B; the exponent
  // is 130 for x < 200 and 128 + 1 below 2 afterwards: runs 127 + 73 and a run of 100.
  const size_t header = file.find("+X 300\n") + 7;
  EXPECT_EQ(file.size() - header, 4u + 3u * (4u + 101u) + 6u);
}

TEST(Rgbe, DecodesFlatOldRunLengthAndShortScanlines) {
  // Width 3 (below 8: always flat), with the old repeat pixel (1, 1, 1, n) repeating the previous
  // pixel n times, and n << 8 for a second repeat in a row.
  const std::string head = "#?RGBE\n\n-Y 2 +X 3\n";
  const std::string flat =
      head + bytes({128, 64, 0, 129, 1, 1, 1, 2}) + bytes({0, 0, 128, 130, 0, 0, 0, 0, 128, 0, 0, 128});
  const io::RgbeImage a = io::decode_rgbe(flat);
  EXPECT_FALSE(a.run_length_encoded);
  const std::vector<float> want = {1, 0.5f, 0, 1, 0.5f, 0, 1, 0.5f, 0, 0, 0, 2, 0, 0, 0, 0.5f, 0, 0};
  EXPECT_EQ(a.rgb, want);
  // a scanline of 8 that is not run-length encoded starts with an ordinary pixel
  std::string eight = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 8\n" + bytes({128, 0, 0, 129, 1, 1, 1, 7});
  const io::RgbeImage b = io::decode_rgbe(eight);
  for (int x = 0; x < 8; ++x) EXPECT_EQ(b.rgb[size_t(3 * x)], 1.0f) << x;
  // consecutive repeats shift: 1 pixel, then a repeat of 1, then of 1 << 8: 1 + 1 + 256 pixels
  const std::string shifted = "#?RADIANCE\n\n-Y 1 +X 258\n" + bytes({128, 128, 128, 129, 1, 1, 1, 1, 1, 1, 1, 1});
  const io::RgbeImage c = io::decode_rgbe(shifted);
  EXPECT_EQ(c.width, 258);
  EXPECT_EQ(c.rgb[3 * 257], 1.0f);
}

TEST(Rgbe, EveryScanlineOrderLandsWhereTheFormatSays) {
  // A 3 x 2 image, pixel (x, y) = 1 + x + 3 y in red (y = 0 the top row), stored in each of the
  // eight orders: the first axis across scanlines, the second along them; +Y is up, +X right.
  auto value = [](int x, int y) { return float(1 + x + 3 * y); };
  const struct {
    const char* order;
    bool x_first, x_reversed, y_up;
  } orders[] = {{"-Y 2 +X 3", false, false, false}, {"-Y 2 -X 3", false, true, false},
                {"+Y 2 +X 3", false, false, true},  {"+Y 2 -X 3", false, true, true},
                {"+X 3 -Y 2", true, false, false},  {"+X 3 +Y 2", true, false, true},
                {"-X 3 -Y 2", true, true, false},   {"-X 3 +Y 2", true, true, true}};
  for (const auto& o : orders) {
    std::string file = std::string("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n") + o.order + "\n";
    const int n1 = o.x_first ? 3 : 2, n2 = o.x_first ? 2 : 3;
    for (int k = 0; k < n1; ++k)
      for (int p = 0; p < n2; ++p) {
        const int xi = o.x_first ? k : p, yi = o.x_first ? p : k;
        const int x = o.x_reversed ? 2 - xi : xi, y = o.y_up ? 1 - yi : yi;
        const float rgb[3] = {value(x, y), 0, 0};
        uint8_t e[4];
        io::float_to_rgbe(rgb, e);
        file.append(reinterpret_cast<const char*>(e), 4);
      }
    const io::RgbeImage img = io::decode_rgbe(file);
    ASSERT_EQ(img.width, 3) << o.order;
    ASSERT_EQ(img.height, 2) << o.order;
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 3; ++x)
        EXPECT_EQ(img.rgb[size_t(3 * (3 * y + x))], value(x, y)) << o.order << " " << x << "," << y;
  }
}

TEST(Rgbe, HeaderVariants) {
  const std::string pixels = bytes({128, 128, 128, 129});
  EXPECT_EQ(io::decode_rgbe("#?RADIANCE\r\nFORMAT=32-bit_rle_rgbe\r\n\r\n-Y 1 +X 1\r\n" + pixels).rgb[0], 1.0f);
  EXPECT_EQ(io::decode_rgbe("#?RADIANCE\n# a comment\nEXPOSURE=2.0\n\n-Y 1 +X 1\n" + pixels).rgb[0], 1.0f)
      << "no FORMAT line: RGBE; EXPOSURE does not scale the stored values";
  EXPECT_NE(error_of_decode("#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n" + pixels).find("xyze"),
            std::string::npos);
  EXPECT_NE(error_of_decode("#?RADIANCE\nFORMAT=16-bit\n\n-Y 1 +X 1\n" + pixels).find("unknown pixel format"),
            std::string::npos);
  EXPECT_NE(error_of_decode("#?RADIANCE\n\n-Y 1 -Y 1\n" + pixels).find("bad resolution"), std::string::npos);
  EXPECT_NE(error_of_decode("#?RADIANCE\n\n-Y 0 +X 1\n").find("bad resolution"), std::string::npos);
  EXPECT_NE(error_of_decode("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n").find("no end"), std::string::npos);
  EXPECT_NE(error_of_decode("P6 not a radiance file").find("#?"), std::string::npos);
  EXPECT_NE(error_of_decode("#?RADIANCE\n\n-Y 100000 +X 100000\n").find("too large"), std::string::npos);
}

TEST(Rgbe, EveryTruncationAndCorruptionIsAnError) {
  std::vector<float> rgb;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 4.0f);
  for (int k = 0; k < 16 * 4; ++k) {
    const float v = k % 5 < 3 ? 1.0f : u(rng);  // runs and dumps
    rgb.insert(rgb.end(), {v, v * 0.5f, u(rng)});
  }
  const std::string file = io::encode_rgbe(16, 4, rgb.data());
  const size_t data_start = file.find("+X 16\n") + 6;
  for (size_t n = 0; n < file.size(); ++n)
    EXPECT_NE(error_of_decode(file.substr(0, n)), "(no error)") << "cut at " << n << " of " << file.size();
  EXPECT_NE(error_of_decode(file.substr(0, data_start + 10)).find("truncated"), std::string::npos);
  // a run that overruns its scanline
  std::string overrun = file;
  overrun[data_start + 4] = static_cast<char>(128 + 20);
  EXPECT_NE(error_of_decode(overrun).find("overruns"), std::string::npos);
  // a stated scanline length that is not the width
  std::string length = file;
  length[data_start + 3] = 15;
  EXPECT_NE(error_of_decode(length).find("states length 15"), std::string::npos);
  // an old-style repeat with nothing before it
  EXPECT_NE(error_of_decode("#?RADIANCE\n\n-Y 1 +X 2\n" + bytes({1, 1, 1, 1, 0, 0, 0, 0})).find("starts with a repeat"),
            std::string::npos);
}

TEST(Rgbe, EncoderRefusesWhatRgbeCannotHold) {
  for (float bad : {-1.0f, std::nanf(""), std::numeric_limits<float>::infinity()}) {
    const float rgb[3] = {1.0f, bad, 0.0f};
    EXPECT_THROW(io::encode_rgbe(1, 1, rgb), Error) << bad;
  }
}

// OpenImageIO, an independent reader, sees what we wrote: the same values we decode, for widths
// that take either encoding.
TEST(Rgbe, OpenImageIoReadsOurFilesAsWeDo) {
  const fs::path dir = temp_dir("rgbe-oiio");
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int width : {3, 8, 301}) {
    const int height = 5;
    std::vector<float> rgb;
    for (int k = 0; k < width * height; ++k) {
      const float scale = std::pow(10.0f, 6.0f * u(rng) - 3.0f);  // 1e-3 .. 1e3
      const float v = k % 4 == 0 ? 0.25f : scale * u(rng);
      rgb.insert(rgb.end(), {v, 0.5f * v, k % 3 == 0 ? 0.0f : u(rng) * scale});
    }
    const fs::path p = dir / ("w" + std::to_string(width) + ".hdr");
    {
      io::TempFile temp(p.string());
      io::write_rgbe(temp, width, height, rgb.data());
      temp.commit();
    }
    const io::FloatImage ours = io::read_image(p.string(), kMaxPixels);
    auto in = OIIO::ImageInput::open(p.string());
    ASSERT_TRUE(in) << OIIO::geterror();
    ASSERT_EQ(in->spec().width, width);
    ASSERT_EQ(in->spec().height, height);
    std::vector<float> theirs(rgb.size());
    ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, theirs.data()));
    EXPECT_EQ(ours.pixels, theirs) << "width " << width;
    EXPECT_NE(ours.description.find(width >= 8 ? "run-length encoded" : "flat"), std::string::npos);
  }
}

// ---- OpenEXR -------------------------------------------------------------------------------------

struct ExrCase {
  const char* name;
  OIIO::TypeDesc type;
  int tile;         // 0: scanline
  bool mip_mapped;  // every level down to 1 x 1 written (OpenEXR's round-down sizes)
  int x0, y0;       // data window origin
  std::vector<std::string> channels;
};

TEST(ExrReader, ReadsWhatOpenImageIoWrites) {
  const fs::path dir = temp_dir("exr");
  const ExrCase cases[] = {
      {"half_scanline", OIIO::TypeDesc::HALF, 0, false, 0, 0, {"R", "G", "B"}},
      {"float_offset", OIIO::TypeDesc::FLOAT, 0, false, 5, -3, {"R", "G", "B", "A"}},
      {"tiled_mipmapped", OIIO::TypeDesc::HALF, 16, true, 0, 0, {"R", "G", "B"}},
      {"tiled_float", OIIO::TypeDesc::FLOAT, 8, false, 3, 2, {"R", "G", "B"}},
      {"extra_channels", OIIO::TypeDesc::FLOAT, 0, false, 0, 0, {"Z", "R", "G", "B"}},
      {"grey", OIIO::TypeDesc::FLOAT, 0, false, 0, 0, {"Y"}},
  };
  const int w = 40, h = 20;
  for (const ExrCase& c : cases) {
    const int nch = int(c.channels.size());
    // channel value: (1 + x + w y) / 64 + channel / 4, exact in half below 2048
    auto value = [&](int x, int y, int ch) { return float(1 + x + w * y) / 64.0f + float(ch) / 4.0f; };
    const fs::path p = dir / (std::string(c.name) + ".exr");
    auto out = OIIO::ImageOutput::create(p.string());
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(w, h, nch, c.type);
    spec.x = c.x0;
    spec.y = c.y0;
    spec.channelnames = c.channels;
    spec.alpha_channel = -1;
    if (c.tile) spec.tile_width = spec.tile_height = c.tile;
    if (c.mip_mapped) spec.attribute("textureformat", "Plain Texture");  // OpenImageIO: MIPMAP_LEVELS
    ASSERT_TRUE(out->open(p.string(), spec)) << out->geterror();
    // 40 x 20 rounds down to 20x10, 10x5, 5x2, 2x1, 1x1: six levels
    const int levels = c.mip_mapped ? 6 : 1;
    for (int level = 0; level < levels; ++level) {
      const int lw = std::max(1, w >> level), lh = std::max(1, h >> level);
      if (level > 0) {
        OIIO::ImageSpec ls = spec;
        ls.width = ls.full_width = lw;
        ls.height = ls.full_height = lh;
        ASSERT_TRUE(out->open(p.string(), ls, OIIO::ImageOutput::AppendMIPLevel)) << out->geterror();
      }
      std::vector<float> px;
      for (int y = 0; y < lh; ++y)
        for (int x = 0; x < lw; ++x)
          for (int ch = 0; ch < nch; ++ch) px.push_back(level == 0 ? value(x, y, ch) : -1.0f);
      ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data())) << out->geterror();
    }
    ASSERT_TRUE(out->close());
    out.reset();  // a mip-mapped file is complete only once OpenImageIO's writer is destroyed

    const io::FloatImage img = io::read_image(p.string(), kMaxPixels);
    EXPECT_EQ(img.width, w) << c.name;
    EXPECT_EQ(img.height, h) << c.name;
    ASSERT_EQ(img.channels, nch) << c.name;
    // R, G, B, A first, then the others: the order OpenImageIO reports
    std::vector<std::string> want_names;
    for (const char* n : {"R", "G", "B", "A"})
      if (std::find(c.channels.begin(), c.channels.end(), n) != c.channels.end()) want_names.push_back(n);
    for (const auto& n : c.channels)
      if (std::find(want_names.begin(), want_names.end(), n) == want_names.end()) want_names.push_back(n);
    EXPECT_EQ(img.channel_names, want_names) << c.name;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int k = 0; k < nch; ++k) {
          const int written =
              int(std::find(c.channels.begin(), c.channels.end(), want_names[size_t(k)]) - c.channels.begin());
          ASSERT_EQ(img.pixels[size_t((y * w + x) * nch + k)], value(x, y, written))
              << c.name << " (" << x << ", " << y << ") " << want_names[size_t(k)];
        }
    if (c.tile) {
      EXPECT_NE(img.description.find("tiled"), std::string::npos) << img.description;
    }
    if (c.mip_mapped) {
      EXPECT_NE(img.description.find("6 mip levels (level 0 read)"), std::string::npos) << img.description;
    }
    EXPECT_NE(img.description.find(c.type == OIIO::TypeDesc::HALF ? "half" : "float"), std::string::npos)
        << img.description;
  }
}

// A row so long that OpenEXR's 16-row ZIP block would pass INT_MAX bytes (3 channels x 11,184,811
// cells: 134 MB a row; `fresnel --size 16777216` wrote one that no reader opened): written a row a
// block, and read back as written.
TEST(ExrReader, RowsLongerThanAZipBlockAllowsAreReadBack) {
  const fs::path dir = temp_dir("exr-long");
  const fs::path p = dir / "long.exr";
  const int width = 11184811;
  ASSERT_GT(size_t(width) * 3 * sizeof(float) * 16, size_t(INT_MAX));
  std::vector<float> px(size_t(width) * 3);
  for (size_t i = 0; i < px.size(); ++i) px[i] = float(i % 1000) * 0.25f;
  {
    io::TempFile temp(p.string());
    io::write_exr(temp, width, 1, 3, px.data(), {{"brdfbake:kind", "test"}});
    temp.commit();
  }
  const io::FloatImage back = io::read_image(p.string(), io::ImageLimits{uint64_t(1) << 28, 0});
  ASSERT_EQ(back.width, width);
  ASSERT_EQ(back.height, 1);
  EXPECT_TRUE(back.pixels == px);
}

TEST(ExrReader, TruncatedAndOversizedFilesAreErrors) {
  const fs::path dir = temp_dir("exr-bad");
  const fs::path p = dir / "full.exr";
  std::vector<float> px(64 * 32 * 3, 2.0f);
  {
    io::TempFile temp(p.string());
    io::write_exr(temp, 64, 32, 3, px.data(), {{"brdfbake:kind", "test"}});
    temp.commit();
  }
  EXPECT_EQ(io::read_image(p.string(), kMaxPixels).pixels, px);
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  const std::string all = s.str();
  for (size_t cut : {size_t(8), all.size() / 3, all.size() - 10}) {
    write_file(dir / "cut.exr", all.substr(0, cut));
    try {
      io::read_image((dir / "cut.exr").string(), kMaxPixels);
      ADD_FAILURE() << "no error for a file cut at " << cut;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("OpenEXR"), std::string::npos) << e.what();
    }
  }
  try {
    io::read_image(p.string(), io::ImageLimits{100, 0});
    ADD_FAILURE() << "no error for an image above max_pixels";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("too large"), std::string::npos) << e.what();
  }
}

// ---- The OpenImageIO module ---------------------------------------------------------------------

// A format no focused reader takes (TIFF) goes through the module; the values match OpenImageIO's
// own reading. PNG is read with libpng since issue 24 (png_image.cpp): the same values (16-bit
// without a colour chunk is read as stored).
TEST(OiioModule, ReadsOtherFormats) {
  const fs::path dir = temp_dir("module");
  for (const char* ext : {".png", ".tif"}) {
    const fs::path p = dir / (std::string("img") + ext);
    auto out = OIIO::ImageOutput::create(p.string());
    ASSERT_TRUE(out) << ext;
    OIIO::ImageSpec spec(6, 3, 3, OIIO::TypeDesc::UINT16);
    std::vector<uint16_t> px;
    for (int k = 0; k < 6 * 3 * 3; ++k) px.push_back(uint16_t(k * 1000));
    ASSERT_TRUE(out->open(p.string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT16, px.data()));
    out->close();
    const io::FloatImage img = io::read_image(p.string(), kMaxPixels);
    if (std::string(ext) == ".tif") {
      EXPECT_TRUE(io::oiio_module_loaded());
    }
    ASSERT_EQ(img.width, 6);
    ASSERT_EQ(img.channels, 3);
    EXPECT_EQ(img.channel_names, (std::vector<std::string>{"R", "G", "B"}));
    for (size_t k = 0; k < px.size(); ++k) EXPECT_FLOAT_EQ(img.pixels[k], float(px[k]) / 65535.0f) << ext << " " << k;
  }
  // what OpenImageIO does not read either: its reason, on one line
  write_file(dir / "text.xyz", "not an image\nat all\n");
  try {
    io::read_image((dir / "text.xyz").string(), kMaxPixels);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace brdfbake
