// `brdfbake view`: pictures whose pixels can be predicted (a constant cube is a constant cross of
// the tone-mapped value, a table's colour scale puts its minimum and maximum at the ends, a constant
// environment's SH sphere is one colour), the regions and labels of the sheet, and every kind of
// output the tool writes viewed through the command line without an error.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/io.hpp"
#include "brdfbake/preview.hpp"
#include "brdfbake/view.hpp"
#include "families/preview/model.hpp"
#include "families/preview/output.hpp"
#include "io/png_image.hpp"
#include "support/cli_runner.hpp"
#include "support/temp_dir.hpp"
#include "support/tolerances.hpp"
#include "view/canvas.hpp"
#include "view/exposure.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;
using Rgb8 = std::array<int, 3>;
using test::CliRun;
using test::run_cli;

// A fresh, empty folder `name` in the test's temporary folder (removed when the test ends).
fs::path temp_dir(const std::string& name) { return brdfbake::test::test_temp_dir(name); }

// The display transfer the sheet states, written out independently of the renderer: Narkowicz's
// ACES fit, then the sRGB encoding (IEC 61966-2-1), rounded to 8 bits.
int aces_srgb8(double x) {
  const double t = std::clamp(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
  const double e = t <= 0.0031308 ? 12.92 * t : 1.055 * std::pow(t, 1.0 / 2.4) - 0.055;
  return static_cast<int>(std::lround(e * 255.0));
}

Rgb8 pixel(const ContactSheet& s, int x, int y) {
  const uint8_t* p = &s.rgb[3 * (size_t(y) * size_t(s.width) + size_t(x))];
  return {p[0], p[1], p[2]};
}

std::vector<SheetRegion> regions(const ContactSheet& s, const std::string& role) {
  std::vector<SheetRegion> out;
  for (const auto& r : s.regions)
    if (r.role == role) out.push_back(r);
  return out;
}

// Whether any pixel of the rectangle differs from the colour at its top-left corner (text drawn).
bool has_marks(const ContactSheet& s, int x, int y, int w, int h) {
  const Rgb8 bg = pixel(s, x, y);
  for (int j = y; j < y + h && j < s.height; ++j)
    for (int i = x; i < x + w && i < s.width; ++i)
      if (pixel(s, i, j) != bg) return true;
  return false;
}

CubeLevels constant_cube(int size, int levels, float value) {
  CubeLevels c;
  c.size = size;
  for (int l = 0; l < levels; ++l) {
    const size_t s = static_cast<size_t>(c.level_size(l));
    std::vector<float> v(24 * s * s, value);
    for (size_t t = 3; t < v.size(); t += 4) v[t] = 1.0f;
    c.levels.push_back(v);
  }
  c.set_meta("roughness_per_level", "0,0.5,1");
  c.set_meta("kind", "prefiltered radiance");
  return c;
}

// Where the faces sit in a cross of face f: -X +Z +X -Z in the middle row, +Y above +Z, -Y below.
const int kFaceCells[6][2] = {{2, 1}, {0, 1}, {1, 0}, {1, 2}, {1, 1}, {3, 1}};

// view::srgb8 finds its code among thresholds instead of calling pow: every value must get the
// formula's own code (IEC 61966-2-1, rounded to 8 bits; written out here as aces_srgb8 does): on
// a sweep of [0, 1] in linear and in log steps, and on both sides of every step between codes.
TEST(View, Srgb8IsTheFormulaItStandsFor) {
  auto formula = [](double v) {
    if (!(v > 0.0)) return 0;
    if (v >= 1.0) return 255;
    const double e = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
    return static_cast<int>(std::lround(e * 255.0));
  };
  int checked = 0;
  auto check = [&](double v) {
    ASSERT_EQ(int(view::srgb8(v)), formula(v)) << "at " << v;
    ++checked;
  };
  for (int i = 0; i <= 200000; ++i) check(i / 200000.0);
  for (int i = 0; i <= 200000; ++i) check(std::exp2(-40.0 + 40.0 * i / 200000.0));
  // the last double below each step and the step itself (the step found from the formula)
  for (int k = 1; k < 256; ++k) {
    double lo = 0.0, hi = 1.0;
    for (int i = 0; i < 200 && std::nextafter(lo, 1.0) < hi; ++i) {
      const double mid = 0.5 * (lo + hi);
      (formula(mid) >= k ? hi : lo) = mid;
    }
    check(hi);
    check(std::nextafter(hi, 0.0));
    check(std::nextafter(hi, 1.0));
  }
  EXPECT_GT(checked, 400000);
  EXPECT_EQ(view::srgb8(-1.0), 0);
  EXPECT_EQ(view::srgb8(std::nan("")), 0);
  EXPECT_EQ(view::srgb8(2.0), 255);
}

TEST(View, ConstantCubeIsAConstantCrossInEveryContainer) {
  const fs::path dir = temp_dir("constant");
  const CubeLevels cube = constant_cube(16, 3, 0.25f);  // 0.25 is exact in binary16
  std::vector<std::string> paths;
  for (const char* name : {"c.ktx2", "c.ktx", "c.dds", "faces/"}) {
    const std::string p = (dir / name).string();
    write_cubemap(cube, p, cube_format_from_path(p));
    paths.push_back(p);
  }
  ViewOptions o;
  o.face_size = 16;
  for (double exposure : {0.0, 2.0}) {
    o.exposure = exposure;
    const ContactSheet s = render_contact_sheet(paths, o);
    const int expected = aces_srgb8(0.25 * std::exp2(exposure));
    const auto levels = regions(s, "cube level");
    ASSERT_EQ(levels.size(), 4u * 3u);
    for (const auto& r : levels) {
      SCOPED_TRACE(r.file + " " + r.label);
      EXPECT_EQ(r.width, 4 * 16);
      EXPECT_EQ(r.height, 3 * 16);
      std::set<std::pair<int, int>> face_cells;
      for (const auto& c : kFaceCells) {
        face_cells.insert({c[0], c[1]});
        for (int y = 0; y < 16; ++y)
          for (int x = 0; x < 16; ++x)
            ASSERT_EQ(pixel(s, r.x + c[0] * 16 + x, r.y + c[1] * 16 + y), (Rgb8{expected, expected, expected}));
      }
      // The six empty cells are one colour, not the cube's.
      const Rgb8 empty = pixel(s, r.x, r.y);
      EXPECT_NE(empty, (Rgb8{expected, expected, expected}));
      for (int col = 0; col < 4; ++col)
        for (int row = 0; row < 3; ++row)
          if (!face_cells.count({col, row})) {
            EXPECT_EQ(pixel(s, r.x + col * 16 + 7, r.y + row * 16 + 7), empty);
          }
      // The level's caption (size and roughness) is drawn under the cross.
      EXPECT_TRUE(has_marks(s, r.x, r.y + r.height + 1, r.width, 26)) << "no caption";
    }
    EXPECT_EQ(levels[0].label, "level 0");
    EXPECT_EQ(levels[2].label, "level 2");
    EXPECT_NE(s.tone_map_text.find(exposure == 0 ? "exposure +0.0 EV, ACES" : "exposure +2.0 EV, ACES"),
              std::string::npos)
        << s.tone_map_text;
    // Each file has its title, with text in it.
    const auto titles = regions(s, "file title");
    ASSERT_EQ(titles.size(), 4u);
    for (const auto& t : titles) EXPECT_TRUE(has_marks(s, t.x, t.y, t.width, 10)) << t.label;
    EXPECT_GE(s.width, 4 * 16 * 3);
    EXPECT_EQ(s.rgb.size(), 3u * size_t(s.width) * size_t(s.height));
  }
}

TEST(View, TableColourScaleMapsMinimumAndMaximumToItsEnds) {
  const fs::path dir = temp_dir("table");
  Table t;
  t.width = 8;
  t.height = 6;
  t.channels = {"scale", "bias"};
  t.x_name = "n_dot_v";
  t.y_name = "roughness";
  for (int i = 0; i < t.width; ++i) t.x.push_back((i + 0.5) / t.width);
  for (int j = 0; j < t.height; ++j) t.y.push_back((j + 0.5) / t.height);
  // scale rises with i + j from 0.25 to 1.5; bias is 0.1 but for one texel of 10 and one of 0.01:
  // the maximum is 100 times the rest, so the scale is log10, from 0.01 to 10.
  for (int j = 0; j < t.height; ++j)
    for (int i = 0; i < t.width; ++i) {
      t.data.push_back(0.25f + 1.25f * float(i + j) / float(t.width + t.height - 2));
      t.data.push_back(i == t.width - 1 && j == t.height - 1 ? 10.0f : i == 0 && j == 0 ? 0.01f : 0.1f);
    }
  t.set_meta("x_axis", "n_dot_v = (i + 0.5) / width, the cell centre of column i");
  t.set_meta("y_axis", "roughness = (j + 0.5) / height");
  const std::string path = (dir / "t.exr").string();
  write_table(t, path, TableFormat::Exr);
  const ContactSheet s = render_contact_sheet({path});
  const auto images = regions(s, "table channel");
  const auto scales = regions(s, "colour scale");
  ASSERT_EQ(images.size(), 2u);
  ASSERT_EQ(scales.size(), 2u);
  // scale: linear from its minimum to its maximum.
  EXPECT_FALSE(images[0].log_scale);
  EXPECT_DOUBLE_EQ(images[0].lo, 0.25);
  EXPECT_DOUBLE_EQ(images[0].hi, 1.5);
  EXPECT_EQ(scales[0].lo, images[0].lo);
  EXPECT_EQ(scales[0].hi, images[0].hi);
  // Cubehelix runs from black to white: the scale's ends, the minimum texel (0, 0) at the bottom
  // left of the image (y points up) and the maximum texel at the top right.
  const SheetRegion& im = images[0];
  const SheetRegion& bar = scales[0];
  EXPECT_EQ(pixel(s, bar.x, bar.y + 2), (Rgb8{0, 0, 0}));
  EXPECT_EQ(pixel(s, bar.x + bar.width - 1, bar.y + 2), (Rgb8{255, 255, 255}));
  EXPECT_EQ(pixel(s, im.x + 1, im.y + im.height - 2), (Rgb8{0, 0, 0}));
  EXPECT_EQ(pixel(s, im.x + im.width - 2, im.y + 1), (Rgb8{255, 255, 255}));
  // A middle value is neither end.
  const Rgb8 mid = pixel(s, bar.x + bar.width / 2, bar.y + 2);
  EXPECT_NE(mid, (Rgb8{0, 0, 0}));
  EXPECT_NE(mid, (Rgb8{255, 255, 255}));
  // bias: log10, its ends at log10 of its extremes; the extremes' texels at the scale's ends.
  EXPECT_TRUE(images[1].log_scale);
  EXPECT_NEAR(images[1].lo, -2.0, test::kFloatLog10);
  EXPECT_NEAR(images[1].hi, 1.0, test::kFloatLog10);
  EXPECT_EQ(pixel(s, images[1].x + 1, images[1].y + images[1].height - 2), (Rgb8{0, 0, 0}));
  EXPECT_EQ(pixel(s, images[1].x + images[1].width - 2, images[1].y + 1), (Rgb8{255, 255, 255}));
  // Labels: the axes' ends and the scale's ends are written below the image.
  EXPECT_TRUE(has_marks(s, im.x, im.y + im.height + 1, im.width, 12)) << "no x axis labels";
  EXPECT_TRUE(has_marks(s, bar.x, bar.y + bar.height + 1, bar.width, 10)) << "no scale labels";
  EXPECT_TRUE(has_marks(s, im.x - 30, im.y, 28, 10)) << "no y axis label";
}

TEST(View, OneDimensionalTableIsAPlot) {
  const fs::path dir = temp_dir("plot");
  Table t;
  t.width = 32;
  t.height = 1;
  t.channels = {"r", "g", "b"};
  t.x_name = "cos_theta";
  for (int i = 0; i < t.width; ++i) {
    t.x.push_back((i + 0.5) / t.width);
    for (int c = 0; c < 3; ++c) t.data.push_back(float(c + 1) * float(i) / 31.0f);
  }
  const std::string path = (dir / "f.csv").string();
  write_table(t, path, TableFormat::Csv);
  const ContactSheet s = render_contact_sheet({path});
  const auto plots = regions(s, "plot");
  ASSERT_EQ(plots.size(), 1u);
  EXPECT_DOUBLE_EQ(plots[0].lo, 0.0);
  EXPECT_DOUBLE_EQ(plots[0].hi, 3.0);
  EXPECT_TRUE(regions(s, "table channel").empty());
  // The blue series (the largest) ends at the top right corner of the plot.
  bool blue_at_top = false;
  for (int x = plots[0].x + plots[0].width - 4; x < plots[0].x + plots[0].width; ++x)
    blue_at_top |= pixel(s, x, plots[0].y)[2] > 200 && pixel(s, x, plots[0].y)[0] < 150;
  EXPECT_TRUE(blue_at_top);
}

TEST(View, ConstantEnvironmentShIsAUniformSphere) {
  const fs::path dir = temp_dir("sh");
  // L = 1 everywhere: E / pi = 1 = c00 Y00 with Y00 = 1 / (2 sqrt(pi)).
  ShCoefficients sh;
  sh.order = 3;
  sh.radiance.assign(27, 0.0);
  sh.irradiance_over_pi.assign(27, 0.0);
  for (int c = 0; c < 3; ++c) {
    sh.irradiance_over_pi[size_t(c)] = 2.0 * std::sqrt(3.14159265358979323846);
    sh.radiance[size_t(c)] = 2.0 * std::sqrt(3.14159265358979323846);
  }
  const std::string path = (dir / "sh.json").string();
  write_sh_json(sh, {{"kind", "irradiance"}}, path);
  ViewOptions o;
  o.exposure = 0.0;  // the pixel asserted below is the tone map of 1.0 itself
  const ContactSheet s = render_contact_sheet({path}, o);
  const auto spheres = regions(s, "sphere");
  ASSERT_EQ(spheres.size(), 2u);
  const int v = aces_srgb8(1.0);
  for (const auto& r : spheres) {
    const int cx = r.x + r.width / 2, cy = r.y + r.height / 2;
    for (int dy = -40; dy <= 40; dy += 8)
      for (int dx = -40; dx <= 40; dx += 8) EXPECT_EQ(pixel(s, cx + dx, cy + dy), (Rgb8{v, v, v})) << r.label;
    EXPECT_NE(pixel(s, r.x, r.y), (Rgb8{v, v, v})) << "the corner is outside the sphere";
  }
  const auto bands = regions(s, "band plot");
  ASSERT_EQ(bands.size(), 1u);
  EXPECT_NEAR(bands[0].hi, 2.0 * std::sqrt(3.14159265358979323846), test::kRoundingFewOps) << "band 0 holds everything";
}

TEST(View, BadInputIsAClearError) {
  const fs::path dir = temp_dir("bad");
  auto error_of = [](const std::vector<std::string>& p) {
    try {
      render_contact_sheet(p);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error_of({(dir / "missing.ktx2").string()}).find("no such file"), std::string::npos);
  std::ofstream(dir / "x.txt") << "text";
  EXPECT_NE(error_of({(dir / "x.txt").string()}).find("unknown kind of file"), std::string::npos);
  std::ofstream(dir / "job.json") << R"({"tables": []})";
  EXPECT_NE(error_of({(dir / "job.json").string()}).find("not a JSON file brdfbake writes"), std::string::npos);
  std::ofstream(dir / "bad.ktx2") << "not a ktx2";
  EXPECT_NE(error_of({(dir / "bad.ktx2").string()}).find("KTX2"), std::string::npos);
  EXPECT_NE(error_of({}).find("nothing to view"), std::string::npos);
}

// ---- The exposure chosen from the content (issue 24, a new user's item 6) -----------------------

// The automatic exposure, against its rule written out (view/exposure.hpp): the log-average
// luminance at 0.18, the 99th percentile at most 1.0, rounded down to a tenth of an EV.
TEST(ViewExposure, AutomaticExposureFollowsItsRule) {
  auto ev = [](const std::vector<float>& rgb) { return view::auto_exposure(rgb.data(), rgb.size() / 3, 3); };
  // Uniform luminance L: the key alone, log2(0.18 / L) (below log2(2 / L)).
  for (float level : {1.0f, 100.0f, 65000.0f, 1e-3f}) {
    const std::vector<float> flat(3 * 1000, level);
    EXPECT_DOUBLE_EQ(ev(flat), std::floor(10 * std::log2(0.18 / double(level))) / 10) << level;
  }
  // A sky of 1 with a sun of 65000 on 4 texels in 1000 (below the top percent): the key of the
  // log-average exp(4 ln 65000 / 1000), the sun left to clip as in a photograph.
  std::vector<float> sun(3 * 1000, 1.0f);
  for (size_t t = 0; t < 4 * 3; ++t) sun[t] = 65000.0f;
  EXPECT_DOUBLE_EQ(ev(sun), std::floor(10 * std::log2(0.18 / std::exp(4 * std::log(65000.0) / 1000))) / 10);
  // A glow: 5 % of texels at 1000 over a floor of 0.01: the key would put the top percent at
  // 1000 * 0.18 / exp(0.05 ln 1000 + 0.95 ln 0.01), far above 1; the exposure brings it to 1.
  std::vector<float> glow(3 * 1000, 0.01f);
  for (size_t t = 0; t < 50 * 3; ++t) glow[t] = 1000.0f;
  EXPECT_DOUBLE_EQ(ev(glow), std::floor(10 * std::log2(1.0 / 1000.0)) / 10);
  // Nothing bright: 0 EV, not a division by zero.
  EXPECT_EQ(ev(std::vector<float>(30, 0.0f)), 0.0);
}

// A blurred level of a sun map (radiance ~100 everywhere) and its SH sphere were white at 0 EV:
// by default each picture is drawn at its own exposure, which the sheet records and the caption
// states; --exposure still overrides it.
TEST(ViewExposure, BrightCubesAndSpheresAreNotWhiteByDefault) {
  const fs::path dir = temp_dir("bright");
  const CubeLevels cube = constant_cube(16, 3, 96.0f);
  const std::string cube_path = (dir / "c.ktx2").string();
  write_cubemap(cube, cube_path, cube_format_from_path(cube_path));
  ShCoefficients sh;
  sh.order = 3;
  sh.radiance.assign(27, 0.0);
  sh.irradiance_over_pi.assign(27, 0.0);
  for (int c = 0; c < 3; ++c) sh.irradiance_over_pi[size_t(c)] = sh.radiance[size_t(c)] = 96.0 * 2.0 * std::sqrt(M_PI);
  const std::string sh_path = (dir / "sh.json").string();
  write_sh_json(sh, {{"kind", "irradiance"}}, sh_path);
  ViewOptions o;
  o.face_size = 16;
  const ContactSheet s = render_contact_sheet({cube_path, sh_path}, o);
  const double expected_ev = std::floor(10 * std::log2(0.18 / 96.0)) / 10;
  const int v = aces_srgb8(96.0 * std::exp2(expected_ev));
  EXPECT_LT(v, 200) << "middle grey, not white";
  const auto levels = regions(s, "cube level");
  ASSERT_EQ(levels.size(), 3u);
  for (const auto& r : levels) {
    EXPECT_DOUBLE_EQ(r.exposure, expected_ev) << r.label;
    EXPECT_EQ(pixel(s, r.x + 16 + 8, r.y + 16 + 8), (Rgb8{v, v, v})) << r.label;  // +Z's centre
  }
  const auto spheres = regions(s, "sphere");
  ASSERT_EQ(spheres.size(), 2u);
  for (const auto& r : spheres) {
    EXPECT_NEAR(r.exposure, expected_ev, 0.1 + 1e-9) << "the sphere's E/pi is 96 up to float rounding";
    const int sv = aces_srgb8(96.0 * std::exp2(r.exposure));
    EXPECT_EQ(pixel(s, r.x + r.width / 2, r.y + r.height / 2), (Rgb8{sv, sv, sv}));
  }
  EXPECT_NE(s.tone_map_text.find("chosen per picture"), std::string::npos) << s.tone_map_text;
  // An exposure asked for is the one used, everywhere (0 EV paints this cube white).
  o.exposure = 0.0;
  const ContactSheet fixed = render_contact_sheet({cube_path}, o);
  for (const auto& r : regions(fixed, "cube level")) {
    EXPECT_EQ(r.exposure, 0.0);
    EXPECT_EQ(pixel(fixed, r.x + 16 + 8, r.y + 16 + 8), (Rgb8{255, 255, 255}));
  }
}

// The map of the report: rooitou_park (a sun of luminance ~65 000 over a sky near 1). Every level
// of its chain and its SH sphere show mostly not-white pixels by default.
TEST(ViewExposure, SunMapChainIsNotBlownOut) {
  const fs::path map = fs::path(BRDFBAKE_SHARED_DIR) / "envmaps" / "rooitou_park_1k.hdr";
  if (!fs::exists(map)) GTEST_SKIP() << "the shared maps (../shared) are absent: " << map;
  const fs::path dir = temp_dir("sun");
  const CliRun chain = run_cli("prefilter --environment " + map.string() + " --size 16 --min-size 4 --quiet -o " +
                               (dir / "p.ktx2").string());
  ASSERT_EQ(chain.code, 0) << chain.err;
  const CliRun sh = run_cli("irradiance --environment " + map.string() + " --quiet -o " + (dir / "sh.json").string());
  ASSERT_EQ(sh.code, 0) << sh.err;
  ViewOptions o;
  o.face_size = 16;
  const ContactSheet s = render_contact_sheet({(dir / "p.ktx2").string(), (dir / "sh.json").string()}, o);
  auto white_fraction = [&](const SheetRegion& r, bool disc) {
    int white = 0, all = 0;
    for (int y = 0; y < r.height; ++y)
      for (int x = 0; x < r.width; ++x) {
        const double u = (x + 0.5) / r.width * 2 - 1, w = (y + 0.5) / r.height * 2 - 1;
        if (disc && u * u + w * w > 0.9) continue;
        ++all;
        white += pixel(s, r.x + x, r.y + y) == Rgb8{255, 255, 255};
      }
    return double(white) / all;
  };
  const auto levels = regions(s, "cube level");
  ASSERT_EQ(levels.size(), 3u);
  for (const auto& r : levels) EXPECT_LT(white_fraction(r, false), 0.05) << r.label << " at " << r.exposure << " EV";
  for (const auto& r : regions(s, "sphere")) EXPECT_LT(white_fraction(r, true), 0.05) << r.label;
}

// ---- Labels: material rows, scale values, folders inside folders (item 10) ----------------------

// Whether `text` is drawn at (x, y) in colour c: every pixel the font sets is c on the sheet.
bool text_at(const ContactSheet& s, int x, int y, const std::string& text, view::Rgb8 c) {
  view::Canvas probe(view::text_width(text) + 2, view::kLineHeight, {0, 0, 0});
  probe.text(0, 0, text, c);
  int lit = 0;
  for (int j = 0; j < probe.height(); ++j)
    for (int i = 0; i < probe.width(); ++i)
      if (probe.get(i, j) == c) {
        ++lit;
        if (x + i >= s.width || y + j >= s.height) return false;
        if (pixel(s, x + i, y + j) != (Rgb8{c[0], c[1], c[2]})) return false;
      }
  return lit > 0;
}

// A log scale from 0.01 to 10 is labelled with values ("0.01", "10"), not exponents ("1e-2").
TEST(ViewLabels, LogScaleEndsAreValues) {
  const fs::path dir = temp_dir("log-labels");
  Table t;
  t.width = 16;
  t.height = 16;
  t.channels = {"v"};
  for (int j = 0; j < t.height; ++j)
    for (int i = 0; i < t.width; ++i) t.data.push_back(i == 15 && j == 15 ? 10.0f : i == 0 && j == 0 ? 0.01f : 0.1f);
  const std::string path = (dir / "t.exr").string();
  write_table(t, path, TableFormat::Exr);
  const ContactSheet s = render_contact_sheet({path});
  const auto scales = regions(s, "colour scale");
  ASSERT_EQ(scales.size(), 1u);
  const SheetRegion& bar = scales[0];
  ASSERT_TRUE(bar.log_scale);
  const int y = bar.y + bar.height + 2;
  EXPECT_TRUE(text_at(s, bar.x, y, "0.01", view::kAxis)) << "the left end, as a value";
  EXPECT_TRUE(text_at(s, bar.x + bar.width - view::text_width("10"), y, "10", view::kAxis)) << "the right end";
  EXPECT_FALSE(text_at(s, bar.x, y, "1e-2", view::kAxis));
}

// A table whose median sits in the darkest tenth of a linear scale (the 32^2 Charlie table: a
// median of 0.19 under grazing texels of 3.2, all within 5x of the 99th percentile) is drawn on a
// log scale rather than black.
TEST(ViewLabels, MostlyDarkTableGetsALogScale) {
  const fs::path dir = temp_dir("dark");
  Table t;
  t.width = 32;
  t.height = 32;
  t.channels = {"v"};
  for (int j = 0; j < t.height; ++j)
    for (int i = 0; i < t.width; ++i)
      t.data.push_back(i < 24 ? 0.1f + 0.1f * float(j) / 31 : 0.2f + 3.0f * float(i - 24) / 7);
  const std::string path = (dir / "c.exr").string();
  write_table(t, path, TableFormat::Exr);
  const ContactSheet s = render_contact_sheet({path});
  const auto images = regions(s, "table channel");
  ASSERT_EQ(images.size(), 1u);
  EXPECT_TRUE(images[0].log_scale);
  EXPECT_NEAR(images[0].hi, std::log10(3.2), test::kFloatLog10);
  EXPECT_NEAR(images[0].lo, std::log10(0.1), test::kFloatLog10);
}

// An albedo table of three materials names its rows from material_names.
TEST(ViewLabels, AlbedoRowsAreNamedFromTheMetadata) {
  const fs::path dir = temp_dir("albedo");
  std::ofstream(dir / "m.json") << R"({"materials": [
      {"name": "gold", "model": "gltf", "baseColor": [1.0, 0.78, 0.34], "metallic": 1, "roughness": 0.3},
      {"name": "blue", "model": "gltf", "baseColor": [0.1, 0.2, 0.8], "metallic": 0, "roughness": 0.5},
      {"name": "chalk", "model": "gltf", "baseColor": [0.9, 0.9, 0.9], "metallic": 0, "roughness": 0.9}]})";
  const CliRun r = run_cli("tabulate --material " + (dir / "m.json").string() + " --layout albedo --res 8 --quiet -o " +
                           (dir / "albedo.exr").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const ContactSheet s = render_contact_sheet({(dir / "albedo.exr").string()});
  const auto images = regions(s, "table channel");
  ASSERT_FALSE(images.empty());
  const SheetRegion& im = images[0];
  const char* names[3] = {"gold", "blue", "chalk"};
  for (int j = 0; j < 3; ++j) {  // row 0 at the bottom
    const int band_top = im.y + (2 - j) * im.height / 3, band_h = im.height / 3;
    const int x = im.x - 4 - view::text_width(names[j]);
    EXPECT_TRUE(text_at(s, x, band_top + (band_h - 8) / 2, names[j], view::kAxis)) << names[j];
  }
}

