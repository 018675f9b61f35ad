// Reading images by signature, with OpenImageIO (the module) for the formats read nowhere else;
// the RGBE writer. The OpenEXR and PNG code is in exr.cpp and png.cpp.
#include "io/image_file.hpp"

#include <fstream>
#include <sstream>

#include "brdfbake/error.hpp"
#include "io/oiio_module.hpp"
#include "io/rgbe.hpp"

namespace brdfbake::io {
namespace {

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw Error("cannot open it");
  const std::streamoff size = in.tellg();
  if (size < 0) throw Error("cannot tell its size");
  std::string bytes(static_cast<size_t>(size), '\0');
  in.seekg(0);
  in.read(bytes.data(), size);
  if (in.gcount() != size) throw Error("read failed");
  return bytes;
}

std::string read_head(const std::string& path, size_t n) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open it");
  std::string head(n, '\0');
  in.read(head.data(), static_cast<std::streamsize>(n));
  head.resize(static_cast<size_t>(in.gcount()));
  return head;
}

FloatImage read_rgbe_file(const std::string& path, const ImageLimits& limits) {
  RgbeImage rgbe = decode_rgbe(read_all(path), limits);
  FloatImage out;
  out.width = rgbe.width;
  out.height = rgbe.height;
  out.channels = 3;
  out.channel_names = {"R", "G", "B"};
  out.pixels = std::move(rgbe.rgb);
  out.description = "Radiance RGBE " + std::to_string(out.width) + "x" + std::to_string(out.height) + ", " +
                    (rgbe.run_length_encoded ? "run-length encoded" : "flat") + ", " + rgbe.orientation;
  return out;
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
  if (module->read(path.c_str(), limits.max_pixels, limits.max_bytes, &image, error, sizeof error) != 0)
    throw Error(std::string(error[0] ? error : "OpenImageIO could not read it"));
  FloatImage out;
  try {
    out.width = image.width;
    out.height = image.height;
    out.channels = image.channels;
    out.pixels.assign(image.pixels, image.pixels + size_t(image.width) * size_t(image.height) * size_t(image.channels));
    std::stringstream names(image.channel_names ? image.channel_names : "");
    for (std::string name; std::getline(names, name, ',');) out.channel_names.push_back(name);
    out.description = image.description ? image.description : "";
  } catch (...) {
    module->free(&image);
    throw;
  }
  module->free(&image);
  return out;
}

}  // namespace

FloatImage read_image(const std::string& path, const ImageLimits& limits) {
  const std::string head = read_head(path, 4);
  FloatImage out;
  if (is_exr(head) && read_exr(path, limits, out)) return out;
  if (is_rgbe(head)) return read_rgbe_file(path, limits);
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
