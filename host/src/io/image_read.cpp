// OpenEXR through the OpenEXR library (Imf::InputFile), Radiance RGBE through stb_image (its HDR
// loader only: STBI_ONLY_HDR).
#include "io/image_read.hpp"

#include <Iex.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfStringAttribute.h>

#include <algorithm>
#include <limits>

#include "brdfbake/error.hpp"
#include "io/png_image.hpp"

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_HDR
#define STBI_NO_STDIO
#include <stb/stb_image.h>

namespace brdfbake::io {

namespace {

int channel_rank(const std::string& name) {
  static const char* const kOrder[] = {"R", "G", "B", "A"};
  for (int k = 0; k < 4; ++k)
    if (name == kOrder[k]) return k;
  return 4;
}

}  // namespace

FloatImage read_exr(const std::string& path) {
  try {
    Imf::InputFile file(path.c_str());
    const Imf::Header& header = file.header();
    const Imath::Box2i window = header.dataWindow();
    const long long w = static_cast<long long>(window.max.x) - window.min.x + 1;
    const long long h = static_cast<long long>(window.max.y) - window.min.y + 1;
    if (w <= 0 || h <= 0 || w * h > (1ll << 28)) throw Error("cannot read '" + path + "': unsupported image size");
    FloatImage im;
    im.width = static_cast<int>(w);
    im.height = static_cast<int>(h);
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it)
      im.channel_names.push_back(it.name());
    std::stable_sort(im.channel_names.begin(), im.channel_names.end(),
                     [](const std::string& a, const std::string& b) { return channel_rank(a) < channel_rank(b); });
    if (im.channel_names.empty()) throw Error("cannot read '" + path + "': the file has no channels");
    const size_t nc = im.channel_names.size();
    im.pixels.assign(static_cast<size_t>(w * h) * nc, 0.0f);
    Imf::FrameBuffer fb;
    // The slices address pixel (x, y) of the data window at base + x xStride + y yStride.
    char* base =
        reinterpret_cast<char*>(im.pixels.data()) -
        (static_cast<ptrdiff_t>(window.min.x) + static_cast<ptrdiff_t>(window.min.y) * static_cast<ptrdiff_t>(w)) *
            static_cast<ptrdiff_t>(nc * sizeof(float));
    for (size_t c = 0; c < nc; ++c)
      fb.insert(im.channel_names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), nc * sizeof(float),
                                                nc * sizeof(float) * static_cast<size_t>(w)));
    file.setFrameBuffer(fb);
    file.readPixels(window.min.y, window.max.y);
    for (auto it = header.begin(); it != header.end(); ++it)
      if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
        im.attributes.emplace_back(it.name(), s->value());
    return im;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error("cannot read '" + path + "': " + e.what());
  }
}

FloatImage read_rgbe(const std::string& path) {
  const std::vector<uint8_t> bytes = read_binary_file(path, "RGBE image");
  if (bytes.size() > static_cast<size_t>(std::numeric_limits<int>::max()))
    throw Error("cannot read '" + path + "': file too large");
  int w = 0, h = 0, n = 0;
  float* data = stbi_loadf_from_memory(bytes.data(), static_cast<int>(bytes.size()), &w, &h, &n, 3);
  if (!data) throw Error("cannot read '" + path + "': not a Radiance RGBE file (" + stbi_failure_reason() + ")");
  FloatImage im;
  im.width = w;
  im.height = h;
  im.channel_names = {"R", "G", "B"};
  im.pixels.assign(data, data + 3u * static_cast<size_t>(w) * static_cast<size_t>(h));
  stbi_image_free(data);
  return im;
}

}  // namespace brdfbake::io