// A folder holding folders: what they hold is shown, and what view cannot show is named as skipped.
TEST(ViewLabels, FoldersInsideFoldersAreShownAndSkippedFilesNamed) {
  const fs::path dir = temp_dir("nested");
  fs::create_directories(dir / "top" / "inner" / "deeper");
  const CubeLevels cube = constant_cube(4, 1, 0.25f);
  write_cubemap(cube, (dir / "top" / "a.ktx2").string(), CubeFormat::Ktx2);
  write_cubemap(cube, (dir / "top" / "inner" / "deeper" / "b.ktx2").string(), CubeFormat::Ktx2);
  std::ofstream(dir / "top" / "inner" / "notes.md") << "# notes\n";
  const ContactSheet s = render_contact_sheet({(dir / "top").string()});
  ASSERT_EQ(s.files.size(), 2u);
  EXPECT_NE(s.files[1].find("deeper/b.ktx2"), std::string::npos) << s.files[1];
  ASSERT_EQ(s.skipped.size(), 1u);
  EXPECT_NE(s.skipped[0].find("notes.md"), std::string::npos) << s.skipped[0];
  const CliRun cli = run_cli("view " + (dir / "top").string() + " -o " + (dir / "s.png").string());
  ASSERT_EQ(cli.code, 0) << cli.err;
  EXPECT_NE(cli.err.find("2 files"), std::string::npos) << cli.err;
  EXPECT_NE(cli.err.find("skipped " + (dir / "top" / "inner" / "notes.md").string()), std::string::npos) << cli.err;
}

