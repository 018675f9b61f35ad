// brdfbake_oiio.so: the OpenImageIO reader behind io/oiio_module.hpp. Built as its own shared
// module; the only code of brdfbake that includes OpenImageIO. It exports the C functions of
// oiio_module.hpp and nothing else.
#include "io/oiio_module.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <sstream>
#include <string>
#include <vector>

#include "io/image_limits.hpp"
#include "io/srgb.hpp"

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

namespace {

// How integer-coded values of a colour space become linear (empty note: they are linear).
struct Transfer {
  enum class Kind { Linear, Srgb, Gamma } kind = Kind::Linear;
  double exponent = 1.0;
  std::string note;
};

using brdfbake::io::srgb_to_linear;

// False (with `why`) for a colour space whose transfer is not known.
bool integer_transfer(const OIIO::ImageSpec& spec, Transfer& t, std::string& why) {
  const std::string space = spec.get_string_attribute("oiio:ColorSpace");
  std::string lower = space;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const int bits = int(spec.format.size()) * 8;
  const std::string depth = std::to_string(bits) + "-bit ";
  if (lower.empty() && bits > 8) {
    t.kind = Transfer::Kind::Linear;  // 16-bit data is as often linear as not: read as stored, and said so
    t.note = depth + "with no colour space stated: read as linear values";
  } else if (lower.empty()) {
    t.kind = Transfer::Kind::Srgb;
    t.note = depth + "sRGB (no colour space stated: assumed, as for any untagged 8-bit image) decoded to linear";
  } else if (lower == "srgb" || lower == "srgb_texture" || lower == "srgb_rec709_scene") {
    t.kind = Transfer::Kind::Srgb;
    t.note = depth + "sRGB (oiio:ColorSpace " + space + ") decoded to linear";
  } else if (lower.find("linear") != std::string::npos || lower == "scene_linear" || lower == "raw") {
    t.kind = Transfer::Kind::Linear;
  } else if (lower.rfind("gammacorrected", 0) == 0 || lower.rfind("gamma", 0) == 0) {
    const size_t digits = lower.find_first_of("0123456789.");
    const double g = digits == std::string::npos ? 0.0 : std::atof(lower.c_str() + digits);
    if (!(g > 0.05 && g < 20.0)) {
      why = "its colour space '" + space.substr(0, 40) + "' has no gamma brdfbake can read";
      return false;
    }
    t.kind = Transfer::Kind::Gamma;
    t.exponent = g;
    t.note = depth + "gamma " + std::to_string(g).substr(0, 4) + " (oiio:ColorSpace " + space + ") decoded to linear";
  } else {
    why = "its colour space '" + space.substr(0, 40) +
          "' is not one brdfbake can decode to linear: save it as linear OpenEXR or Radiance .hdr";
    return false;
  }
  return true;
}

struct StopCheck {
  brdfbake_oiio_stop_fn should_stop;
  bool stopped;
};
bool on_progress(void* data, float) {
  auto* s = static_cast<StopCheck*>(data);
  if (s->should_stop != nullptr && s->should_stop() != 0) s->stopped = true;
  return s->stopped;  // true aborts the read
}

}  // namespace

BRDFBAKE_OIIO_EXPORT int brdfbake_oiio_read(const char* path, unsigned long long max_pixels,
                                            unsigned long long max_bytes, brdfbake_oiio_stop_fn should_stop,
                                            brdfbake_oiio_image* out, char* error, size_t error_size) {
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
    Transfer transfer;
    const bool integer =
        spec.format.basetype == OIIO::TypeDesc::UINT8 || spec.format.basetype == OIIO::TypeDesc::UINT16 ||
        spec.format.basetype == OIIO::TypeDesc::INT8 || spec.format.basetype == OIIO::TypeDesc::INT16 ||
        spec.format.basetype == OIIO::TypeDesc::UINT32 || spec.format.basetype == OIIO::TypeDesc::INT32;
    if (integer) {
      std::string why;
      if (!integer_transfer(spec, transfer, why)) {
        set_error(error, error_size, why);
        return 1;
      }
    }
    const size_t count = static_cast<size_t>(w) * static_cast<size_t>(h) * static_cast<size_t>(nch);
    float* pixels = static_cast<float*>(std::malloc(count * sizeof(float)));
    if (pixels == nullptr) {
      set_error(error, error_size, "out of memory");
      return 1;
    }
    StopCheck stop{should_stop, false};
    if (!in->read_image(0, 0, 0, nch, OIIO::TypeDesc::FLOAT, pixels, OIIO::AutoStride, OIIO::AutoStride,
                        OIIO::AutoStride, on_progress, &stop)) {
      std::string why = one_line(in->geterror());
      if (why.empty()) why = "read failed";
      std::free(pixels);
      if (stop.stopped) {
        set_error(error, error_size, "cancelled");
        return 2;
      }
      set_error(error, error_size, "truncated or corrupt? " + why);
      return 1;
    }
    if (transfer.kind != Transfer::Kind::Linear) {
      // Colour channels only: alpha (and any channel after it) stays as stored.
      const int alpha = spec.alpha_channel;
      for (size_t p = 0; p < size_t(w) * size_t(h); ++p)
        for (int c = 0; c < nch; ++c) {
          if (c == alpha) continue;
          float& v = pixels[p * size_t(nch) + size_t(c)];
          const double x = std::max(0.0, double(v));
          v = float(transfer.kind == Transfer::Kind::Srgb ? srgb_to_linear(x) : std::pow(x, transfer.exponent));
        }
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
    if (!transfer.note.empty()) d << ", " << transfer.note;
    out->description = copy_string(d.str());
    out->transfer_note = copy_string(transfer.note);
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
  std::free(image->transfer_note);
  image->pixels = nullptr;
  image->channel_names = image->description = image->transfer_note = nullptr;
}
