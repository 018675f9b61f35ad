// Drawing the contact sheet: each file becomes a block of tiles (a cross per cube level, an image
// per table channel, a plot, spheres, slices), laid out left to right and wrapped at the sheet's
// width; blocks stack down the sheet under a header that states the tone map and the colour scale.
//
// Display rules (docs/VIEW.md):
// - a picture larger than its tile is box-filtered (the mean of the texels under each pixel, in
//   linear values, before any tone map or colour scale); a smaller one is magnified by repeating
//   texels, so that every texel stays visible as a block;
// - tables are drawn with x to the right and y upwards (row 0 at the bottom), the first and last
//   coordinates written at the ends of each axis;
// - a table channel maps its minimum to the left end of its colour scale and its maximum to the
//   right end, linearly, or over log10 when the values are positive and span more than three
//   decades (the scale then says "log10").
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include "brdfbake/error.hpp"
#include "brdfbake/error_figures.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/sh.hpp"
#include "brdfbake/version.hpp"
#include "brdfbake/view.hpp"
#include "enum_names.hpp"
#include "io/atomic_file.hpp"
#include "io/png_image.hpp"
#include "text.hpp"
#include "view/canvas.hpp"
#include "view/exposure.hpp"
#include "view/load.hpp"

namespace brdfbake {

namespace view {
namespace {

namespace fs = std::filesystem;
using brdfbake::math::kPi;
constexpr int kGap = 10;      // between tiles
constexpr int kMargin = 12;   // sheet border
constexpr int kCaption = 14;  // a caption line
constexpr int kMinTableWidth = 112;

std::string fmt(double v, const char* f = "%.3g") {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

using detail::split;  // text.hpp

std::string meta_of(const Metadata& m, const std::string& key) {
  for (const auto& [k, v] : m)
    if (k == key) return v;
  return "";
}

// A picture with the regions it holds (coordinates relative to its top-left corner).
struct Tile {
  Canvas canvas;
  std::vector<SheetRegion> regions;
};

void add_region(Tile& t, const std::string& role, const std::string& label, int x, int y, int w, int h, double lo = 0,
                double hi = 0, bool log_scale = false, double exposure = 0) {
  SheetRegion r;
  r.role = role;
  r.label = label;
  r.x = x;
  r.y = y;
  r.width = w;
  r.height = h;
  r.lo = lo;
  r.hi = hi;
  r.log_scale = log_scale;
  r.exposure = exposure;
  t.regions.push_back(r);
}

// The source texels under each display pixel: when shrinking an axis, every texel the pixel
// covers (a box filter); when magnifying it, the texel under the pixel's centre.
std::vector<std::pair<int, int>> footprints(int src, int dst) {
  std::vector<std::pair<int, int>> f(static_cast<size_t>(dst));
  for (int x = 0; x < dst; ++x) {
    if (dst >= src) {
      const int i = std::min(src - 1, static_cast<int>((x + 0.5) * src / dst));
      f[size_t(x)] = {i, i + 1};
    } else {
      const int i0 = static_cast<int>(std::floor(double(x) * src / dst));
      const int i1 = std::max(i0 + 1, static_cast<int>(std::ceil(double(x + 1) * src / dst)));
      f[size_t(x)] = {std::clamp(i0, 0, src - 1), std::clamp(i1, 1, src)};
    }
  }
  return f;
}

// A dw x dh picture of a sw x sh source: sample(i, j, acc) adds texel (i, j) to acc, put(x, y, mean)
// receives the mean of the pixel's footprint.
template <typename Sample, typename Put>
void resample(int sw, int sh, int dw, int dh, const Sample& sample, const Put& put, int channels) {
  const auto fx = footprints(sw, dw), fy = footprints(sh, dh);
  std::vector<double> acc(static_cast<size_t>(channels));
  for (int y = 0; y < dh; ++y)
    for (int x = 0; x < dw; ++x) {
      std::fill(acc.begin(), acc.end(), 0.0);
      const auto [x0, x1] = fx[size_t(x)];
      const auto [y0, y1] = fy[size_t(y)];
      for (int j = y0; j < y1; ++j)
        for (int i = x0; i < x1; ++i) sample(i, j, acc.data());
      const double n = double(x1 - x0) * double(y1 - y0);
      for (auto& a : acc) a /= n;
      put(x, y, acc.data());
    }
}

// ---- Exposure ------------------------------------------------------------------------------------

// The options a picture of radiance is drawn with: the exposure asked for, else the picture's own
// (view/exposure.hpp) from its texels (`stride` floats apart).
ViewOptions exposed(const ViewOptions& o, const float* rgb, size_t texels, size_t stride) {
  ViewOptions p = o;
  if (!p.exposure) p.exposure = auto_exposure(rgb, texels, stride);
  return p;
}

std::string ev_text(const ViewOptions& o) { return fmt(*o.exposure, "%+.1f") + " EV"; }

// ---- Cubes ---------------------------------------------------------------------------------------

// Where each face goes in the horizontal cross (docs/CONVENTIONS.md): -X +Z +X -Z in the middle
// row, +Y above +Z, -Y below it.
struct CrossCell {
  int col, row;
};
constexpr CrossCell kCross[6] = {{2, 1}, {0, 1}, {1, 0}, {1, 2}, {1, 1}, {3, 1}};

std::vector<double> level_roughness(const CubeLevels& cube) {
  std::vector<double> r;
  const std::string list = cube.meta("roughness_per_level");
  if (list.empty()) return r;
  for (const auto& s : split(list, ',')) r.push_back(std::atof(s.c_str()));
  if (static_cast<int>(r.size()) != cube.level_count()) r.clear();
  return r;
}

std::vector<Tile> cube_tiles(const CubeLevels& cube, const ViewOptions& o) {
  std::vector<Tile> tiles;
  const std::vector<double> roughness = level_roughness(cube);
  const int f = std::max(4, o.face_size);
  for (int l = 0; l < cube.level_count(); ++l) {
    Tile t;
    t.canvas = Canvas(4 * f, 3 * f + 2 * kCaption, kBackground);
    t.canvas.fill_rect(0, 0, 4 * f, 3 * f, kPanel);
    const int s = cube.level_size(l);
    const ViewOptions lo = exposed(o, cube.levels[size_t(l)].data(), 6 * size_t(s) * size_t(s), 4);
    for (int face = 0; face < 6; ++face) {
      const int ox = kCross[face].col * f, oy = kCross[face].row * f;
      resample(
          s, s, f, f,
          [&](int i, int j, double* acc) {
            const float* p = cube.texel(l, face, i, j);
            for (int c = 0; c < 3; ++c) acc[c] += double(p[c]);
          },
          [&](int x, int y, const double* v) {
            const float rgb[3] = {float(v[0]), float(v[1]), float(v[2])};
            t.canvas.set(ox + x, oy + y, tone_map(rgb, lo));
          },
          3);
    }
    std::string label = "level " + std::to_string(l) + ": " + std::to_string(s) + "^2, " + ev_text(lo);
    std::string second;
    if (!roughness.empty())
      second = "roughness " + fmt(roughness[size_t(l)], "%.3f");
    else if (cube.meta("kind") == "irradiance")
      second = "E / pi";
    t.canvas.text(2, 3 * f + 2, label);
    if (!second.empty()) t.canvas.text(2, 3 * f + 2 + 12, second, kDim);
    add_region(t, "cube level", "level " + std::to_string(l), 0, 0, 4 * f, 3 * f, 0, 0, false, *lo.exposure);
    tiles.push_back(std::move(t));
  }
  return tiles;
}

// ---- Tables --------------------------------------------------------------------------------------

struct Range {
  double lo = 0, hi = 0;
  bool log_scale = false;
};

// The colour scale of a channel: linear from its minimum to its maximum, or log10 when the values
// are not negative and a linear scale would paint most of them one dark colour: a few texels dwarf
// the rest (the maximum above 5 times the 99th percentile, or above 1000 times the median: a
// grazing peak, a specular spike), or more than half the texels would fall in the darkest tenth of
// the scale (the median below a tenth of the range: the 32^2 Charlie table, whose grazing texels
// reach 3.2 over a median of 0.19). A log scale spans at most four decades below the maximum;
// values at or below its left end (zeros included) take the left end's colour.
Range channel_range(const Table& t, int c) {
  std::vector<double> v;
  for (size_t k = static_cast<size_t>(c); k < t.data.size(); k += t.channels.size())
    if (std::isfinite(t.data[k])) v.push_back(double(t.data[k]));
  Range r;
  if (v.empty()) return r;
  std::sort(v.begin(), v.end());
  r.lo = v.front();
  r.hi = v.back();
  const double p99 = v[(v.size() - 1) * 99 / 100], median = v[(v.size() - 1) / 2];
  const bool dark = median - r.lo < 0.1 * (r.hi - r.lo);
  if (r.lo >= 0 && r.hi > 0 && (r.hi > 5 * p99 || r.hi > 1e3 * median || dark)) {
    const auto first_positive = std::upper_bound(v.begin(), v.end(), 0.0);
    r.log_scale = true;
    r.hi = std::log10(v.back());
    r.lo = std::max(std::log10(*first_positive), r.hi - 4.0);
  }
  return r;
}

// A value for a scale's label: 3 significant digits, without an exponent between 1e-4 and 1e5.
std::string value_label(double v) {
  const double a = std::fabs(v);
  if (a != 0 && (a < 1e-4 || a >= 1e5)) return fmt(v, "%.2e");
  return fmt(v, "%.4g");
}

// The labels under a colour scale of `width` pixels at x: its ends as values (a log scale's too,
// not as exponents), and on a log scale a tick and a label at each decade inside it where there is
// room ("0.01", "1", "1e+06").
void scale_labels(Tile& t, int x, int y, int width, const Range& r, const char* log_name) {
  const std::string lo = value_label(r.log_scale ? std::pow(10.0, r.lo) : r.lo);
  const std::string hi = value_label(r.log_scale ? std::pow(10.0, r.hi) : r.hi);
  t.canvas.text(x, y, lo, kAxis);
  t.canvas.text(x + width - text_width(hi), y, hi, kAxis);
  if (!r.log_scale || !(r.hi > r.lo)) return;
  int free_from = x + text_width(lo) + 6;
  const int free_to = x + width - text_width(hi) - 6;
  bool labelled = false;
  for (double d = std::ceil(r.lo); d <= std::floor(r.hi); d += 1.0) {
    const int at = x + static_cast<int>(std::lround((d - r.lo) / (r.hi - r.lo) * (width - 1)));
    t.canvas.fill_rect(at, y - 3, 1, 3, kAxis);
    const std::string label = value_label(std::pow(10.0, d));
    const int lx = at - text_width(label) / 2;
    if (lx >= free_from && lx + text_width(label) <= free_to) {
      t.canvas.text(lx, y, label, kDim);
      free_from = lx + text_width(label) + 6;
      labelled = true;
    }
  }
  const std::string name = std::string(log_name) + ", decades marked";
  t.canvas.text(x + (width - text_width(name)) / 2, y + kCaption - 2, labelled ? name : std::string(log_name), kDim);
}

double scale_position(double v, const Range& r) {
  const double x = r.log_scale ? (v > 0 ? std::log10(v) : r.lo) : v;
  return r.hi > r.lo ? (x - r.lo) / (r.hi - r.lo) : 0.0;
}

// The display size of a w x h table: longer side `size`, aspect kept within 1:4.
void display_size(int w, int h, int size, int* dw, int* dh) {
  const double aspect = std::clamp(double(w) / double(h), 0.25, 4.0);
  if (aspect >= 1) {
    *dw = size;
    *dh = std::max(1, static_cast<int>(std::lround(size / aspect)));
  } else {
    *dh = size;
    *dw = std::max(1, static_cast<int>(std::lround(size * aspect)));
  }
  *dw = std::max(*dw, kMinTableWidth);  // room for the axis and scale labels
}

bool monotonic(const std::vector<double>& v) {
  for (size_t k = 1; k < v.size(); ++k)
    if (!(v[k] > v[k - 1])) return false;
  return true;
}

// Axis labels: the first and last coordinates at the ends, the name between them.
void x_axis_labels(Tile& t, int x, int y, int w, const std::string& name, const std::vector<double>& values) {
  const bool known = !values.empty() && monotonic(values);
  const std::string lo = known ? fmt(values.front()) : "", hi = known ? fmt(values.back()) : "";
  t.canvas.text(x, y, lo, kAxis);
  t.canvas.text(x + w - text_width(hi), y, hi, kAxis);
  const std::string n = name.empty() ? "x" : name;
  const int lo_w = text_width(lo) + 6, hi_w = text_width(hi) + 6;
  int nx = x + (w - text_width(n)) / 2;
  nx = std::max(nx, x + lo_w);
  if (nx + text_width(n) > x + w - hi_w) nx = x + lo_w;
  t.canvas.text(nx, y, n, kDim);
}

// The name of each row when the table's rows are materials (tabulate's albedo layout records them
// in material_names), else nothing.
std::vector<std::string> row_names(const Table& t) {
  const std::vector<std::string> names = split(t.meta("material_names"), ',');
  return static_cast<int>(names.size()) == t.height ? names : std::vector<std::string>{};
}

Tile table_channel_tile(const Table& t, int c, const ViewOptions& o) {
  int dw = 0, dh = 0;
  display_size(t.width, t.height, o.table_size, &dw, &dh);
  const Range r = channel_range(t, c);
  const std::vector<std::string> rows = row_names(t);
  const bool named_rows = !rows.empty() && dh / t.height >= 9;  // a line of text a row
  const std::string y_lo = !named_rows && !t.y.empty() && monotonic(t.y) ? fmt(t.y.front()) : "";
  const std::string y_hi = !named_rows && !t.y.empty() && monotonic(t.y) ? fmt(t.y.back()) : "";
  int names_w = 0;
  if (named_rows)
    for (const auto& n : rows) names_w = std::max(names_w, text_width(n));
  const int left = std::max({text_width(y_lo), text_width(y_hi), names_w, 18}) + 4;
  const int top = kCaption + 12;  // channel name, then the y axis name
  const int bar_h = 8;
  const int width = left + std::max(dw, 120) + 4;
  const int height = top + dh + 4 + 12 + 6 + bar_h + 2 + 12 + (r.log_scale ? kCaption : 0);
  Tile tile;
  tile.canvas = Canvas(width, height, kBackground);
  tile.canvas.text(left, 1, t.channels[size_t(c)], kText);
  tile.canvas.text(2, kCaption, "^ " + (t.y_name.empty() ? std::string("y") : t.y_name), kDim);
  // The image, row 0 at the bottom.
  resample(
      t.width, t.height, dw, dh, [&](int i, int j, double* acc) { acc[0] += double(t.at(i, t.height - 1 - j, c)); },
      [&](int x, int y, const double* v) { tile.canvas.set(left + x, top + y, cubehelix(scale_position(v[0], r))); },
      1);
  add_region(tile, "table channel", t.channels[size_t(c)], left, top, dw, dh, r.lo, r.hi, r.log_scale);
  tile.canvas.text(1, top, y_hi, kAxis);
  tile.canvas.text(1, top + dh - 9, y_lo, kAxis);
  if (named_rows)  // row j's name beside its band (row 0 at the bottom)
    for (int j = 0; j < t.height; ++j) {
      const int band_top = top + (t.height - 1 - j) * dh / t.height, band_h = dh / t.height;
      tile.canvas.text(left - 4 - text_width(rows[size_t(j)]), band_top + (band_h - 8) / 2, rows[size_t(j)], kAxis);
    }
  x_axis_labels(tile, left, top + dh + 3, dw, t.x_name, t.x);
  // The colour scale: its left end is the minimum, its right end the maximum.
  const int by = top + dh + 4 + 12 + 4;
  for (int x = 0; x < dw; ++x) {
    const Rgb8 col = cubehelix(dw > 1 ? double(x) / double(dw - 1) : 0.0);
    tile.canvas.fill_rect(left + x, by, 1, bar_h, col);
  }
  add_region(tile, "colour scale", t.channels[size_t(c)], left, by, dw, bar_h, r.lo, r.hi, r.log_scale);
  scale_labels(tile, left, by + bar_h + 2, dw, r, "log10");
  return tile;
}

int channel_index(const Table& t, const char* a, const char* b) {
  for (size_t c = 0; c < t.channels.size(); ++c)
    if (t.channels[c] == a || t.channels[c] == b) return static_cast<int>(c);
  return -1;
}

// r, g, b channels shown as the colour they are (reflectances: linear, clamped to [0, 1], sRGB).
Tile table_rgb_tile(const Table& t, int cr, int cg, int cb, const ViewOptions& o) {
  int dw = 0, dh = 0;
  display_size(t.width, t.height, o.table_size, &dw, &dh);
  Tile tile;
  const int top = kCaption + 12;
  tile.canvas =
      Canvas(std::max(dw + 8, text_width("linear, clamped to [0, 1]") + 8), top + dh + 2 + 2 * kCaption, kBackground);
  tile.canvas.text(4, 1, "r, g, b as colour", kText);
  resample(
      t.width, t.height, dw, dh,
      [&](int i, int j, double* acc) {
        acc[0] += double(t.at(i, t.height - 1 - j, cr));
        acc[1] += double(t.at(i, t.height - 1 - j, cg));
        acc[2] += double(t.at(i, t.height - 1 - j, cb));
      },
      [&](int x, int y, const double* v) {
        tile.canvas.set(4 + x, top + y, {srgb8(v[0]), srgb8(v[1]), srgb8(v[2])});
      },
      3);
  add_region(tile, "table rgb", "rgb", 4, top, dw, dh);
  tile.canvas.text(4, top + dh + 3, "linear, clamped to [0, 1]", kDim);
  return tile;
}

// A 1-D table: every channel against x.
Tile plot_tile(const Table& t, const std::string& title) {
  const int pw = 320, ph = 140, left = 44, top = kCaption + 4;
  Tile tile;
  const int legend_h = kCaption * static_cast<int>((t.channels.size() + 3) / 4);
  tile.canvas = Canvas(left + pw + 10, top + ph + 16 + legend_h + 4, kBackground);
  tile.canvas.text(left, 1, title, kText);
  double lo = INFINITY, hi = -INFINITY;
  for (float v : t.data)
    if (std::isfinite(v)) {
      lo = std::min(lo, double(v));
      hi = std::max(hi, double(v));
    }
  if (!(lo <= hi)) lo = hi = 0;
  if (hi == lo) {
    hi += 0.5;
    lo -= 0.5;
  }
  tile.canvas.fill_rect(left, top, pw, ph, kPanel);
  tile.canvas.outline_rect(left - 1, top - 1, pw + 2, ph + 2, kAxis);
  const int n = t.width;
  const int nc = t.channel_count();
  for (int c = 0; c < nc; ++c) {
    const Rgb8 col = series_colour(t.channels[size_t(c)], c);
    auto py = [&](double v) { return top + ph - 1 - (v - lo) / (hi - lo) * (ph - 1); };
    if (n <= pw) {
      for (int i = 0; i + 1 < n; ++i)
        tile.canvas.line(left + double(i) / std::max(1, n - 1) * (pw - 1), py(t.at(i, 0, c)),
                         left + double(i + 1) / std::max(1, n - 1) * (pw - 1), py(t.at(i + 1, 0, c)), col);
      if (n == 1) tile.canvas.set(left, static_cast<int>(py(t.at(0, 0, c))), col);
    } else {  // more points than pixels: the range of each pixel column
      for (int x = 0; x < pw; ++x) {
        const int i0 = static_cast<int>(double(x) * n / pw),
                  i1 = std::max(i0 + 1, static_cast<int>(double(x + 1) * n / pw));
        double a = INFINITY, b = -INFINITY;
        for (int i = i0; i < i1 && i < n; ++i) {
          a = std::min(a, double(t.at(i, 0, c)));
          b = std::max(b, double(t.at(i, 0, c)));
        }
        tile.canvas.line(left + x, py(a), left + x, py(b), col);
      }
    }
  }
  add_region(tile, "plot", title, left, top, pw, ph, lo, hi);
  tile.canvas.text(2, top, fmt(hi), kAxis);
  tile.canvas.text(2, top + ph - 9, fmt(lo), kAxis);
  x_axis_labels(tile, left, top + ph + 3, pw, t.x_name, t.x);
  int lx = left, ly = top + ph + 16;
  for (int c = 0; c < nc; ++c) {
    const Rgb8 col = series_colour(t.channels[size_t(c)], c);
    if (lx + 80 > left + pw) {
      lx = left;
      ly += kCaption;
    }
    tile.canvas.fill_rect(lx, ly + 3, 10, 3, col);
    tile.canvas.text(lx + 14, ly, t.channels[size_t(c)], kText);
    lx += 20 + std::max(60, text_width(t.channels[size_t(c)]) + 10);
  }
  return tile;
}

std::vector<Tile> table_tiles(const Table& t, const ViewOptions& o) {
  std::vector<Tile> tiles;
  if (t.height == 1) {
    tiles.push_back(plot_tile(t, t.channels.size() == 1 ? t.channels[0] : "channels against " + t.x_name));
    return tiles;
  }
  for (int c = 0; c < t.channel_count(); ++c) tiles.push_back(table_channel_tile(t, c, o));
  // r, g, b reflectances (at most 1: Fresnel, thin film, albedo) are also shown as the colour they are.
  const int r = channel_index(t, "r", "R"), g = channel_index(t, "g", "G"), b = channel_index(t, "b", "B");
  const bool reflectance = std::all_of(t.data.begin(), t.data.end(), [](float v) { return !(v > 1.0f); });
  if (r >= 0 && g >= 0 && b >= 0 && t.channel_count() <= 4 && reflectance)
    tiles.push_back(table_rgb_tile(t, r, g, b, o));
  return tiles;
}

// ---- Spherical harmonics -------------------------------------------------------------------------

std::array<double, 3> sh_eval(const std::vector<double>& coeffs, int order, const Vec3& d) {
  const std::vector<double> y = math::sh_basis(order, d);
  std::array<double, 3> v = {0, 0, 0};
  for (size_t k = 0; k < y.size(); ++k)
    for (size_t c = 0; c < 3; ++c) v[c] += coeffs[3 * k + c] * y[k];
  return v;
}

std::vector<Tile> sh_tiles(const ShView& sh, const ViewOptions& o) {
  std::vector<Tile> tiles;
  // Two spheres: seen from +Z and from -Z (orthographic, +Y up), each pixel E(n) / pi at its normal:
  // the radiance a white Lambertian sphere reflects.
  const int d = 128;
  // E(n) / pi at each pixel's normal, both spheres, then one exposure for the pair.
  std::vector<float> values(2 * size_t(d) * size_t(d) * 3, 0.0f);
  std::vector<float> inside;
  for (int view_index = 0; view_index < 2; ++view_index) {
    const double sign = view_index == 0 ? 1.0 : -1.0;
    for (int y = 0; y < d; ++y)
      for (int x = 0; x < d; ++x) {
        const double u = (x + 0.5) / d * 2 - 1, v = 1 - (y + 0.5) / d * 2;
        const double r2 = u * u + v * v;
        if (r2 > 1) continue;
        const Vec3 n = {sign * u, v, sign * std::sqrt(1 - r2)};
        const auto e = sh_eval(sh.irradiance_over_pi, sh.order, n);
        float* out = &values[3 * ((size_t(view_index) * size_t(d) + size_t(y)) * size_t(d) + size_t(x))];
        for (int c = 0; c < 3; ++c) {
          out[c] = float(e[size_t(c)]);
          inside.push_back(out[c]);
        }
      }
  }
  const ViewOptions so = exposed(o, inside.data(), inside.size() / 3, 3);
  Tile spheres;
  spheres.canvas = Canvas(2 * d + kGap, d + 2 * kCaption + 4, kBackground);
  spheres.canvas.text(0, 1, "E(n) / pi on a white sphere, " + ev_text(so), kText);
  for (int view_index = 0; view_index < 2; ++view_index) {
    const int ox = view_index * (d + kGap), oy = kCaption + 2;
    for (int y = 0; y < d; ++y)
      for (int x = 0; x < d; ++x) {
        const double u = (x + 0.5) / d * 2 - 1, v = 1 - (y + 0.5) / d * 2;
        if (u * u + v * v > 1) continue;  // outside the disc
        const float* rgb = &values[3 * ((size_t(view_index) * size_t(d) + size_t(y)) * size_t(d) + size_t(x))];
        spheres.canvas.set(ox + x, oy + y, tone_map(rgb, so));
      }
    add_region(spheres, "sphere", view_index == 0 ? "seen from +Z" : "seen from -Z", ox, oy, d, d, 0, 0, false,
               *so.exposure);
    spheres.canvas.text(ox, oy + d + 2, view_index == 0 ? "from +Z" : "from -Z", kDim);
  }
  tiles.push_back(std::move(spheres));

  // Bands: sqrt(sum_m c_lm^2) per band and channel, for E / pi.
  Tile bands;
  const int pw = 40 * sh.order + 20, ph = 110, left = 44, top = kCaption + 4;
  bands.canvas = Canvas(left + pw + 10, top + ph + 2 * kCaption + 4, kBackground);
  bands.canvas.text(left, 1, "E / pi: |c_l| per band", kText);
  std::vector<std::array<double, 3>> norm(static_cast<size_t>(sh.order), {0, 0, 0});
  double hi = 0;
  for (int l = 0; l < sh.order; ++l) {
    for (int m = -l; m <= l; ++m)
      for (size_t c = 0; c < 3; ++c) {
        const double v = sh.irradiance_over_pi[3 * size_t(l * (l + 1) + m) + c];
        norm[size_t(l)][c] += v * v;
      }
    for (size_t c = 0; c < 3; ++c) {
      norm[size_t(l)][c] = std::sqrt(norm[size_t(l)][c]);
      hi = std::max(hi, norm[size_t(l)][c]);
    }
  }
  if (!(hi > 0)) hi = 1;
  bands.canvas.fill_rect(left, top, pw, ph, kPanel);
  bands.canvas.outline_rect(left - 1, top - 1, pw + 2, ph + 2, kAxis);
  static const char* const kRgb[3] = {"r", "g", "b"};
  for (int l = 0; l < sh.order; ++l) {
    for (int c = 0; c < 3; ++c) {
      const int bh = static_cast<int>(std::lround(norm[size_t(l)][size_t(c)] / hi * (ph - 2)));
      bands.canvas.fill_rect(left + 12 + 40 * l + 8 * c, top + ph - 1 - bh, 7, bh, series_colour(kRgb[c], c));
    }
    bands.canvas.text(left + 14 + 40 * l, top + ph + 3, "l=" + std::to_string(l), kAxis);
  }
  bands.canvas.text(2, top, fmt(hi), kAxis);
  bands.canvas.text(2, top + ph - 9, "0", kAxis);
  add_region(bands, "band plot", "bands", left, top, pw, ph, 0.0, hi);
  tiles.push_back(std::move(bands));
  return tiles;
}

// ---- MERL ----------------------------------------------------------------------------------------

std::vector<Tile> merl_tiles(const MerlTable& m) {
  std::vector<Tile> tiles;
  // Slices over (theta_h bin i, theta_d bin j) at three phi_d bins, luminance of f on a log10
  // scale shared by the slices.
  const int ks[3] = {45, 90, 135};
  auto lum = [&](int i, int j, int k) {
    const size_t b = (size_t(i) * kMerlThetaD + size_t(j)) * kMerlPhiD + size_t(k);
    const double r = m.values[b], g = m.values[kMerlBins + b], bl = m.values[2 * kMerlBins + b];
    if (r < 0 || g < 0 || bl < 0) return -1.0;
    return 0.2126 * r + 0.7152 * g + 0.0722 * bl;
  };
  double lo = INFINITY, hi = -INFINITY;
  for (int k : ks)
    for (int i = 0; i < kMerlThetaH; ++i)
      for (int j = 0; j < kMerlThetaD; ++j) {
        const double v = lum(i, j, k);
        if (v > 0) {
          lo = std::min(lo, std::log10(v));
          hi = std::max(hi, std::log10(v));
        }
      }
  if (!(lo <= hi)) lo = hi = 0;
  lo = std::max(lo, hi - 6.0);  // six decades below the peak are enough to see the lobe's shape
  Range r{lo, hi, true};
  const int z = 2, left = 18, top = kCaption + 12;
  for (int s = 0; s < 3; ++s) {
    const int k = ks[s];
    Tile t;
    t.canvas =
        Canvas(left + z * kMerlThetaH + 6, top + z * kMerlThetaD + 4 + 12 + 6 + 8 + 2 + 12 + kCaption, kBackground);
    const std::string label = "phi_d = " + fmt((k + 0.5) / 180.0 * 180.0, "%.1f") + " deg";
    t.canvas.text(left, 1, label, kText);
    t.canvas.text(2, kCaption, "^ theta_d", kDim);
    for (int j = 0; j < kMerlThetaD; ++j)
      for (int i = 0; i < kMerlThetaH; ++i) {
        const double v = lum(i, j, k);
        const Rgb8 c = v < 0 ? kNoData : cubehelix(v > 0 ? (std::log10(v) - r.lo) / std::max(r.hi - r.lo, 1e-12) : 0.0);
        t.canvas.fill_rect(left + z * i, top + z * (kMerlThetaD - 1 - j), z, z, c);
      }
    add_region(t, "merl slice", label, left, top, z * kMerlThetaH, z * kMerlThetaD, r.lo, r.hi, true);
    t.canvas.text(1, top, "90", kAxis);
    t.canvas.text(1, top + z * kMerlThetaD - 9, "0", kAxis);
    const std::vector<double> th = {0.0, 90.0};
    x_axis_labels(t, left, top + z * kMerlThetaD + 3, z * kMerlThetaH, "theta_h (sqrt bins)", th);
    const int by = top + z * kMerlThetaD + 4 + 12 + 4;
    for (int x = 0; x < z * kMerlThetaH; ++x)
      t.canvas.fill_rect(left + x, by, 1, 8, cubehelix(double(x) / (z * kMerlThetaH - 1)));
    add_region(t, "colour scale", label, left, by, z * kMerlThetaH, 8, r.lo, r.hi, true);
    scale_labels(t, left, by + 10, z * kMerlThetaH, r, "log10 luminance");
    tiles.push_back(std::move(t));
  }
  return tiles;
}

// ---- HDR images ----------------------------------------------------------------------------------

Tile hdr_tile(const HdrImage& im, const ViewOptions& o) {
  int dw = 0, dh = 0;
  display_size(im.width, im.height, 2 * o.table_size, &dw, &dh);
  Tile t;
  t.canvas = Canvas(std::max(dw, 160), dh + kCaption, kBackground);
  const ViewOptions io = im.display_referred ? o : exposed(o, im.rgb.data(), im.rgb.size() / 3, 3);
  resample(
      im.width, im.height, dw, dh,
      [&](int i, int j, double* acc) {
        const float* p = &im.rgb[3 * (size_t(j) * size_t(im.width) + size_t(i))];
        for (int c = 0; c < 3; ++c) acc[c] += double(p[c]);
      },
      [&](int x, int y, const double* v) {
        const float rgb[3] = {float(v[0]), float(v[1]), float(v[2])};
        if (im.display_referred)  // stored sRGB values, shown as they are
          t.canvas.set(x, y,
                       {uint8_t(std::lround(std::clamp(v[0], 0.0, 1.0) * 255)),
                        uint8_t(std::lround(std::clamp(v[1], 0.0, 1.0) * 255)),
                        uint8_t(std::lround(std::clamp(v[2], 0.0, 1.0) * 255))});
        else
          t.canvas.set(x, y, tone_map(rgb, io));
      },
      3);
  add_region(t, "image", "image", 0, 0, dw, dh, 0, 0, false, io.exposure.value_or(0.0));
  t.canvas.text(0, dh + 2,
                std::to_string(im.width) + "x" + std::to_string(im.height) +
                    (im.display_referred ? ", as stored (sRGB)" : ", " + ev_text(io)),
                kDim);
  return t;
}

// ---- Pictures drawn already (a preview's sheet) ---------------------------------------------------

// As it is where it fits the sheet's width, else scaled down (a box filter on the sRGB values).
Tile picture_tile(const Picture& p, int width) {
  const int dw = std::min(p.width, width);
  const int dh = std::max(1, int(std::lround(double(p.height) * dw / p.width)));
  Tile t;
  t.canvas = Canvas(dw, dh, kBackground);
  resample(
      p.width, p.height, dw, dh,
      [&](int i, int j, double* acc) {
        const uint8_t* q = &p.rgb[3 * (size_t(j) * size_t(p.width) + size_t(i))];
        for (int c = 0; c < 3; ++c) acc[c] += double(q[c]);
      },
      [&](int x, int y, const double* v) {
        Rgb8 c;
        for (int k = 0; k < 3; ++k) c[size_t(k)] = uint8_t(std::clamp(std::lround(v[k]), 0L, 255L));
        t.canvas.set(x, y, c);
      },
      3);
  add_region(t, "preview sheet", "preview", 0, 0, dw, dh);
  return t;
}

// ---- Blocks and the sheet ------------------------------------------------------------------------

// What a file's title line says beside its name and kind.
std::string facts(const Item& it) {
  std::vector<std::string> f;
  auto add = [&](const std::string& key, const std::string& value) {
    if (!value.empty()) f.push_back(key.empty() ? value : key + " " + value);
  };
  const Metadata* meta = nullptr;
  if (const auto* t = std::get_if<Table>(&it.content)) {
    meta = &t->metadata;
    f.push_back(std::to_string(t->width) + "x" + std::to_string(t->height));
  } else if (const auto* c = std::get_if<CubeLevels>(&it.content)) {
    meta = &c->metadata;
    f.push_back(std::to_string(c->size) + "^2, " + std::to_string(c->level_count()) +
                (c->level_count() == 1 ? " level" : " levels"));
    add("schedule", c->meta("roughness_schedule"));
    add("", c->meta("lod_from_roughness"));
  } else if (const auto* s = std::get_if<ShView>(&it.content)) {
    meta = &s->metadata;
    f.push_back("order " + std::to_string(s->order));
    add("window", s->window);
  } else if (const auto* m = std::get_if<MerlTable>(&it.content)) {
    meta = &m->metadata;
  } else if (const auto* p = std::get_if<Picture>(&it.content)) {
    f.push_back(p->caption);
  }
  if (meta) {
    add("kind", meta_of(*meta, "kind"));
    add("model", meta_of(*meta, "model"));
    add("distribution", meta_of(*meta, "distribution"));
    // the error figure under its kind's name (error_bound in older files)
    if (const auto figure = error_figure_value(*meta)) add(figure->first, figure->second);
    add("precision", meta_of(*meta, "precision"));
  }
  for (const auto& [k, v] : it.notes)
    if (k == "runtime") add("runtime:", v);
  std::string s;
  for (const auto& x : f) s += (s.empty() ? "" : ", ") + x;
  return s;
}

struct Block {
  Canvas canvas;
  std::vector<SheetRegion> regions;
};

// Tiles left to right under a title, wrapped at `width`.
Block layout_block(const std::string& title, const std::string& subtitle, std::vector<Tile> tiles, int width,
                   const std::string& file) {
  int x = 0, y = 2 * kCaption + 4, row_h = 0, used_w = 0;
  struct Placed {
    int x, y;
  };
  std::vector<Placed> at;
  for (const Tile& t : tiles) {
    if (x > 0 && x + t.canvas.width() > width) {
      x = 0;
      y += row_h + kGap;
      row_h = 0;
    }
    at.push_back({x, y});
    x += t.canvas.width() + kGap;
    used_w = std::max(used_w, x - kGap);
    row_h = std::max(row_h, t.canvas.height());
  }
  Block b;
  const int title_w = std::max(text_width(title), text_width(subtitle));
  b.canvas = Canvas(std::min(width, std::max(used_w, title_w)), y + row_h, kBackground);
  b.canvas.text(0, 0, title, kText);
  b.canvas.text(0, kCaption, subtitle, kDim);
  SheetRegion r;
  r.file = file;
  r.role = "file title";
  r.label = title;
  r.width = text_width(title);
  r.height = 2 * kCaption;
  b.regions.push_back(r);
  for (size_t k = 0; k < tiles.size(); ++k) {
    b.canvas.blit(tiles[k].canvas, at[k].x, at[k].y);
    for (SheetRegion reg : tiles[k].regions) {
      reg.file = file;
      reg.x += at[k].x;
      reg.y += at[k].y;
      b.regions.push_back(reg);
    }
  }
  return b;
}

// A file as the sheet names it: its path, or relative to options.relative_to (the server names a
// job's file as the job's folder does, not by where the server keeps it).
std::string shown_name(const std::string& path, const ViewOptions& o) {
  if (o.relative_to.empty()) return path;
  const std::string rel = std::filesystem::path(path).lexically_relative(o.relative_to).generic_string();
  return !rel.empty() && rel.rfind("..", 0) != 0 ? rel : path;
}

Block item_block(const Item& it, const ViewOptions& o, int width) {
  std::vector<Tile> tiles;
  std::string subtitle = facts(it);
  if (const auto* t = std::get_if<Table>(&it.content)) {
    tiles = table_tiles(*t, o);
  } else if (const auto* c = std::get_if<CubeLevels>(&it.content)) {
    tiles = cube_tiles(*c, o);
    subtitle += (subtitle.empty() ? "" : "; ") + std::string("cross: -X +Z +X -Z, +Y above, -Y below");
    if (it.irradiance) {  // an engine file's irradiance, beside its chain
      for (Tile& sh : sh_tiles(*it.irradiance, o)) tiles.push_back(std::move(sh));
      subtitle += "; irradiance: " + meta_of(it.irradiance->metadata, "sh_convention");
    }
  } else if (const auto* s = std::get_if<ShView>(&it.content)) {
    tiles = sh_tiles(*s, o);
  } else if (const auto* m = std::get_if<MerlTable>(&it.content)) {
    tiles = merl_tiles(*m);
  } else if (const auto* h = std::get_if<HdrImage>(&it.content)) {
    tiles.push_back(hdr_tile(*h, o));
  } else if (const auto* p = std::get_if<Picture>(&it.content)) {
    tiles.push_back(picture_tile(*p, width));
  }
  return layout_block(shown_name(it.path, o) + "  (" + it.kind + ")", subtitle, std::move(tiles), width, it.path);
}

// Every file to show, in order: manifests and folders expand to what they list.
void collect(const std::string& given, std::vector<Item>& items, std::set<std::string>& seen, const Metadata& notes,
             int depth, std::vector<std::string>& skipped) {
  std::error_code ec;
  // A sidecar (FILE.json beside FILE) stands for its file.
  std::string path = given;
  if (path.size() > 5 && path.compare(path.size() - 5, 5, ".json") == 0 &&
      fs::is_regular_file(path.substr(0, path.size() - 5), ec))
    path = path.substr(0, path.size() - 5);
  const std::string key = fs::weakly_canonical(path, ec).string();
  if (seen.count(key)) return;
  seen.insert(key);
  Item it = load(path);
  if (auto* list = std::get_if<FileList>(&it.content)) {
    if (depth > 4) throw Error("cannot view '" + path + "': manifests nested too deep");
    for (auto& s : list->skipped) skipped.push_back(std::move(s));
    for (size_t k = 0; k < list->paths.size(); ++k)
      collect(list->paths[k], items, seen, list->notes[k], depth + 1, skipped);
    return;
  }
  it.notes = notes;
  items.push_back(std::move(it));
}

}  // namespace
}  // namespace view

namespace {
constexpr detail::EnumName<ToneMap> kToneMapNames[] = {
    {ToneMap::Aces, "aces"}, {ToneMap::Reinhard, "reinhard"}, {ToneMap::Clamp, "clamp"}};
}  // namespace

ToneMap tone_map_from_name(const std::string& name) { return detail::enum_from_name(kToneMapNames, name, "tone map"); }

const char* tone_map_name(ToneMap m) { return detail::enum_name(kToneMapNames, m); }

std::string view_kind(const std::string& path) { return view::load(path).kind; }

ContactSheet render_contact_sheet(const std::vector<std::string>& paths, const ViewOptions& o) {
  using namespace view;
  if (paths.empty()) throw Error("nothing to view: give one or more files or folders");
  if (o.exposure && (!std::isfinite(*o.exposure) || std::fabs(*o.exposure) > 64))
    throw Error("exposure must be a number of EV in [-64, 64]");
  if (o.face_size < 4 || o.face_size > 1024) throw Error("face size must be 4 to 1024 pixels");
  if (o.table_size < 32 || o.table_size > 2048) throw Error("table size must be 32 to 2048 pixels");
  if (o.max_width < 320 || o.max_width > 16384) throw Error("sheet width must be 320 to 16384 pixels");
  std::vector<Item> items;
  std::set<std::string> seen;
  ContactSheet sheet;
  for (const auto& p : paths) collect(p, items, seen, {}, 0, sheet.skipped);

  const char* curve = o.tone_map == ToneMap::Aces       ? "ACES filmic fit (Narkowicz 2015)"
                      : o.tone_map == ToneMap::Reinhard ? "Reinhard x / (1 + x)"
                                                        : "clamp to [0, 1]";
  const std::string exposure =
      o.exposure ? fmt(*o.exposure, "%+.1f") + " EV"
                 : "chosen per picture (log-average luminance at 0.18, 99th percentile at most 1; each caption "
                   "says its EV)";
  sheet.tone_map_text = "HDR: exposure " + exposure + ", " + curve + ", sRGB";
  sheet.colour_scale_text =
      "tables: cubehelix (Green 2011), minimum at the left end of each scale, maximum at the right; log10 where marked";
  const int inner = o.max_width - 2 * kMargin;
  std::vector<Block> blocks;
  for (const Item& it : items) {
    blocks.push_back(item_block(it, o, inner));
    sheet.files.push_back(shown_name(it.path, o));
  }
  const std::string title = o.title.empty() ? "brdfbake view" : o.title;
  const std::string count =
      std::to_string(items.size()) + (items.size() == 1 ? " file" : " files") + ", brdfbake " + kVersion;
  int width = std::max(
      {text_width(title, 2), text_width(sheet.tone_map_text), text_width(sheet.colour_scale_text), text_width(count)});
  int height = 2 * kLineHeight + 3 * kCaption + kGap;
  for (const Block& b : blocks) {
    width = std::max(width, b.canvas.width());
    height += b.canvas.height() + 2 * kGap;
  }
  width = std::min(width, inner) + 2 * kMargin;
  height += 2 * kMargin;
  Canvas c(width, height, kBackground);
  int y = kMargin;
  c.text(kMargin, y, title, kText, 2);
  SheetRegion tr;
  tr.role = "sheet title";
  tr.label = title;
  tr.x = kMargin;
  tr.y = y;
  tr.width = text_width(title, 2);
  tr.height = 2 * kLineHeight;
  sheet.regions.push_back(tr);
  y += 2 * kLineHeight + 2;
  c.text(kMargin, y, count, kDim);
  c.text(kMargin, y + kCaption, sheet.tone_map_text, kText);
  c.text(kMargin, y + 2 * kCaption, sheet.colour_scale_text, kText);
  y += 3 * kCaption + kGap;
  for (const Block& b : blocks) {
    c.fill_rect(kMargin, y - kGap / 2 - 1, width - 2 * kMargin, 1, kPanel);
    c.blit(b.canvas, kMargin, y);
    for (SheetRegion r : b.regions) {
      r.x += kMargin;
      r.y += y;
      sheet.regions.push_back(r);
    }
    y += b.canvas.height() + 2 * kGap;
  }
  sheet.width = c.width();
  sheet.height = c.height();
  sheet.rgb = std::move(c.rgb());
  return sheet;
}

void write_contact_sheet(const ContactSheet& sheet, const std::string& path) {
  std::vector<std::pair<std::string, std::string>> text = {
      {"Software", std::string("brdfbake ") + kVersion},
      {"Description", "brdfbake contact sheet: " + sheet.tone_map_text + "; " + sheet.colour_scale_text},
  };
  std::string files;
  for (const auto& f : sheet.files) files += (files.empty() ? "" : "\n") + f;
  text.emplace_back("brdfbake:files", files);
  io::ParentFolders folders(path);  // made if missing, as every output's
  io::write_png_rgb8(path, sheet.width, sheet.height, sheet.rgb, text);
  folders.keep();
}

}  // namespace brdfbake
