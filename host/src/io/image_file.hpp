// Image files. The formats on the hot path go through focused libraries, linked into the program:
//   OpenEXR (.exr, read and write)       OpenEXR 3.1 (Imf), float32 written uncompressed below 1 MiB, ZIP above
//   PNG (.png, 16-bit write; read)       libpng (read: decoded to linear, read_png_linear)
//   Radiance RGBE (.hdr, read and write) io/rgbe (a small codec: stb_image hangs or returns black
//                                        on truncated files, see rgbe.hpp)
// Every other format is read through OpenImageIO, which lives in a separate module
// (brdfbake_oiio.so, io/oiio_module.hpp) loaded with dlopen the first time such a file is read:
// a program that never reads one never loads OpenImageIO and its few hundred libraries.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "io/atomic_file.hpp"
#include "io/image_limits.hpp"

namespace brdfbake::io {

// Level 0 of the first image of a file, as float.
struct FloatImage {
  int width = 0;
  int height = 0;
  int channels = 0;
  // The file's channel names (may be empty where the format has none), in OpenImageIO's order:
  // R, G, B, A first when present, then the others as the file lists them.
  std::vector<std::string> channel_names;
  std::vector<float> pixels;  // width x height x channels, row 0 (the top row) first
  // e.g. "OpenEXR 1024x512, 3 channel(s), half, tiled, 11 mip levels (level 0 read)"
  std::string description;
  // The file's string attributes (OpenEXR; empty for the other formats), in the file's order.
  std::vector<std::pair<std::string, std::string>> attributes;
  // What the reader did to the values that the user should hear of, e.g. "8-bit sRGB (untagged PNG:
  // sRGB assumed) decoded to linear". Empty for files that hold linear values.
  std::string transfer_note;
};

// Reads an image, choosing the reader by the file's signature (its first bytes): OpenEXR
// (scanline or tiled, mip-mapped or not, half, float or uint; not subsampled luminance/chroma or
// deep data, which go to OpenImageIO), Radiance RGBE and PNG here, any other format through the
// OpenImageIO module. A FIFO or a device is refused (decoders seek); every read stops on a stop
// request (brdfbake/cancel.hpp) between parts of the file. An image beyond `limits` (pixels, or the memory its decoding
// takes) is refused from its header, before any pixel buffer is allocated. Throws Error with a one-line reason that
// does not repeat the path (callers say what the file was for), e.g. "truncated: the data ends in scanline 17", or, for
// a format only OpenImageIO reads when the module cannot be loaded, "... needs the OpenImageIO module ...: <why>".
FloatImage read_image(const std::string& path, const ImageLimits& limits);

// The OpenEXR reader behind read_image: whether `head` (the first bytes of a file) is OpenEXR's
// magic number, and the file read into `out`. Returns false, reading nothing, for the variants
// left to OpenImageIO (deep data, subsampled channels); throws Error(reason) for a bad file.
bool is_exr(std::string_view head);
bool read_exr(const std::string& path, const ImageLimits& limits, FloatImage& out);

// The PNG reader behind read_image (libpng, png_image.cpp): any PNG as linear float. The transfer
// the file states is undone: the sRGB chunk (or an ICC profile libpng recognises as sRGB), an iCCP
// profile named sRGB or linear, else gAMA; an 8-bit PNG without any of them is sRGB (the convention
// for untagged images), a 16-bit one is read as stored (tables and measurements are linear), and
// FloatImage::transfer_note says which. An ICC profile it cannot tell, without gAMA, is refused.
// Alpha stays as stored.
// Checked against `limits` from the header, read row by row (a stop request ends it between rows);
// libpng's messages become the Error's reason, never stderr lines.
bool is_png(std::string_view head);
FloatImage read_png_linear(const std::string& path, const ImageLimits& limits);

// Writers: each fills the temporary `temp` (the caller commits it) and throws
// Error("cannot write '<destination>': <reason>").
//
// OpenEXR: `channels` (1..4) float32 channels named R, G, B, A in that order (BySize: uncompressed
// below 1 MiB of pixels, ZIP above; None: uncompressed), every attribute a string attribute (keys as
// given).
enum class ExrCompression {
  BySize,
  // Float radiance with noise in every bit (a render): ZIP saved 7 % of a 512 x 512 preview image
  // for 0.1 s of CPU, half the preview's whole process (measured).
  None,
};
void write_exr(const TempFile& temp, int width, int height, int channels, const float* pixels,
               const std::vector<std::pair<std::string, std::string>>& attributes,
               ExrCompression compression = ExrCompression::BySize);
// The same file's bytes, in memory (errors name `destination`): what POST /v1/tables sends.
std::string encode_exr(const std::string& destination, int width, int height, int channels, const float* pixels,
                       const std::vector<std::pair<std::string, std::string>>& attributes,
                       ExrCompression compression = ExrCompression::BySize);
// PNG: 16-bit grey (1 channel), RGB (3) or RGBA (4, straight alpha), gAMA 1.0 (linear data, no
// sRGB chunk), every text entry a tEXt chunk (iTXt, UTF-8, where a value is not plain ASCII).
// Keywords must be 1 to 79 bytes (checked by the caller, who knows the prefix).
void write_png16(const TempFile& temp, int width, int height, int channels, const uint16_t* pixels,
                 const std::vector<std::pair<std::string, std::string>>& text);
// Radiance RGBE: RGB values, finite and in [0, kRgbeMax] (rgbe.hpp; callers clamp and count).
void write_rgbe(const TempFile& temp, int width, int height, const float* rgb);

}  // namespace brdfbake::io