// ---- Every output the tool writes, through the command line -----------------------------------

TEST(CliView, EveryOutputKindCanBeViewed) {
  const fs::path dir = temp_dir("every");
  std::ofstream(dir / "materials.json") << R"({"materials": [
      {"name": "gold", "model": "gltf", "baseColor": [1.0, 0.78, 0.34], "metallic": 1, "roughness": 0.3},
      {"name": "blue", "model": "gltf", "baseColor": [0.1, 0.2, 0.8], "metallic": 0, "roughness": 0.5}]})";
  {
    std::ofstream p(dir / "pairs.csv");
    p << "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n";
    for (int k = 0; k < 16; ++k) p << "0,0,1," << std::sin(k * 0.1) << ",0," << std::cos(k * 0.1) << "\n";
  }
  const std::string m = (dir / "materials.json").string(), pairs = (dir / "pairs.csv").string();
  // One job bakes one output of every kind and container: one process, one program cache.
  const std::string job = R"({"brdfbake_job": 1, "output_dir": ")" + (dir / "out").string() + R"(", "tables": [
    {"kind": "ggx", "size": 8, "output": "ggx.exr"},
    {"kind": "ggx", "size": 8, "output": "ggx.csv"},
    {"kind": "ggx", "size": 8, "output": "ggx.h"},
    {"kind": "ggx-multiscatter", "size": 8, "output": "ms.ktx2"},
    {"kind": "charlie", "size": 8, "output": "charlie.hdr"},
    {"kind": "fresnel", "model": "conductor", "material": "gold", "size": 16, "output": "gold.exr"},
    {"kind": "fresnel", "model": "schlick", "table": "2d", "size": 8, "output": "schlick.png"},
    {"kind": "thin-film", "film_ior": 1.3, "base_ior": 1.5, "size": 8, "output": "film.exr"},
    {"kind": "prefilter", "size": 8, "min_size": 4, "output": "p.ktx2"},
    {"kind": "prefilter", "size": 8, "min_size": 4, "output": "p.ktx"},
    {"kind": "prefilter", "size": 8, "min_size": 4, "output": "p.dds"},
    {"kind": "prefilter", "size": 8, "min_size": 4, "output": "pl.dds", "format": "dds-legacy"},
    {"kind": "prefilter", "size": 8, "min_size": 4, "output": "faces"},
    {"kind": "prefilter", "size": 8, "min_size": 4, "output": "cross", "layout": "cross", "image_format": "hdr"},
    {"kind": "prefilter", "size": 8, "min_size": 4, "output": "vcross", "layout": "vcross"},
    {"kind": "prefilter", "size": 8, "min_size": 4, "output": "equirect", "layout": "equirect"},
    {"kind": "irradiance", "output": "sh.json"},
    {"kind": "irradiance", "cube_size": 8, "output": "irr.ktx2"},
    {"kind": "eval", "material": ")" +
                          m + R"(", "name": "gold", "input": ")" + pairs + R"(", "output": "f.csv"},
    {"kind": "tabulate", "material": ")" +
                          m + R"(", "name": "gold", "layout": "merl", "output": "gold.binary"},
    {"kind": "tabulate", "material": ")" +
                          m + R"(", "name": "gold", "layout": "grid", "res": 4, "output": "grid.exr"},
    {"kind": "tabulate", "material": ")" +
                          m + R"(", "layout": "albedo", "res": 8, "output": "albedo.exr"},
    {"kind": "tabulate", "material": ")" +
                          m + R"(", "name": "gold", "layout": "slice", "res": 8, "output": "slice.exr"}]})";
  std::ofstream(dir / "job.json") << job;
  const CliRun baked = run_cli("run " + (dir / "job.json").string() + " --quiet");
  ASSERT_EQ(baked.code, 0) << baked.err;
  // Each file alone (sidecars stand for their files), then the folder: the manifest lists all.
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(dir / "out")) files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  std::string args;
  for (const auto& f : files) args += " " + f;
  const CliRun each = run_cli("view" + args + " -o " + (dir / "each.png").string());
  ASSERT_EQ(each.code, 0) << each.err;
  const CliRun all =
      run_cli("view " + (dir / "out").string() + " -o " + (dir / "all.png").string() + " --face-size 16");
  ASSERT_EQ(all.code, 0) << all.err;
  EXPECT_NE(all.err.find("23 files"), std::string::npos) << all.err;
  const io::PngImage png = io::read_png((dir / "all.png").string());
  EXPECT_EQ(png.channels, 3);
  EXPECT_EQ(png.bit_depth, 8);
  std::string listed;
  for (const auto& [k, v] : png.text)
    if (k == "brdfbake:files") listed = v;
  for (const char* f :
       {"ggx.exr", "ggx.csv",  "ggx.h", "ms.ktx2",     "charlie.hdr", "gold.exr",   "schlick.png", "film.exr",
        "p.ktx2",  "p.ktx",    "p.dds", "pl.dds",      "faces",       "cross",      "vcross",      "equirect",
        "sh.json", "irr.ktx2", "f.csv", "gold.binary", "grid.exr",    "albedo.exr", "slice.exr"})
    EXPECT_NE(listed.find(std::string("/out/") + f), std::string::npos) << f;
  // The float32 eval output (streamed by the command, not by a job).
  std::string bin;
  for (int k = 0; k < 4; ++k) {
    const float a = 0.2f * static_cast<float>(k);
    const float v[6] = {0, 0, 1, std::sin(a), 0, std::cos(a)};
    bin.append(reinterpret_cast<const char*>(v), sizeof v);
  }
  std::ofstream(dir / "pairs.f32", std::ios::binary) << bin;
  ASSERT_EQ(run_cli("eval --material " + m + " --name gold --binary -i " + (dir / "pairs.f32").string() + " -o " +
                    (dir / "f.f32").string() + " --quiet")
                .code,
            0);
  const CliRun f32 = run_cli("view " + (dir / "f.f32").string() + " -o " + (dir / "f32.png").string());
  EXPECT_EQ(f32.code, 0) << f32.err;
  EXPECT_NE(f32.err.find("1 file;"), std::string::npos) << f32.err;
}

