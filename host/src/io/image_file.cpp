// Reading images by signature, with OpenImageIO (the module) for the formats read nowhere else;
// the RGBE writer. The OpenEXR code is in exr.cpp, the PNG writer in png.cpp, the PNG reader in png_image.cpp.
#include "io/image_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "brdfbake/cancel.hpp"
#include "brdfbake/error.hpp"
#include "io/oiio_module.hpp"
#include "io/rgbe.hpp"
#include "io/special_files.hpp"
#include "runtime/stderr_capture.hpp"

namespace brdfbake::io {
namespace {

// The first bytes of an image file (a regular file: checked by read_image first).
std::string read_head(const std::string& path, size_t n) { return read_input_head(path, "image", n, Streams::No); }

FloatImage read_rgbe_file(const std::string& path, const ImageLimits& limits) {
  // Only what the header's picture can take is read (trailing bytes of a huge file are not).
  const std::uint64_t bound = rgbe_file_bound(read_head(path, kRgbeMaxHeaderBytes + 64));
  const std::string bytes = read_head(path, static_cast<size_t>(bound));
  RgbeImage rgbe = decode_rgbe(bytes, limits);
  FloatImage out;
  out.width = rgbe.width;
  out.height = rgbe.height;
  out.channels = 3;
  out.channel_names = {"R", "G", "B"};
  out.pixels = std::move(rgbe.rgb);
  out.description = "Radiance RGBE " + std::to_string(out.width) + "x" + std::to_string(out.height) + ", " +
                    (rgbe.run_length_encoded ? "run-length encoded" : "flat") + ", " + rgbe.orientation;
  if (rgbe.exposure != 1.0) {
    // As OpenImageIO and stb_image read it: said, not silently different from what Radiance shows.
    char b[160];
    std::snprintf(b, sizeof b, "its header's EXPOSURE (%.6g) is not divided out: values as stored", rgbe.exposure);
    out.transfer_note = b;
    out.description += std::string(", ") + b;
  }
  return out;
}

int stop_requested() { return cancel_requested() ? 1 : 0; }

// The first non-empty line of `text`, at most 160 characters.
std::string first_line(const std::string& text) {
  std::stringstream in(text);
  for (std::string line; std::getline(in, line);) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (!line.empty()) return line.substr(0, 160);
  }
  return "";
}

FloatImage read_with_oiio(const std::string& path, const ImageLimits& limits) {
  const OiioModule* module = nullptr;
  try {
    module = &oiio_module();
  } catch (const Error& e) {
    throw Error(std::string("not OpenEXR or Radiance RGBE, and other formats need OpenImageIO: ") + e.what());
  }
  brdfbake_oiio_image image{};
  char error[512] = {};
  int status = 0;
  // The libraries behind OpenImageIO (libjpeg, libtiff, ...) may print to stderr: their words go
  // into the one-line error, never onto the terminal.
  const std::string printed = detail::run_with_stderr_captured([&] {
    status =
        module->read(path.c_str(), limits.max_pixels, limits.max_bytes, stop_requested, &image, error, sizeof error);
  });
  if (status == 2) throw_if_cancelled();
  if (status != 0) {
    std::string why = error[0] ? error : "OpenImageIO could not read it";
    if (const std::string line = first_line(printed); !line.empty() && why.find(line) == std::string::npos)
      why += " (" + line + ")";
    throw Error(why);
  }
  FloatImage out;
  try {
    out.width = image.width;
    out.height = image.height;
    out.channels = image.channels;
    out.pixels.assign(image.pixels, image.pixels + size_t(image.width) * size_t(image.height) * size_t(image.channels));
    std::stringstream names(image.channel_names ? image.channel_names : "");
    for (std::string name; std::getline(names, name, ',');) out.channel_names.push_back(name);
    out.description = image.description ? image.description : "";
    out.transfer_note = image.transfer_note ? image.transfer_note : "";
  } catch (...) {
    module->free(&image);
    throw;
  }
  module->free(&image);
  return out;
}

}  // namespace

FloatImage read_image(const std::string& path, const ImageLimits& limits) {
  // Decoders seek and size the file: a FIFO or a device is refused here, never read (special_files.hpp).
  if (const std::string problem = input_problem(path, Streams::No); !problem.empty()) throw Error(problem);
  if (::access(path.c_str(), R_OK) != 0) throw Error(std::strerror(errno));  // the reason, without the path again
  const std::string head = read_head(path, 8);
  FloatImage out;
  if (is_exr(head) && read_exr(path, limits, out)) return out;
  if (is_rgbe(head)) return read_rgbe_file(path, limits);
  if (is_png(head)) return read_png_linear(path, limits);
  return read_with_oiio(path, limits);
}

void write_rgbe(const TempFile& temp, int width, int height, const float* rgb) {
  std::string bytes;
  try {
    bytes = encode_rgbe(width, height, rgb);
  } catch (const Error& e) {
    throw_write_error(temp.destination(), e.what());
  }
  write_bytes(temp, bytes);
}

}  // namespace brdfbake::io
