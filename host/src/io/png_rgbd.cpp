// libpng in memory, and RGBD (see png_rgbd.hpp).
#include "io/png_rgbd.hpp"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "brdfbake/error.hpp"

namespace brdfbake::io {
namespace {

constexpr double kGammaEncode = 1.0 / 2.2;  // Babylon's GammaEncodePowerApprox
constexpr double kGammaDecode = 2.2;        // LinearEncodePowerApprox

[[noreturn]] void png_error_fn(png_structp png, png_const_charp message) {
  auto* what = static_cast<std::string*>(png_get_error_ptr(png));
  if (what) *what = message;
  png_longjmp(png, 1);
}
void png_warning_fn(png_structp, png_const_charp) {}

struct Reader {
  const uint8_t* data;
  size_t size;
  size_t at;
};

void read_fn(png_structp png, png_bytep out, png_size_t n) {
  auto* r = static_cast<Reader*>(png_get_io_ptr(png));
  if (n > r->size - r->at) png_error(png, "truncated PNG");
  std::memcpy(out, r->data + r->at, n);
  r->at += n;
}

void write_fn(png_structp png, png_bytep in, png_size_t n) {
  auto* out = static_cast<std::vector<uint8_t>*>(png_get_io_ptr(png));
  out->insert(out->end(), in, in + n);
}
void flush_fn(png_structp) {}

// 8-bit code of a value in [0, 1]: round to nearest (the GPU's float -> UNORM8 conversion).
uint8_t unorm8(double v) { return uint8_t(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); }

}  // namespace

// libpng reports errors by longjmp: the functions below keep every C++ object with a destructor
// outside the setjmp scope (the output vector and the row pointers live in the caller's frame and
// are only written to through libpng's callbacks).
std::vector<uint8_t> encode_png_rgba8(int width, int height, const std::vector<uint8_t>& rgba) {
  if (width < 1 || height < 1 || rgba.size() != size_t(width) * size_t(height) * 4)
    throw Error("PNG writer: " + std::to_string(rgba.size()) + " bytes for " + std::to_string(width) + "x" +
                std::to_string(height) + " RGBA");
  std::vector<uint8_t> out;
  std::string what;
  std::vector<png_bytep> rows(static_cast<size_t>(height));
  for (int y = 0; y < height; ++y) rows[size_t(y)] = const_cast<png_bytep>(rgba.data() + size_t(y) * size_t(width) * 4);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &what, png_error_fn, png_warning_fn);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    throw Error("PNG writer: libpng could not be initialised");
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw Error("PNG writer: " + what);
  }
  png_set_write_fn(png, &out, write_fn, flush_fn);
  png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8, PNG_COLOR_TYPE_RGB_ALPHA, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, 6);
  png_set_rows(png, info, rows.data());
  png_write_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
  png_destroy_write_struct(&png, &info);
  return out;
}

std::vector<uint8_t> decode_png_rgba8(const uint8_t* data, size_t size, int* width, int* height) {
  if (size < 8 || png_sig_cmp(data, 0, 8) != 0) throw Error("not a PNG (bad signature)");
  std::string what;
  Reader reader{data, size, 0};
  std::vector<uint8_t> pixels;
  std::vector<png_bytep> rows;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &what, png_error_fn, png_warning_fn);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw Error("PNG reader: libpng could not be initialised");
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw Error("PNG reader: " + what);
  }
  png_set_read_fn(png, &reader, read_fn);
  png_read_info(png, info);
  const png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
  if (png_get_bit_depth(png, info) != 8 || png_get_color_type(png, info) != PNG_COLOR_TYPE_RGB_ALPHA) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw Error("PNG reader: expected 8-bit RGBA");
  }
  pixels.resize(size_t(w) * size_t(h) * 4);
  rows.resize(h);
  for (png_uint_32 y = 0; y < h; ++y) rows[y] = pixels.data() + size_t(y) * size_t(w) * 4;
  png_read_image(png, rows.data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  *width = int(w);
  *height = int(h);
  return pixels;
}

void rgbd_encode(const float rgb[3], uint8_t out[4], bool* clamped) {
  double c[3];
  for (int i = 0; i < 3; ++i) c[i] = std::isfinite(rgb[i]) && rgb[i] > 0.0f ? double(rgb[i]) : 0.0;
  const double m = std::max(std::max(std::max(c[0], c[1]), c[2]), 1e-7);
  const double k = std::clamp(std::floor(std::max(kRgbdMaxValue / m, 1.0)), 1.0, 255.0);  // D = k / 255
  const double d = k / 255.0;
  if (clamped) *clamped = m > kRgbdMaxValue;
  for (int i = 0; i < 3; ++i) out[i] = unorm8(std::pow(std::min(c[i] * d, 1.0), kGammaEncode));
  out[3] = uint8_t(k);
}

void rgbd_decode(const uint8_t in[4], double rgb[3]) {
  const double d = in[3] / 255.0;
  for (int i = 0; i < 3; ++i) rgb[i] = d > 0.0 ? std::pow(in[i] / 255.0, kGammaDecode) / d : 0.0;
}

double rgbd_half_step(const uint8_t in[4], int channel) {
  const double d = in[3] / 255.0;
  if (d <= 0.0) return 0.0;
  const int code = in[channel];
  const double lo = std::pow(std::max(code - 0.5, 0.0) / 255.0, kGammaDecode) / d;
  const double hi = std::pow(std::min(code + 0.5, 255.0) / 255.0, kGammaDecode) / d;
  const double v = std::pow(code / 255.0, kGammaDecode) / d;
  return std::max(v - lo, hi - v);
}

}  // namespace brdfbake::io
