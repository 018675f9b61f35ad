// OpenEXR files through OpenEXR 3.1's Imf library (no OpenImageIO): reading level 0 of the first
// part, and writing float32 images with string attributes.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTestFile.h>
#include <OpenEXR/ImfThreading.h>
#include <OpenEXR/ImfTileDescription.h>
#include <OpenEXR/ImfTiledInputFile.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <exception>
#include <mutex>
#include <sstream>
#include <thread>

#include "brdfbake/cancel.hpp"
#include "brdfbake/error.hpp"
#include "io/image_file.hpp"

namespace brdfbake::io {
namespace {

// Decompression and compression run on OpenEXR's global thread pool, one thread per core: a 4k
// PIZ or ZIP file decodes in a fraction of the single-threaded time. Started on the first EXR.
void start_exr_threads() {
  static std::once_flag once;
  std::call_once(
      once, [] { Imf::setGlobalThreadCount(static_cast<int>(std::max(1u, std::thread::hardware_concurrency()))); });
}

const char* pixel_type_name(Imf::PixelType t) {
  switch (t) {
    case Imf::HALF:
      return "half";
    case Imf::FLOAT:
      return "float";
    case Imf::UINT:
      return "uint";
    default:
      return "unknown";
  }
}

// The number of levels of a mip-mapped file with level 0 of w x h (OpenEXR's TileDescription:
// each level halves the larger side, rounding down or up, down to 1).
int mip_levels(int w, int h, Imf::LevelRoundingMode rounding) {
  int levels = 1;
  for (int size = std::max(w, h); size > 1; ++levels) size = rounding == Imf::ROUND_UP ? (size + 1) / 2 : size / 2;
  return levels;
}

// Channel names in OpenImageIO's order: R, G, B, A, then the rest as the file lists them
// (OpenEXR lists channels alphabetically).
std::vector<std::string> ordered_channels(const Imf::ChannelList& list) {
  std::vector<std::string> names;
  for (const char* first : {"R", "G", "B", "A"})
    if (list.findChannel(first)) names.emplace_back(first);
  for (auto it = list.begin(); it != list.end(); ++it) {
    const std::string name = it.name();
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
  return names;
}

}  // namespace

bool is_exr(std::string_view head) {
  // The magic number 20000630, little-endian (OpenEXR, "OpenEXR File Layout").
  return head.size() >= 4 && static_cast<uint8_t>(head[0]) == 0x76 && static_cast<uint8_t>(head[1]) == 0x2f &&
         static_cast<uint8_t>(head[2]) == 0x31 && static_cast<uint8_t>(head[3]) == 0x01;
}

namespace {

// Reads level 0 of an opened file (Imf::InputFile, or Imf::TiledInputFile for tiled files: reading
// whole tiles is several times faster than InputFile's scanline view of them). False for the
// variants left to OpenImageIO.
template <typename File, typename Read>
bool read_level0(File& file, const ImageLimits& limits, FloatImage& out, Read read) {
  const Imf::Header& header = file.header();
  const Imf::ChannelList& list = header.channels();
  for (auto it = list.begin(); it != list.end(); ++it)
    if (it.channel().xSampling != 1 || it.channel().ySampling != 1) return false;  // luminance/chroma

  const Imath::Box2i window = header.dataWindow();
  const int64_t w = int64_t(window.max.x) - window.min.x + 1, h = int64_t(window.max.y) - window.min.y + 1;
  const std::vector<std::string> names = ordered_channels(list);
  if (w < 1 || h < 1 || names.empty()) throw Error("no pixels");
  const std::string problem = image_limits_problem(uint64_t(w), uint64_t(h), names.size(), 1, limits);
  if (!problem.empty()) throw Error(problem);

  out.width = int(w);
  out.height = int(h);
  out.channels = int(names.size());
  out.channel_names = names;
  out.pixels.assign(size_t(w) * size_t(h) * names.size(), 0.0f);
  // Slices address pixel (x, y) of the data window at base + x xStride + y yStride.
  const size_t x_stride = sizeof(float) * names.size(), y_stride = x_stride * size_t(w);
  char* origin = reinterpret_cast<char*>(out.pixels.data()) - ptrdiff_t(window.min.x) * ptrdiff_t(x_stride) -
                 ptrdiff_t(window.min.y) * ptrdiff_t(y_stride);
  Imf::FrameBuffer frame;
  for (size_t c = 0; c < names.size(); ++c)
    frame.insert(names[c], Imf::Slice(Imf::FLOAT, origin + c * sizeof(float), x_stride, y_stride));
  file.setFrameBuffer(frame);
  read(file, window);

  std::ostringstream d;
  d << "OpenEXR " << w << "x" << h << ", " << names.size() << " channel(s), "
    << pixel_type_name(list.findChannel(names[0])->type);
  if (header.hasTileDescription()) {
    const Imf::TileDescription tiles = header.tileDescription();
    d << ", tiled";
    if (tiles.mode == Imf::MIPMAP_LEVELS)
      d << ", " << mip_levels(int(w), int(h), tiles.roundingMode) << " mip levels (level 0 read)";
    if (tiles.mode == Imf::RIPMAP_LEVELS) d << ", rip-mapped (level 0 read)";
  }
  out.description = d.str();
  for (auto it = header.begin(); it != header.end(); ++it)
    if (const auto* a = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
      out.attributes.emplace_back(it.name(), a->value());
  return true;
}

}  // namespace

bool read_exr(const std::string& path, const ImageLimits& limits, FloatImage& out) {
  start_exr_threads();
  try {
    bool tiled = false, deep = false, multi_part = false;
    if (!Imf::isOpenExrFile(path.c_str(), tiled, deep, multi_part)) throw Error("not an OpenEXR file");
    if (deep) return false;
    // Read in parts (rows of tiles, blocks of scanlines) with a check for a stop request between
    // them: a 16k file stops within one part. The parts are large enough to keep OpenEXR's thread
    // pool busy (a ZIP block is 16 scanlines, PIZ 32).
    if (tiled && !multi_part) {
      Imf::TiledInputFile file(path.c_str());
      return read_level0(file, limits, out, [](Imf::TiledInputFile& f, const Imath::Box2i&) {
        const int rows = f.numYTiles(0), step = std::max(1, 256 / std::max(1, int(f.tileYSize())));
        for (int y = 0; y < rows; y += step) {
          throw_if_cancelled();
          f.readTiles(0, f.numXTiles(0) - 1, y, std::min(rows, y + step) - 1, 0, 0);
        }
      });
    }
    // Scanline files, and the first part of multi-part files.
    Imf::InputFile file(path.c_str());
    if (file.header().hasType() && Imf::isDeepData(file.header().type())) return false;
    return read_level0(file, limits, out, [](Imf::InputFile& f, const Imath::Box2i& window) {
      constexpr int64_t kLines = 256;
      for (int64_t y = window.min.y; y <= window.max.y; y += kLines) {
        throw_if_cancelled();
        f.readPixels(int(y), int(std::min<int64_t>(window.max.y, y + kLines - 1)));
      }
    });
  } catch (const Cancelled&) {
    throw;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {  // Iex::BaseExc and std::bad_alloc
    throw Error(std::string("truncated or corrupt OpenEXR file: ") + e.what());
  }
}

namespace {

// The OpenEXR file of write_exr into `target`: a file name, or an Imf::OStream.
template <class Target>
void write_exr_to(Target&& target, const std::string& destination, int width, int height, int channels,
                  const float* pixels, const std::vector<std::pair<std::string, std::string>>& attributes,
                  ExrCompression compression) {
  static const char* const kNames[] = {"R", "G", "B", "A"};
  if (channels < 1 || channels > 4)
    throw_write_error(destination, "OpenEXR output holds 1 to 4 channels, not " + std::to_string(channels));
  // Small images (a LUT: under 1 MiB of pixels) are stored uncompressed and on this thread: ZIP
  // saved under 2% of a 128^2 float table and cost 5 ms, about a tenth of the whole `lut` command
  // (measured); larger ones are ZIP-compressed on the thread pool.
  const bool small = compression == ExrCompression::None ||
                     size_t(width) * size_t(height) * size_t(channels) * sizeof(float) < (size_t(1) << 20);
  if (!small) start_exr_threads();
  // OpenEXR reads a ZIP file 16 scanlines a block and refuses a block above INT_MAX bytes
  // (ScanLineInputFile: "maximum bytes per scanline exceeds maximum permissible size"): `fresnel
  // --size 16777216` wrote a 16M x 1 table that no reader could open. Rows that long are compressed
  // one at a time (ZIPS: a block is a scanline).
  const size_t line_bytes = size_t(width) * size_t(channels) * sizeof(float);
  const bool long_lines = line_bytes * 16 > size_t(INT_MAX);
  if (line_bytes > size_t(INT_MAX))
    throw_write_error(destination, "a row of " + std::to_string(line_bytes) +
                                       " bytes: OpenEXR reads rows of at most 2 GiB (give fewer cells a row)");
  try {
    Imf::Header header(width, height);
    header.compression() = small ? Imf::NO_COMPRESSION : long_lines ? Imf::ZIPS_COMPRESSION : Imf::ZIP_COMPRESSION;
    for (int c = 0; c < channels; ++c) header.channels().insert(kNames[c], Imf::Channel(Imf::FLOAT));
    for (const auto& [key, value] : attributes) header.insert(key, Imf::StringAttribute(value));
    const size_t x_stride = sizeof(float) * size_t(channels), y_stride = x_stride * size_t(width);
    Imf::FrameBuffer frame;
    for (int c = 0; c < channels; ++c) {
      // Imf::Slice takes a non-const base; OutputFile only reads through it.
      char* base = const_cast<char*>(reinterpret_cast<const char*>(pixels)) + size_t(c) * sizeof(float);
      frame.insert(kNames[c], Imf::Slice(Imf::FLOAT, base, x_stride, y_stride));
    }
    Imf::OutputFile file(target, header);
    file.setFrameBuffer(frame);
    file.writePixels(height);
  } catch (const std::exception& e) {
    throw_write_error(destination, e.what());
  }
}

}  // namespace

void write_exr(const TempFile& temp, int width, int height, int channels, const float* pixels,
               const std::vector<std::pair<std::string, std::string>>& attributes, ExrCompression compression) {
  write_exr_to(temp.path().c_str(), temp.destination(), width, height, channels, pixels, attributes, compression);
}

std::string encode_exr(const std::string& destination, int width, int height, int channels, const float* pixels,
                       const std::vector<std::pair<std::string, std::string>>& attributes, ExrCompression compression) {
  Imf::StdOSStream out;
  write_exr_to(out, destination, width, height, channels, pixels, attributes, compression);
  return out.str();
}

}  // namespace brdfbake::io
