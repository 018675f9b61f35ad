// PNG reading and writing through libpng (the "classic" API: it gives the text chunks and the sRGB
// chunk that the simplified API hides). libpng reports errors by longjmp: every libpng call sits in
// a function whose C++ objects live in a state struct reached through a pointer that is not changed
// after setjmp, so nothing is left in an indeterminate state when an error jumps back.
#include "io/png_image.hpp"

#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string_view>
#include <system_error>

#include "brdfbake/error.hpp"
#include "io/atomic_file.hpp"

namespace brdfbake::io {
namespace {

// libpng's error and warning handlers: the message is kept for the exception thrown after the jump.
struct ErrorState {
  char message[256] = {0};
};

void on_error(png_structp png, png_const_charp message) {
  auto* state = static_cast<ErrorState*>(png_get_error_ptr(png));
  std::snprintf(state->message, sizeof state->message, "%s", message ? message : "libpng error");
  png_longjmp(png, 1);
}
void on_warning(png_structp, png_const_charp) {}  // warnings (e.g. unknown chunks) do not stop a read

struct ReadState {
  const std::vector<uint8_t>* bytes = nullptr;
  size_t offset = 0;
  PngImage image;
  std::vector<png_bytep> rows;
  std::vector<uint8_t> raw;
};

void read_from_memory(png_structp png, png_bytep out, png_size_t length) {
  auto* s = static_cast<ReadState*>(png_get_io_ptr(png));
  if (s->offset + length > s->bytes->size()) png_error(png, "the file is truncated");
  std::memcpy(out, s->bytes->data() + s->offset, length);
  s->offset += length;
}

// Returns false (with err->message) when libpng failed.
bool decode(ReadState* s, ErrorState* err) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, err, on_error, on_warning);
  if (!png) {
    std::snprintf(err->message, sizeof err->message, "out of memory");
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
    if (!err->message[0]) std::snprintf(err->message, sizeof err->message, "out of memory");
    return false;
  }
  png_set_read_fn(png, s, read_from_memory);
  png_read_info(png, info);
  const png_uint_32 width = png_get_image_width(png, info), height = png_get_image_height(png, info);
  const int color = png_get_color_type(png, info);
  const int depth = png_get_bit_depth(png, info);
  if (color == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (color == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (png_get_valid(png, info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png);
  if (depth == 16) png_set_swap(png);  // host (little-endian) order for the uint16 copy below
  png_read_update_info(png, info);
  const int channels = png_get_channels(png, info);
  const int out_depth = png_get_bit_depth(png, info);
  const size_t row_bytes = png_get_rowbytes(png, info);
  s->raw.resize(row_bytes * height);
  s->rows.resize(height);
  for (png_uint_32 y = 0; y < height; ++y) s->rows[y] = s->raw.data() + y * row_bytes;
  png_read_image(png, s->rows.data());
  png_read_end(png, info);
  png_textp text = nullptr;
  int n_text = 0;
  png_get_text(png, info, &text, &n_text);
  for (int k = 0; k < n_text; ++k)
    s->image.text.emplace_back(
        text[k].key ? text[k].key : "",
        text[k].text ? std::string(text[k].text, text[k].text_length ? text[k].text_length : std::strlen(text[k].text))
                     : std::string());
  s->image.width = static_cast<int>(width);
  s->image.height = static_cast<int>(height);
  s->image.channels = channels;
  s->image.bit_depth = out_depth;
  png_destroy_read_struct(&png, &info, nullptr);
  return true;
}

struct WriteState {
  std::vector<uint8_t> out;
  const std::vector<uint8_t>* rgb = nullptr;
  const std::vector<std::pair<std::string, std::string>>* text = nullptr;
  std::vector<png_text> chunks;
  int width = 0, height = 0;
  int level = 9;
};

void write_to_memory(png_structp png, png_bytep data, png_size_t length) {
  auto* s = static_cast<WriteState*>(png_get_io_ptr(png));
  s->out.insert(s->out.end(), data, data + length);
}
void flush_memory(png_structp) {}

bool encode(WriteState* s, ErrorState* err) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, err, on_error, on_warning);
  if (!png) {
    std::snprintf(err->message, sizeof err->message, "out of memory");
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, info ? &info : nullptr);
    if (!err->message[0]) std::snprintf(err->message, sizeof err->message, "out of memory");
    return false;
  }
  png_set_write_fn(png, s, write_to_memory, flush_memory);
  png_set_IHDR(png, info, static_cast<png_uint_32>(s->width), static_cast<png_uint_32>(s->height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  s->chunks.resize(s->text->size());
  for (size_t k = 0; k < s->text->size(); ++k) {
    png_text& t = s->chunks[k];
    std::memset(&t, 0, sizeof t);
    t.compression = PNG_TEXT_COMPRESSION_NONE;
    t.key = const_cast<char*>((*s->text)[k].first.c_str());
    t.text = const_cast<char*>((*s->text)[k].second.c_str());
    t.text_length = (*s->text)[k].second.size();
  }
  if (!s->chunks.empty()) png_set_text(png, info, s->chunks.data(), static_cast<int>(s->chunks.size()));
  png_set_compression_level(png, s->level);
  png_write_info(png, info);
  const size_t stride = 3u * static_cast<size_t>(s->width);
  for (int y = 0; y < s->height; ++y)
    png_write_row(png, const_cast<png_bytep>(s->rgb->data() + static_cast<size_t>(y) * stride));
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

std::vector<uint8_t> read_binary_file(const std::string& path, const std::string& what) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw Error("cannot read " + what + " '" + path + "': it is a folder");
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int e = errno;
    throw Error("cannot read " + what + " '" + path + "': " +
                (std::filesystem::exists(path, ec) ? std::error_code(e ? e : EACCES, std::system_category()).message()
                                                   : std::string("no such file")));
  }
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw Error("cannot read " + what + " '" + path + "': read error");
  return bytes;
}

PngImage decode_png(const std::vector<uint8_t>& bytes, const std::string& origin) {
  if (bytes.size() < 8 || png_sig_cmp(bytes.data(), 0, 8) != 0)
    throw Error("cannot read '" + origin + "': not a PNG file");
  ReadState state;
  state.bytes = &bytes;
  ErrorState err;
  if (!decode(&state, &err)) throw Error("cannot read '" + origin + "': " + err.message);
  PngImage& im = state.image;
  const size_t n = static_cast<size_t>(im.width) * static_cast<size_t>(im.height) * static_cast<size_t>(im.channels);
  im.samples.resize(n);
  if (im.bit_depth == 16) {
    std::memcpy(im.samples.data(), state.raw.data(), 2 * n);
  } else {
    for (size_t k = 0; k < n; ++k) im.samples[k] = state.raw[k];
  }
  return std::move(state.image);
}

PngImage read_png(const std::string& path) { return decode_png(read_binary_file(path, "PNG"), path); }

std::vector<uint8_t> encode_png_rgb8(int width, int height, const std::vector<uint8_t>& rgb,
                                     const std::vector<std::pair<std::string, std::string>>& text, int level) {
  if (width <= 0 || height <= 0 || rgb.size() != 3u * static_cast<size_t>(width) * static_cast<size_t>(height))
    throw Error("PNG writer: " + std::to_string(rgb.size()) + " bytes for a " + std::to_string(width) + "x" +
                std::to_string(height) + " RGB image");
  for (const auto& [key, value] : text)
    if (key.empty() || key.size() > 79) throw Error("PNG writer: text key '" + key + "' must have 1 to 79 characters");
  WriteState state;
  state.rgb = &rgb;
  state.text = &text;
  state.width = width;
  state.height = height;
  state.level = level;
  ErrorState err;
  if (!encode(&state, &err)) throw Error(std::string("PNG writer: ") + err.message);
  return std::move(state.out);
}

void write_png_rgb8(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb,
                    const std::vector<std::pair<std::string, std::string>>& text, int level) {
  std::vector<uint8_t> bytes;
  try {
    bytes = encode_png_rgb8(width, height, rgb, text, level);
  } catch (const Error& e) {
    throw_write_error(path, e.what());
  }
  write_file_atomically(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace brdfbake::io
