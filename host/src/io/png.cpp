// 16-bit PNG output through libpng (PNG specification, third edition: IHDR, gAMA, tEXt, iTXt).
//
// libpng reports errors by longjmp to the setjmp of the caller. Only encode() below calls setjmp,
// and it holds no C++ object with a destructor, so the jump skips none; everything with a
// destructor lives in write_png16, outside the jump's reach.
#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "brdfbake/error.hpp"
#include "io/image_file.hpp"

namespace brdfbake::io {
namespace {

struct PngJob {
  int width = 0, height = 0, color_type = 0;
  png_bytep* rows = nullptr;
  png_textp text = nullptr;
  int text_count = 0;
  std::string* out = nullptr;  // the encoded file
  char error[256] = {};
};

extern "C" void on_png_error(png_structp png, png_const_charp message) {
  auto* job = static_cast<PngJob*>(png_get_error_ptr(png));
  std::snprintf(job->error, sizeof job->error, "%s", message);
  png_longjmp(png, 1);
}

extern "C" void on_png_warning(png_structp, png_const_charp) {}  // nothing we write warns

extern "C" void on_png_write(png_structp png, png_bytep data, png_size_t length) {
  auto* job = static_cast<PngJob*>(png_get_io_ptr(png));
  bool ok = true;
  try {
    job->out->append(reinterpret_cast<const char*>(data), length);
  } catch (...) {  // no exception may cross libpng's C frames
    ok = false;
  }
  if (!ok) png_error(png, "out of memory");
}

extern "C" void on_png_flush(png_structp) {}

bool encode(PngJob& job) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &job, on_png_error, on_png_warning);
  if (png == nullptr) {
    std::snprintf(job.error, sizeof job.error, "libpng could not start");
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    std::snprintf(job.error, sizeof job.error, "libpng could not start");
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, &job, on_png_write, on_png_flush);
  png_set_IHDR(png, info, static_cast<png_uint_32>(job.width), static_cast<png_uint_32>(job.height), 16, job.color_type,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_gAMA_fixed(png, info, PNG_GAMMA_LINEAR);  // linear data: gamma 1.0, no sRGB chunk
  if (job.text_count > 0) png_set_text(png, info, job.text, job.text_count);
  png_set_rows(png, info, job.rows);
  // Rows hold 16-bit samples in host order; PNG stores them big-endian.
  png_write_png(png, info, PNG_TRANSFORM_SWAP_ENDIAN, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

bool plain_ascii(const std::string& s) {
  for (char c : s)
    if (static_cast<unsigned char>(c) >= 0x80) return false;
  return true;
}

}  // namespace

void write_png16(const TempFile& temp, int width, int height, int channels, const uint16_t* pixels,
                 const std::vector<std::pair<std::string, std::string>>& text) {
  PngJob job;
  job.width = width;
  job.height = height;
  switch (channels) {
    case 1:
      job.color_type = PNG_COLOR_TYPE_GRAY;
      break;
    case 3:
      job.color_type = PNG_COLOR_TYPE_RGB;
      break;
    case 4:
      job.color_type = PNG_COLOR_TYPE_RGB_ALPHA;
      break;
    default:
      throw_write_error(temp.destination(), "PNG output holds 1, 3 or 4 channels, not " + std::to_string(channels));
  }
  std::vector<png_bytep> rows(static_cast<size_t>(height));
  for (size_t y = 0; y < rows.size(); ++y)
    rows[y] = reinterpret_cast<png_bytep>(const_cast<uint16_t*>(pixels + y * size_t(width) * size_t(channels)));
  // tEXt holds Latin-1; a value with other bytes goes to iTXt as UTF-8 (keywords stay Latin-1).
  std::vector<png_text> chunks(text.size());
  for (size_t k = 0; k < text.size(); ++k) {
    png_text& t = chunks[k];
    std::memset(&t, 0, sizeof t);
    t.compression = plain_ascii(text[k].second) ? PNG_TEXT_COMPRESSION_NONE : PNG_ITXT_COMPRESSION_NONE;
    t.key = const_cast<char*>(text[k].first.c_str());
    t.text = const_cast<char*>(text[k].second.c_str());
    t.text_length = t.compression == PNG_TEXT_COMPRESSION_NONE ? text[k].second.size() : 0;
    t.itxt_length = t.compression == PNG_TEXT_COMPRESSION_NONE ? 0 : text[k].second.size();
  }
  std::string bytes;
  job.rows = rows.data();
  job.text = chunks.data();
  job.text_count = static_cast<int>(chunks.size());
  job.out = &bytes;
  if (!encode(job)) throw_write_error(temp.destination(), std::string("libpng: ") + job.error);
  write_bytes(temp, bytes);
}

}  // namespace brdfbake::io
