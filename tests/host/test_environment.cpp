// Loading environments: equirects (.hdr, .exr including tiled, mip-mapped, half-float), crosses,
// six face files, KTX2 cubes, the builtins; validation of values and shapes with clear errors.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/math/equirect.hpp"
#include "support/temp_dir.hpp"
#include "support/tolerances.hpp"

#ifndef BRDFBAKE_SHARED_DIR
#define BRDFBAKE_SHARED_DIR "../shared"
#endif

namespace brdfbake {
namespace {

namespace fs = std::filesystem;

// A fresh, empty folder `name` in the test's temporary folder (removed when the test ends).
fs::path temp_dir(const std::string& name) { return brdfbake::test::test_temp_dir(name); }

std::string shared_envmap(const std::string& name) {
  return (fs::path(BRDFBAKE_SHARED_DIR) / "envmaps" / name).string();
}

void write_image(const fs::path& p, int w, int h, const std::vector<float>& rgb,
                 OIIO::TypeDesc type = OIIO::TypeDesc::FLOAT) {
  auto out = OIIO::ImageOutput::create(p.string());
  ASSERT_TRUE(out) << p;
  OIIO::ImageSpec spec(w, h, 3, type);
  ASSERT_TRUE(out->open(p.string(), spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, rgb.data())) << out->geterror();
  out->close();
}

std::string error_of(const std::string& spec, bool sanitize = false) {
  try {
    EnvLoadOptions o;
    o.sanitize = sanitize;
    load_environment(spec, o);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Environment, Builtins) {
  for (const std::string name : {"studio", "sun"}) {
    const EnvImage e = builtin_environment(name, 256);
    EXPECT_EQ(e.width, 256);
    EXPECT_EQ(e.height, 128);
    EXPECT_EQ(e.source, "builtin:" + name);
    for (float v : e.rgb) {
      ASSERT_TRUE(std::isfinite(v));
      ASSERT_GE(v, 0.0f);
    }
  }
  // the sun: a peak near 5e4 carrying most of the energy (solid-angle weighted)
  const EnvImage sun = load_environment("builtin:sun");
  EXPECT_EQ(sun.width, 1024);
  double total = 0, bright = 0, peak = 0;
  for (int y = 0; y < sun.height; ++y)
    for (int x = 0; x < sun.width; ++x) {
      const size_t p = 3 * (size_t(y) * size_t(sun.width) + size_t(x));
      const double lum =
          0.2126 * double(sun.rgb[p]) + 0.7152 * double(sun.rgb[p + 1]) + 0.0722 * double(sun.rgb[p + 2]);
      const double w = std::cos(M_PI * (0.5 - (y + 0.5) / sun.height));
      total += lum * w;
      if (lum > 1000) bright += lum * w;
      peak = std::max(peak, lum);
    }
  EXPECT_GT(peak, 3e4);
  EXPECT_GT(bright / total, 0.5);
  EXPECT_NE(error_of("builtin:nope").find("builtin:studio or builtin:sun"), std::string::npos);
}

TEST(Environment, EquirectFilesAndHalfFloatExr) {
  const fs::path dir = temp_dir("equirect");
  std::vector<float> rgb;
  for (int k = 0; k < 8 * 4; ++k) rgb.insert(rgb.end(), {float(k), 0.5f, 2.0f});
  write_image(dir / "e.exr", 8, 4, rgb, OIIO::TypeDesc::HALF);
  write_image(dir / "e.hdr", 8, 4, rgb);
  const EnvImage exr = load_environment((dir / "e.exr").string());
  EXPECT_EQ(exr.layout, EnvImage::Layout::Equirect);
  EXPECT_EQ(exr.width, 8);
  EXPECT_EQ(exr.height, 4);
  EXPECT_EQ(exr.rgb[3 * 17], 17.0f);
  const EnvImage hdr = load_environment((dir / "e.hdr").string());
  EXPECT_NEAR(hdr.rgb[3 * 17], 17.0f, test::kRgbeStepOfLargest * 17.0);  // RGBE
  fs::remove_all(dir);
}

TEST(Environment, TiledMipMappedExrFromShared) {
  const std::string file = shared_envmap("KernerEnvLatLong.exr");
  if (!fs::exists(file)) GTEST_SKIP() << "no shared envmaps at " << BRDFBAKE_SHARED_DIR << " (" << file << ")";
  const EnvImage e = load_environment(file);
  EXPECT_EQ(e.width, 1024);
  EXPECT_EQ(e.height, 512);
  EXPECT_NE(e.description.find("tiled"), std::string::npos) << e.description;
  EXPECT_NE(e.description.find("mip levels (level 0 read)"), std::string::npos) << e.description;
  double peak = 0;
  for (float v : e.rgb) peak = std::max(peak, double(v));
  EXPECT_GT(peak, 1000.0);  // SOURCES.md: max luminance 1678
}

// The documented equirect mapping (math::equirect_coords) puts OpenEXR's chart's black axis
// lines where the chart says the axes are (tests/device/test_prefilter.cpp checks the device's
// conversion the same way).
TEST(Environment, OrientationChartMatchesTheDocumentedMapping) {
  const std::string file = shared_envmap("OrientationLatLong.exr");
  if (!fs::exists(file)) GTEST_SKIP() << "no shared envmaps at " << BRDFBAKE_SHARED_DIR << " (" << file << ")";
  const EnvImage e = load_environment(file);
  auto lum = [&](double x, double y, double z) {
    double u = 0, v = 0;
    math::equirect_coords({x, y, z}, u, v);
    const int px = std::min(e.width - 1, int(u * e.width)), py = std::min(e.height - 1, int(v * e.height));
    double darkest = 1e9;
    for (int dy = -1; dy <= 1; ++dy) {
      const size_t p = 3 * (size_t(std::clamp(py + dy, 0, e.height - 1)) * size_t(e.width) + size_t(px));
      darkest = std::min(darkest, (double(e.rgb[p]) + double(e.rgb[p + 1]) + double(e.rgb[p + 2])) / 3.0);
    }
    return darkest;
  };
  const double c = std::cos(0.1), s = std::sin(0.1);
  EXPECT_LT(lum(c, 0, s), 0.3) << "+X towards +Z";
  EXPECT_GT(lum(c, 0, -s), 0.5) << "+X towards -Z";
  EXPECT_LT(lum(s, 0, c), 0.3) << "+Z towards +X";
  EXPECT_GT(lum(-s, 0, c), 0.5) << "+Z towards -X";
  EXPECT_LT(lum(c, s, 0), 0.3) << "+X up towards +Y";
}

TEST(Environment, CrossesAndFaces) {
  const fs::path dir = temp_dir("cross");
  const int s = 4;
  // cell (col, row) of a cross filled with 10 col + row + i / 100 (i the column in the cell)
  auto cross = [&](int cols, int rows) {
    std::vector<float> rgb;
    for (int y = 0; y < rows * s; ++y)
      for (int x = 0; x < cols * s; ++x) {
        const float v = float(10 * (x / s) + y / s) + float(x % s) / 100.0f;
        rgb.insert(rgb.end(), {v, v, v});
      }
    return rgb;
  };
  write_image(dir / "h.exr", 4 * s, 3 * s, cross(4, 3));
  write_image(dir / "v.exr", 3 * s, 4 * s, cross(3, 4));
  const EnvImage h = load_environment((dir / "h.exr").string());
  ASSERT_EQ(h.layout, EnvImage::Layout::Cube);
  ASSERT_EQ(h.width, s);
  // +X, -X, +Y, -Y, +Z, -Z sit in cells (2,1), (0,1), (1,0), (1,2), (1,1), (3,1)
  const float cells[6] = {21, 1, 10, 12, 11, 31};
  for (int f = 0; f < 6; ++f) EXPECT_FLOAT_EQ(h.rgb[3 * size_t(f * s * s + 1)], cells[f] + 0.01f) << f;
  const EnvImage v = load_environment((dir / "v.exr").string());
  ASSERT_EQ(v.width, s);
  // -Z in cell (1, 3), turned by 180 degrees: its texel (1, 0) is the cell's pixel (2, 3)
  EXPECT_FLOAT_EQ(v.rgb[3 * size_t(5 * s * s + 1)], 13.02f);
  // six faces, as a list and as a {face} pattern
  const char* names[6] = {"px", "nx", "py", "ny", "pz", "nz"};
  std::string list;
  for (int f = 0; f < 6; ++f) {
    write_image(dir / ("f_" + std::string(names[f]) + ".exr"), s, s, std::vector<float>(3 * s * s, float(f)));
    list += (f ? "," : "") + (dir / ("f_" + std::string(names[f]) + ".exr")).string();
  }
  for (const std::string& spec : {list, (dir / "f_{face}.exr").string()}) {
    const EnvImage faces = load_environment(spec);
    ASSERT_EQ(faces.layout, EnvImage::Layout::Cube);
    for (int f = 0; f < 6; ++f) EXPECT_FLOAT_EQ(faces.rgb[3 * size_t(f * s * s)], float(f));
  }
  write_image(dir / "g_px.exr", 2 * s, 2 * s, std::vector<float>(12 * s * s, 1.0f));
  for (int f = 1; f < 6; ++f)
    fs::copy_file(dir / ("f_" + std::string(names[f]) + ".exr"), dir / ("g_" + std::string(names[f]) + ".exr"));
  EXPECT_NE(error_of((dir / "g_{face}.exr").string()).find("but"), std::string::npos);
  EXPECT_NE(error_of(dir.string() + "/a.exr," + dir.string() + "/b.exr").find("six files"), std::string::npos);
  fs::remove_all(dir);
}

TEST(Environment, KtxCubeInput) {
  const fs::path dir = temp_dir("ktx");
  CubeLevels c;
  c.size = 2;
  c.levels.assign(1, std::vector<float>(24 * 4, 3.0f));
  write_cubemap(c, (dir / "c.ktx2").string(), CubeFormat::Ktx2);
  const EnvImage e = load_environment((dir / "c.ktx2").string());
  EXPECT_EQ(e.layout, EnvImage::Layout::Cube);
  EXPECT_EQ(e.width, 2);
  EXPECT_FLOAT_EQ(e.rgb[7], 3.0f);
  fs::remove_all(dir);
}

TEST(Environment, BadValuesAreRefusedOrSanitized) {
  const fs::path dir = temp_dir("values");
  std::vector<float> rgb(3 * 8 * 4, 1.0f);
  rgb[0] = std::numeric_limits<float>::quiet_NaN();
  rgb[4] = std::numeric_limits<float>::infinity();
  rgb[5] = -std::numeric_limits<float>::infinity();
  rgb[9] = -2.0f;
  rgb[10] = 7.0f;
  write_image(dir / "bad.exr", 8, 4, rgb);
  const std::string msg = error_of((dir / "bad.exr").string());
  EXPECT_NE(msg.find("1 NaN, 2 infinite and 1 negative"), std::string::npos) << msg;
  EXPECT_NE(msg.find("--sanitize"), std::string::npos) << msg;
  EnvLoadOptions o;
  o.sanitize = true;
  const EnvImage e = load_environment((dir / "bad.exr").string(), o);
  EXPECT_TRUE(e.sanitize.replaced);
  EXPECT_EQ(e.sanitize.nan, 1u);
  EXPECT_EQ(e.sanitize.infinite, 2u);
  EXPECT_EQ(e.sanitize.negative, 1u);
  EXPECT_EQ(e.rgb[0], 0.0f);
  EXPECT_EQ(e.rgb[4], 7.0f);  // +inf: the largest finite value
  EXPECT_EQ(e.rgb[5], 0.0f);
  EXPECT_EQ(e.rgb[9], 0.0f);
  fs::remove_all(dir);
}

TEST(Environment, BadFilesGiveClearErrors) {
  const fs::path dir = temp_dir("files");
  write_image(dir / "odd.exr", 10, 7, std::vector<float>(3 * 70, 1.0f));
  EXPECT_NE(error_of((dir / "odd.exr").string()).find("expected an equirect of 2:1"), std::string::npos);
  // a truncated Radiance file
  std::vector<float> rgb(3 * 64 * 32, 1.5f);
  for (size_t k = 0; k < rgb.size(); ++k) rgb[k] = float(k % 97) + 0.5f;
  write_image(dir / "full.hdr", 64, 32, rgb);
  {
    std::ifstream in(dir / "full.hdr", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(dir / "cut.hdr", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  EXPECT_NE(error_of((dir / "cut.hdr").string()).find("cannot read environment"), std::string::npos);
  std::ofstream(dir / "text.hdr") << "not an image at all";
  EXPECT_NE(error_of((dir / "text.hdr").string()).find("cannot read environment"), std::string::npos);
  std::ofstream(dir / "data.xyz") << "?";
  EXPECT_NE(error_of((dir / "data.xyz").string()).find("cannot read environment"), std::string::npos);
  EXPECT_NE(error_of((dir / "missing.hdr").string()).find("no such file"), std::string::npos);
  std::ofstream(dir / "bad.ktx2") << "KTX";
  EXPECT_NE(error_of((dir / "bad.ktx2").string()).find("KTX2"), std::string::npos);
  EXPECT_NE(error_of("").find("no environment"), std::string::npos);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace brdfbake