TEST(CliView, BadUsageIsOneLineAndExitTwo) {
  const fs::path dir = temp_dir("cli-bad");
  const CliRun none = run_cli("view -o " + (dir / "s.png").string());
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.err.find("missing the files"), std::string::npos) << none.err;
  const CliRun missing = run_cli("view " + (dir / "nope.ktx2").string() + " -o " + (dir / "s.png").string());
  EXPECT_EQ(missing.code, 2);
  EXPECT_EQ(test::count_lines(missing.err), 1) << missing.err;
  EXPECT_NE(missing.err.find("no such file"), std::string::npos) << missing.err;
  const CliRun not_png = run_cli("view " + dir.string() + " -o " + (dir / "s.jpg").string());
  EXPECT_EQ(not_png.code, 2);
  EXPECT_NE(not_png.err.find(".png"), std::string::npos);
  const CliRun tonemap = run_cli("view " + dir.string() + " -o " + (dir / "s.png").string() + " --tonemap filmic");
  EXPECT_EQ(tonemap.code, 2);
  EXPECT_NE(tonemap.err.find("aces, reinhard or clamp"), std::string::npos) << tonemap.err;
  EXPECT_FALSE(fs::exists(dir / "s.png"));
}

// The preview sheet's numbers under each sphere of its error panel are drawn only where they fit
// between a sphere and the one below it (issue 34: at 384 x 192 they covered the next row). The
// pixels that the numbers alone change (two results that differ only in their statistics) are never
// inside a sphere, and at 384 x 192 there are none: the header says which --height holds them.
TEST(PreviewSheet, NumbersUnderTheSpheresNeverCoverASphere) {
  using namespace detail::preview;
  for (const auto& [w, h, drawn] : {std::tuple{512, 512, true}, std::tuple{384, 192, false}}) {
    PreviewSpec spec;
    spec.width = w;
    spec.height = h;
    const PreviewSpec resolved = resolve_spec(spec);
    const Layout layout = make_layout(resolved);
    auto result = [&](double error) {
      PreviewResult r;
      r.spec = resolved;
      r.spheres = layout.spheres;
      r.camera = layout.camera;
      for (PreviewImage* img : {&r.splitsum, &r.reference, &r.ideal}) {
        img->width = w;
        img->height = h;
        img->rgb.assign(3 * size_t(w) * size_t(h), 0.5f);
      }
      r.stats.resize(r.spheres.size());
      for (PreviewSphereStats& st : r.stats) {
        st.linear = {error, error, error};
        st.srgb8 = {10 * error, 100 * error, 100 * error};
        st.bake_share = {error / 2, error, error};
      }
      return r;
    };
    const ContactSheet a = preview_sheet(result(0.012), "t"), b = preview_sheet(result(0.876), "t");
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    // the error panel: the third panel, right of the first sphere region's panel by 2 (w + gap)
    std::vector<SheetRegion> spheres;
    for (const SheetRegion& r : a.regions)
      if (r.role == "sphere") spheres.push_back(r);
    ASSERT_EQ(spheres.size(), layout.spheres.size());
    const SheetRegion* panel = nullptr;
    for (const SheetRegion& r : a.regions)
      if (r.role == "error") panel = &r;
    int changed = 0, inside = 0;
    for (int y = 0; y < a.height; ++y)
      for (int x = 0; x < a.width; ++x) {
        const size_t at = 3 * (size_t(y) * size_t(a.width) + size_t(x));
        if (a.rgb[at] == b.rgb[at] && a.rgb[at + 1] == b.rgb[at + 1] && a.rgb[at + 2] == b.rgb[at + 2]) continue;
        ++changed;
        if (!panel) continue;
        for (const PreviewSphere& sp : layout.spheres) {
          const double dx = x + 0.5 - (panel->x + sp.centre_x), dy = y + 0.5 - (panel->y + sp.centre_y);
          if (dx * dx + dy * dy < sp.radius * sp.radius) ++inside;
        }
      }
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h));
    ASSERT_NE(panel, nullptr) << "no region for the error panel";
    EXPECT_EQ(changed > 0, drawn);
    EXPECT_EQ(inside, 0);
  }
}

}  // namespace
}  // namespace brdfbake
