// PNG reading and writing through libpng (the "classic" API: it gives the text chunks and the sRGB
// chunk that the simplified API hides). libpng reports errors by longjmp: every libpng call sits in
// a function whose C++ objects live in a state struct reached through a pointer that is not changed
// after setjmp, so nothing is left in an indeterminate state when an error jumps back.
#include "io/png_image.hpp"

#include <png.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <csetjmp>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string_view>
#include <system_error>

#include "brdfbake/cancel.hpp"
#include "brdfbake/error.hpp"
#include "io/atomic_file.hpp"
#include "io/image_file.hpp"
#include "io/special_files.hpp"
#include "io/srgb.hpp"

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

// The one libpng read set-up of both readers: the read struct with the handlers above and its
// error jump, `read` as the source of the bytes (its state `io`), the header read, and the
// expansions both ask for set (palette and grey below 8 bits to 8-bit samples, tRNS to alpha,
// 16-bit samples in host order); then `body(png, info)`, which reads what it needs (it may call
// png_read_update_info, png_read_image, png_read_row and any getter) and returns false to stop.
// The structs are destroyed on every way out. Returns false (err->message) when libpng failed, or
// what `body` returned. A libpng error jumps back here over `body`'s frame: `body` keeps no object
// with a destructor on its stack (the callers keep theirs in their state struct).
template <class Body>
bool read_png_with(void* io, png_rw_ptr read, ErrorState* err, Body&& body) {
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
  png_set_read_fn(png, io, read);
  png_read_info(png, info);
  const int color = png_get_color_type(png, info);
  const int depth = png_get_bit_depth(png, info);
  if (color == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (color == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (png_get_valid(png, info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png);
  if (depth == 16) png_set_swap(png);  // host (little-endian) order for the uint16 copies
  const bool ok = body(png, info);
  png_destroy_read_struct(&png, &info, nullptr);
  return ok;
}

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

// Returns false (with err->message) when libpng failed or the image is too large.
bool decode(ReadState* s, ErrorState* err) {
  return read_png_with(s, read_from_memory, err, [s, err](png_structp png, png_infop info) {
    const png_uint_32 width = png_get_image_width(png, info), height = png_get_image_height(png, info);
    if (uint64_t(width) * uint64_t(height) > ImageLimits{}.max_pixels) {  // before the rows are allocated
      std::snprintf(err->message, sizeof err->message, "too large (%lux%lu)", static_cast<unsigned long>(width),
                    static_cast<unsigned long>(height));
      return false;
    }
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
          text[k].text
              ? std::string(text[k].text, text[k].text_length ? text[k].text_length : std::strlen(text[k].text))
              : std::string());
    s->image.width = static_cast<int>(width);
    s->image.height = static_cast<int>(height);
    s->image.channels = channels;
    s->image.bit_depth = out_depth;
    return true;
  });
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

// ---- PNG as linear float (environments) ------------------------------------------------------------

// The transfer function a PNG's values are encoded with.
struct Transfer {
  enum class Kind { Linear, Srgb, Gamma } kind = Kind::Srgb;
  double exponent = 1.0;  // Gamma: linear = sample^exponent
  std::string note;       // what the file said, for FloatImage::transfer_note
};

// Everything with a destructor that decode_linear uses lives here, reached through a pointer set
// before setjmp: a libpng error jumps back over decode_linear's frame without skipping any.
struct LinearState {
  int fd = -1;
  std::string path;
  ImageLimits limits;
  bool cancelled = false;
  bool io_failed = false;
  std::string io_error;
  std::string refused;  // why the image is refused (its transfer, its size)
  FloatImage image;
  Transfer transfer;
  std::vector<uint8_t> raw;   // the rows as bytes
  std::vector<float> decode;  // sample value -> linear
  int bit_depth = 8;
};

void read_from_fd(png_structp png, png_bytep out, png_size_t length) {
  auto* s = static_cast<LinearState*>(png_get_io_ptr(png));
  size_t got = 0;
  try {
    got = read_fd(s->fd, reinterpret_cast<char*>(out), length, s->path);
  } catch (const Cancelled&) {
    s->cancelled = true;
  } catch (const std::exception& e) {
    s->io_failed = true;
    s->io_error = e.what();
  }
  // png_error jumps: never from inside a catch block
  if (s->cancelled) png_error(png, "cancelled");
  if (s->io_failed) png_error(png, "read error");
  if (got != length) png_error(png, "the file is truncated");
}

// The transfer of an opened PNG (after png_read_info); false with s->refused set when it cannot be told.
bool choose_transfer(png_structp png, png_infop info, LinearState* s) {
  Transfer& t = s->transfer;
  int intent = 0;
  const bool srgb = png_get_sRGB(png, info, &intent) != 0;
  png_fixed_point gamma = 0;
  const bool has_gamma = png_get_gAMA_fixed(png, info, &gamma) != 0 && gamma > 0;
  png_charp name = nullptr;
  int compression = 0;
  png_bytep profile = nullptr;
  png_uint_32 profile_length = 0;
  const bool icc = png_get_iCCP(png, info, &name, &compression, &profile, &profile_length) != 0;
  std::string named = name ? std::string(name).substr(0, 40) : std::string();
  std::string lower = named;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (srgb) {
    t.kind = Transfer::Kind::Srgb;
    t.note = icc ? "sRGB (its ICC profile, which libpng recognises as sRGB)" : "sRGB (its sRGB chunk)";
  } else if (icc && lower.find("linear") != std::string::npos) {
    t.kind = Transfer::Kind::Linear;
    t.note.clear();
  } else if (icc && lower.find("srgb") != std::string::npos) {
    t.kind = Transfer::Kind::Srgb;
    t.note = "sRGB (its ICC profile '" + named + "')";
  } else if (has_gamma) {
    if (gamma == PNG_FP_1) {
      t.kind = Transfer::Kind::Linear;
      t.note.clear();
    } else {
      t.kind = Transfer::Kind::Gamma;
      t.exponent = double(PNG_FP_1) / double(gamma);
      char b[96];
      std::snprintf(b, sizeof b, "gamma %.4g (its gAMA chunk)", t.exponent);
      t.note = b;
    }
  } else if (icc) {
    s->refused =
        "its ICC profile '" + named +
        "' is not one brdfbake can interpret, and it has no gAMA chunk: save it as linear OpenEXR or Radiance .hdr";
    return false;
  } else if (png_get_bit_depth(png, info) == 16) {
    // 16-bit data without a colour chunk is as often linear (tables, measurements) as not: read as
    // stored, and said so.
    t.kind = Transfer::Kind::Linear;
    t.note = "16-bit with no colour chunk (sRGB, gAMA or iCCP): read as linear values";
    return true;
  } else {
    t.kind = Transfer::Kind::Srgb;
    t.note = "sRGB (no colour chunk: assumed, as for any untagged 8-bit image)";
  }
  if (!t.note.empty())
    t.note = std::to_string(png_get_bit_depth(png, info) < 8 ? 8 : png_get_bit_depth(png, info)) + "-bit " + t.note +
             " decoded to linear";
  return true;
}

// Row y of the bytes in `row` into the float image, through the decode table (alpha stays linear).
void convert_row(LinearState* s, const uint8_t* row, png_uint_32 y) {
  FloatImage& im = s->image;
  const size_t n = size_t(im.width) * size_t(im.channels);
  const size_t channels = size_t(im.channels);
  const bool alpha = channels == 2 || channels == 4;
  const float scale = s->bit_depth == 16 ? 1.0f / 65535.0f : 1.0f / 255.0f;
  float* out = im.pixels.data() + size_t(y) * n;
  for (size_t k = 0; k < n; ++k) {
    uint16_t v = 0;
    if (s->bit_depth == 16)
      std::memcpy(&v, row + 2 * k, 2);
    else
      v = row[k];
    out[k] = alpha && k % channels == channels - 1 ? float(v) * scale : s->decode[v];
  }
}

// Returns false (err->message, or s->refused, s->cancelled) when libpng failed or the image is refused.
// No object with a destructor lives in this frame (see LinearState).
bool decode_linear(LinearState* s, ErrorState* err) {
  return read_png_with(s, read_from_fd, err, [s](png_structp png, png_infop info) {
    const png_uint_32 width = png_get_image_width(png, info), height = png_get_image_height(png, info);
    if (!choose_transfer(png, info, s)) return false;
    const int passes = png_set_interlace_handling(png);
    png_read_update_info(png, info);
    const int channels = png_get_channels(png, info);
    // The header's promise against the limits, before any pixel buffer exists (two float copies: the
    // image and the caller's RGB).
    s->refused = image_limits_problem(width, height, uint64_t(channels), 2, s->limits);
    if (!s->refused.empty()) return false;
    s->bit_depth = png_get_bit_depth(png, info);
    const size_t row_bytes = png_get_rowbytes(png, info);
    s->image.width = static_cast<int>(width);
    s->image.height = static_cast<int>(height);
    s->image.channels = channels;
    s->image.pixels.assign(size_t(width) * size_t(height) * size_t(channels), 0.0f);
    // Interlaced images pass over every row several times: their rows are kept as bytes until the last.
    s->raw.assign(passes > 1 ? row_bytes * height : row_bytes, 0);
    s->decode.assign(s->bit_depth == 16 ? 65536 : 256, 0.0f);
    const double max = s->bit_depth == 16 ? 65535.0 : 255.0;
    for (size_t v = 0; v < s->decode.size(); ++v) {
      const double c = double(v) / max;
      switch (s->transfer.kind) {
        case Transfer::Kind::Linear:
          s->decode[v] = float(c);
          break;
        case Transfer::Kind::Srgb:
          s->decode[v] = float(srgb_to_linear(c));
          break;
        case Transfer::Kind::Gamma:
          s->decode[v] = float(std::pow(c, s->transfer.exponent));
          break;
      }
    }
    for (int pass = 0; pass < passes; ++pass)
      for (png_uint_32 y = 0; y < height; ++y) {
        if (cancel_requested()) {  // between rows; Cancelled is thrown once libpng is cleaned up
          s->cancelled = true;
          return false;
        }
        uint8_t* row = s->raw.data() + (passes > 1 ? size_t(y) * row_bytes : 0);
        png_read_row(png, row, nullptr);
        if (pass == passes - 1) convert_row(s, row, y);
      }
    // png_read_end is not called: the chunks after the image are not needed, and not reading them
    // bounds what a file can make this reader do.
    return true;
  });
}

}  // namespace

std::vector<uint8_t> read_binary_file(const std::string& path, const std::string& what) {
  // A regular file only (the readers size it first), at most 4 GiB: more than any file brdfbake writes.
  const std::string bytes = read_input(path, what, std::uint64_t(4) << 30, "4 GiB", Streams::No);
  return std::vector<uint8_t>(bytes.begin(), bytes.end());
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

bool is_png(std::string_view head) {
  return head.size() >= 8 && png_sig_cmp(reinterpret_cast<png_const_bytep>(head.data()), 0, 8) == 0;
}

FloatImage read_png_linear(const std::string& path, const ImageLimits& limits) {
  LinearState state;
  state.path = path;
  state.limits = limits;
  state.fd = open_input(path, "PNG", Streams::No);
  ErrorState err;
  const bool ok = decode_linear(&state, &err);
  ::close(state.fd);
  if (state.cancelled) throw_if_cancelled();
  if (state.io_failed) throw IoError(state.io_error);
  if (!state.refused.empty()) throw Error(state.refused);
  if (!ok) throw Error(std::string("truncated or corrupt PNG: ") + err.message);
  FloatImage out = std::move(state.image);
  static const char* const kNames[5][4] = {{}, {"Y"}, {"Y", "A"}, {"R", "G", "B"}, {"R", "G", "B", "A"}};
  for (int c = 0; c < out.channels && out.channels <= 4; ++c) out.channel_names.emplace_back(kNames[out.channels][c]);
  out.description = "PNG " + std::to_string(out.width) + "x" + std::to_string(out.height) + ", " +
                    std::to_string(out.channels) + " channel(s), " + std::to_string(state.bit_depth) + "-bit";
  if (!state.transfer.note.empty()) {
    out.transfer_note = state.transfer.note;
    out.description += ", " + out.transfer_note;
  } else {
    out.description += ", linear";
  }
  return out;
}

}  // namespace brdfbake::io
