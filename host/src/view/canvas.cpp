#include "view/canvas.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

// stb_easy_font (public domain, Sean Barrett): text as axis-aligned quads, no font files.
#include <stb/stb_easy_font.h>

#include "brdfbake/math/conventions.hpp"
#include "io/srgb.hpp"

namespace brdfbake::view {

namespace {

using brdfbake::math::kPi;

std::string printable(const std::string& s) {
  std::string out = s;
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
  return out;
}

}  // namespace

Canvas::Canvas(int width, int height, Rgb8 fill)
    : width_(std::max(0, width)), height_(std::max(0, height)), rgb_(3u * size_t(width_) * size_t(height_)) {
  fill_rect(0, 0, width_, height_, fill);
}

void Canvas::set(int x, int y, Rgb8 c) {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
  uint8_t* p = &rgb_[3 * (size_t(y) * size_t(width_) + size_t(x))];
  p[0] = c[0];
  p[1] = c[1];
  p[2] = c[2];
}

Rgb8 Canvas::get(int x, int y) const {
  const uint8_t* p = &rgb_[3 * (size_t(y) * size_t(width_) + size_t(x))];
  return {p[0], p[1], p[2]};
}

void Canvas::fill_rect(int x, int y, int w, int h, Rgb8 c) {
  const int x0 = std::max(0, x), y0 = std::max(0, y), x1 = std::min(width_, x + w), y1 = std::min(height_, y + h);
  for (int j = y0; j < y1; ++j)
    for (int i = x0; i < x1; ++i) set(i, j, c);
}

void Canvas::outline_rect(int x, int y, int w, int h, Rgb8 c) {
  fill_rect(x, y, w, 1, c);
  fill_rect(x, y + h - 1, w, 1, c);
  fill_rect(x, y, 1, h, c);
  fill_rect(x + w - 1, y, 1, h, c);
}

void Canvas::line(double x0, double y0, double x1, double y1, Rgb8 c) {
  const double dx = x1 - x0, dy = y1 - y0;
  const int steps = std::max(1, static_cast<int>(std::ceil(std::max(std::fabs(dx), std::fabs(dy)))));
  for (int k = 0; k <= steps; ++k) {
    const double t = double(k) / steps;
    set(static_cast<int>(std::lround(x0 + t * dx)), static_cast<int>(std::lround(y0 + t * dy)), c);
  }
}

void Canvas::blit(const Canvas& src, int x, int y) {
  for (int j = 0; j < src.height(); ++j)
    for (int i = 0; i < src.width(); ++i) set(x + i, y + j, src.get(i, j));
}

int Canvas::text(int x, int y, const std::string& s, Rgb8 c, int scale) {
  std::string t = printable(s);
  // 64 bytes a quad; no glyph has more than 12 segments.
  std::vector<char> quads(t.size() * 12 * 64 + 64);
  const int n = stb_easy_font_print(0.0f, 0.0f, t.data(), nullptr, quads.data(), static_cast<int>(quads.size()));
  for (int q = 0; q < n; ++q) {
    const float* v0 = reinterpret_cast<const float*>(quads.data() + 64 * q);       // top-left vertex
    const float* v2 = reinterpret_cast<const float*>(quads.data() + 64 * q + 32);  // bottom-right vertex
    const int qx0 = static_cast<int>(std::lround(v0[0])), qy0 = static_cast<int>(std::lround(v0[1]));
    const int qx1 = static_cast<int>(std::lround(v2[0])), qy1 = static_cast<int>(std::lround(v2[1]));
    fill_rect(x + scale * qx0, y + scale * qy0, scale * (qx1 - qx0), scale * (qy1 - qy0), c);
  }
  return text_width(s, scale);
}

int text_width(const std::string& s, int scale) {
  std::string t = printable(s);
  return scale * stb_easy_font_width(t.data());
}

namespace {

// The sRGB encoding (IEC 61966-2-1) of v in (0, 1), rounded to 8 bits.
int srgb8_formula(double v) {
  const double e = io::linear_to_srgb(v);
  return static_cast<int>(std::lround(e * 255.0));
}

// The code of v in (0, 1) without a pow a channel (a preview sheet tone-maps 0.8 M channels): t[k]
// (k = 1..255) is the smallest double with srgb8_formula >= k, found by bisection over the bit
// patterns of the positive doubles (ordered as integers); the formula is monotone, so the code of v
// is the number of thresholds at or below it. [0, 1) is cut into kCells equal cells (v kCells is
// exact: a power of two), none of which holds two thresholds (the steepest slope, 255 x 12.92 at
// 0, is 0.8 codes a cell; checked when the table is made, a cell that did would take the binary
// search): a cell's first code and the next threshold give the code with one comparison. The
// formula's own results (tests/host/test_view.cpp compares them).
class Srgb8Table {
 public:
  Srgb8Table() {
    auto bits = [](double d) {
      uint64_t b = 0;
      std::memcpy(&b, &d, sizeof b);
      return b;
    };
    auto value = [](uint64_t b) {
      double d = 0;
      std::memcpy(&d, &b, sizeof d);
      return d;
    };
    t_[0] = 0.0;
    for (int k = 1; k < 256; ++k) {
      uint64_t lo = 0, hi = bits(1.0);  // formula(lo) < k <= formula(hi)
      while (hi - lo > 1) {
        const uint64_t mid = lo + (hi - lo) / 2;
        (srgb8_formula(value(mid)) >= k ? hi : lo) = mid;
      }
      t_[size_t(k)] = value(hi);
    }
    t_[256] = t_[257] = 2.0;  // beyond every v < 1
    for (int i = 0; i < kCells; ++i) {
      const double start = double(i) / kCells, end = double(i + 1) / kCells;
      const int first = search(start);
      first_[size_t(i)] = uint8_t(first);
      next_[size_t(i)] = t_[size_t(first) + 1];
      searched_[size_t(i)] = t_[size_t(first) + 2] < end;  // two steps inside: search
    }
  }
  uint8_t code(double v) const {
    const size_t i = size_t(v * kCells);
    if (searched_[i]) return uint8_t(search(v));
    return uint8_t(first_[i] + (v >= next_[i] ? 1 : 0));
  }

