// Internal to `brdfbake view`: an 8-bit sRGB raster with the few drawing operations a contact sheet
// needs (rectangles, lines, text in stb_easy_font's segment font), and the value-to-colour maps it
// states on the sheet: the tone map of HDR radiance and the cubehelix colour scale of table values.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "brdfbake/view.hpp"

namespace brdfbake::view {

using Rgb8 = std::array<uint8_t, 3>;

inline constexpr Rgb8 kBackground = {24, 24, 24};
inline constexpr Rgb8 kPanel = {40, 40, 40};
inline constexpr Rgb8 kText = {230, 230, 230};
inline constexpr Rgb8 kDim = {150, 150, 150};
inline constexpr Rgb8 kAxis = {190, 190, 190};
inline constexpr Rgb8 kNoData = {70, 60, 70};  // texels with no value (below the horizon, empty cross cells)

class Canvas {
 public:
  Canvas() = default;
  Canvas(int width, int height, Rgb8 fill = kBackground);

  int width() const { return width_; }
  int height() const { return height_; }
  const std::vector<uint8_t>& rgb() const { return rgb_; }
  std::vector<uint8_t>& rgb() { return rgb_; }

  void set(int x, int y, Rgb8 c);
  Rgb8 get(int x, int y) const;
  void fill_rect(int x, int y, int w, int h, Rgb8 c);
  void outline_rect(int x, int y, int w, int h, Rgb8 c);
  void line(double x0, double y0, double x1, double y1, Rgb8 c);  // 1-pixel, end points included
  void blit(const Canvas& src, int x, int y);

  // Text in stb_easy_font's font (about 6 pixels an em at scale 1, 12 a line), top-left at (x, y);
  // characters outside printable ASCII are drawn as '?'. Returns the width drawn.
  int text(int x, int y, const std::string& s, Rgb8 c = kText, int scale = 1);

 private:
  int width_ = 0, height_ = 0;
  std::vector<uint8_t> rgb_;
};

int text_width(const std::string& s, int scale = 1);
inline constexpr int kLineHeight = 12;  // of text at scale 1

// ---- Value to colour -----------------------------------------------------------------------------

// The display transfer of HDR radiance: x = 2^exposure v (0 EV when none is set), then the tone
// map per channel, then the sRGB encoding (IEC 61966-2-1) to 8 bits. NaN shows as kNoData's colour.
Rgb8 tone_map(const float rgb[3], const ViewOptions& options);
double tone_curve(double x, ToneMap map);
uint8_t srgb8(double linear);  // [0, 1] linear -> 8-bit sRGB, rounded

// Cubehelix (Green 2011, "A colour scheme for the display of astronomical intensity images",
// Bull. Astr. Soc. India 39, 289): brightness rises monotonically from black (t = 0) to white
// (t = 1) while the hue turns; start 0.5, rotations -1.5, hue 1.2, gamma 1. t is clamped to [0, 1].
Rgb8 cubehelix(double t);

// The line colours of plots, one per channel index (r, g, b channels get red, green, blue).
Rgb8 series_colour(const std::string& channel, int index);

}  // namespace brdfbake::view
