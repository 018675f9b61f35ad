// brdfbake_oiio.so: the OpenImageIO reader behind io/oiio_module.hpp. Built as its own shared
// module; the only code of brdfbake that includes OpenImageIO. It exports the C functions of
// oiio_module.hpp and nothing else.
#include "io/oiio_module.hpp"
#include "io/image_limits.hpp"

#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <sstream>
#include <string>
#include <vector>

#define BRDFBAKE_OIIO_EXPORT extern "C" __attribute__((visibility("default")))

namespace {

char* copy_string(const std::string& s) {
  char* out = static_cast<char*>(std::malloc(s.size() + 1));
  if (out != nullptr) std::memcpy(out, s.c_str(), s.size() + 1);
  return out;
}

void set_error(char* error, size_t size, const std::string& why) {
  if (error != nullptr && size > 0) std::snprintf(error, size, "%s", why.c_str());
}

// One line: OpenImageIO's messages may span several.
std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

}  // namespace

BRDFBAKE_OIIO_EXPORT int brdfbake_oiio_abi_version(void) { return BRDFBAKE_OIIO_ABI_VERSION; }

BRDFBAKE_OIIO_EXPORT int brdfbake_oiio_read(const char* path, unsigned long long max_pixels,
                                            unsigned long long max_bytes, brdfbake_oiio_image* out, char* error,
                                            size_t error_size) {
  try {
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
      std::string why = one_line(OIIO::geterror());
      if (why.empty()) why = "not an image format OpenImageIO reads";
      set_error(error, error_size, why);
      return 1;
    }
    const OIIO::ImageSpec spec = in->spec(0, 0);
    const int w = spec.width, h = spec.height, nch = spec.nchannels;
    if (w < 1 || h < 1 || nch < 1) {
      set_error(error, error_size, "no pixels");
      return 1;
    }
    brdfbake::io::ImageLimits limits;
    limits.max_pixels = max_pixels;
    limits.max_bytes = max_bytes;
    // two copies: this module's buffer and the caller's
    const std::string problem = brdfbake::io::image_limits_problem(uint64_t(w), uint64_t(h), uint64_t(nch), 2, limits);
    if (!problem.empty()) {
      set_error(error, error_size, problem);
      return 1;
    }
    const size_t count = static_cast<size_t>(w) * static_cast<size_t>(h) * static_cast<size_t>(nch);
    float* pixels = static_cast<float*>(std::malloc(count * sizeof(float)));
    if (pixels == nullptr) {
      set_error(error, error_size, "out of memory");
      return 1;
    }
    if (!in->read_image(0, 0, 0, nch, OIIO::TypeDesc::FLOAT, pixels)) {
      std::string why = one_line(in->geterror());
      if (why.empty()) why = "read failed";
      std::free(pixels);
      set_error(error, error_size, "truncated or corrupt? " + why);
      return 1;
    }
    std::string names;
    for (int c = 0; c < nch; ++c) {
      if (c > 0) names += ',';
      if (static_cast<size_t>(c) < spec.channelnames.size()) names += spec.channelnames[static_cast<size_t>(c)];
    }
    std::ostringstream d;
    d << in->format_name() << " " << w << "x" << h << ", " << nch << " channel(s), " << spec.format.c_str();
    if (spec.tile_width > 0) d << ", tiled";
    int levels = 1;
    while (in->seek_subimage(0, levels)) ++levels;
    if (levels > 1) d << ", " << levels << " mip levels (level 0 read)";
    in->close();
    out->width = w;
    out->height = h;
    out->channels = nch;
    out->pixels = pixels;
    out->channel_names = copy_string(names);
    out->description = copy_string(d.str());
    return 0;
  } catch (const std::exception& e) {
    set_error(error, error_size, one_line(e.what()));
    return 1;
  }
}

BRDFBAKE_OIIO_EXPORT void brdfbake_oiio_free(brdfbake_oiio_image* image) {
  if (image == nullptr) return;
  std::free(image->pixels);
  std::free(image->channel_names);
  std::free(image->description);
  image->pixels = nullptr;
  image->channel_names = image->description = nullptr;
}