 private:
  static constexpr int kCells = 4096;
  int search(double v) const { return int(std::upper_bound(t_.begin() + 1, t_.begin() + 256, v) - (t_.begin() + 1)); }
  std::array<double, 258> t_{};
  std::array<uint8_t, kCells> first_{};
  std::array<double, kCells> next_{};
  std::array<bool, kCells> searched_{};
};

}  // namespace

uint8_t srgb8(double v) {
  if (!(v > 0.0)) return 0;
  if (v >= 1.0) return 255;
  static const Srgb8Table table;
  return table.code(v);
}

double tone_curve(double x, ToneMap map) {
  if (!(x > 0.0)) return 0.0;
  switch (map) {
    case ToneMap::Aces:  // Narkowicz 2015, "ACES Filmic Tone Mapping Curve"
      return std::clamp(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
    case ToneMap::Reinhard:  // Reinhard et al. 2002, the global operator L / (1 + L)
      return x / (1.0 + x);
    case ToneMap::Clamp:
      return std::min(x, 1.0);
  }
  return 0.0;
}

Rgb8 tone_map(const float rgb[3], const ViewOptions& o) {
  if (std::isnan(rgb[0]) || std::isnan(rgb[1]) || std::isnan(rgb[2])) return kNoData;
  const double k = std::exp2(o.exposure.value_or(0.0));
  return {srgb8(tone_curve(k * double(rgb[0]), o.tone_map)), srgb8(tone_curve(k * double(rgb[1]), o.tone_map)),
          srgb8(tone_curve(k * double(rgb[2]), o.tone_map))};
}

Rgb8 cubehelix(double t) {
  const double start = 0.5, rotations = -1.5, hue = 1.2;
  const double l = std::clamp(std::isnan(t) ? 0.0 : t, 0.0, 1.0);
  const double phi = 2.0 * kPi * (start / 3.0 + rotations * l);
  const double a = hue * l * (1.0 - l) / 2.0;
  const double c = std::cos(phi), s = std::sin(phi);
  const double r = l + a * (-0.14861 * c + 1.78277 * s);
  const double g = l + a * (-0.29227 * c - 0.90649 * s);
  const double b = l + a * (1.97294 * c);
  auto q = [](double v) { return static_cast<uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); };
  return {q(r), q(g), q(b)};
}

Rgb8 series_colour(const std::string& channel, int index) {
  if (channel == "r" || channel == "R" || channel == "red") return {235, 80, 70};
  if (channel == "g" || channel == "G" || channel == "green") return {90, 200, 90};
  if (channel == "b" || channel == "B" || channel == "blue") return {90, 140, 255};
  static const Rgb8 kSeries[] = {{240, 200, 80},  {80, 200, 220}, {230, 120, 220},
                                 {200, 200, 200}, {250, 140, 60}, {140, 230, 140}};
  return kSeries[static_cast<size_t>(index) % std::size(kSeries)];
}

}  // namespace brdfbake::view
