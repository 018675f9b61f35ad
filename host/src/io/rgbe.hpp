// Radiance RGBE pictures (".hdr"), decoded from and encoded to memory.
//
// The format (Greg Ward, "Radiance File Formats", section "Picture File Format"; Ward, "Real
// Pixels", Graphics Gems II, 1991):
//   header     "#?PROGRAM" (usually "#?RADIANCE" or "#?RGBE"), then lines up to an empty line;
//              "FORMAT=32-bit_rle_rgbe" names the pixel encoding (RGBE is assumed when absent;
//              32-bit_rle_xyze is refused: it holds CIE XYZ, not RGB). Other lines (EXPOSURE,
//              comments, commands) are kept out of the pixels: like OpenImageIO and stb_image we
//              return the stored values, not values divided by EXPOSURE.
//   resolution one line "-Y N +X M" (the usual top-to-bottom, left-to-right order) or any of the
//              eight orders the format defines ("+Y N -X M", "+X M -Y N", ...): the first axis
//              runs across scanlines, the second along them; Y points up, X to the right.
//   scanlines  one per value of the first axis, each either
//                new run-length encoded (scanline length 8..0x7fff): bytes 2, 2, then the length
//                  (big-endian, high bit clear), then the four components one after the other,
//                  each as runs (a byte n > 128: the next byte repeated n - 128 times) and dumps
//                  (a byte n <= 128: n bytes follow);
//              or flat 4-byte pixels, where a pixel (1, 1, 1, n) repeats the previous pixel
//                  n << s times ("old" run-length encoding; s grows by 8 over consecutive repeats).
//   pixel      (R, G, B, E): E = 0 is black, else channel = mantissa * 2^(E - 136). This is the
//              convention of OpenImageIO, stb_image and Bruce Walter's rgbe.c; Radiance's own
//              colr_color adds 0.5 to the mantissa (the bucket centre). We keep the former so that
//              black stays black and values read exactly as OpenImageIO read them before.
// Encoding writes "#?RADIANCE", FORMAT and "-Y H +X W", new run-length encoded scanlines for
// widths 8..0x7fff and flat pixels otherwise, each channel as floor(c * 256 / 2^e) under the
// exponent e of frexp(max(R, G, B)) (Ward's float2rgbe).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "io/image_limits.hpp"

namespace brdfbake::io {

// The largest value RGBE holds: mantissa 255 under exponent byte 255, (255 / 256) * 2^127.
inline constexpr float kRgbeMax = 0x1.FEp126f;

struct RgbeImage {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;           // width x height x 3, row 0 the top row
  std::string orientation;          // the resolution line's order, e.g. "-Y +X"
  bool run_length_encoded = false;  // some scanline used new run-length encoding
  double exposure = 1.0;            // the product of the header's EXPOSURE= lines (not applied)
};

// The longest header read (Radiance headers hold a few lines of history and options).
inline constexpr std::size_t kRgbeMaxHeaderBytes = std::size_t(64) << 10;

// Whether `bytes` start with the "#?" signature of a Radiance picture.
bool is_rgbe(std::string_view bytes);

// The most bytes a picture whose file starts with `head` (at least its header and resolution line,
// up to kRgbeMaxHeaderBytes) can take: its header and the worst encoding of every scanline. What
// follows is never read. When `head` does not hold a valid header, head.size() (decode_rgbe then
// says what is wrong). Counts are checked before any arithmetic: a width that does not fit 32 bits
// is refused, never wrapped.
std::uint64_t rgbe_file_bound(std::string_view head);

// Decodes a whole picture. Throws Error(reason) for a bad header, a truncated or corrupt file,
// or an image beyond `limits`; the reason does not name the file. A header promising more
// scanlines than the data can hold (each takes at least 4 bytes) is refused before the pixels are
// allocated.
RgbeImage decode_rgbe(std::string_view bytes, const ImageLimits& limits = {});

// Encodes width x height RGB floats (row 0 the top row). Values must be finite and in
// [0, kRgbeMax]: callers clamp and count (a value outside throws Error).
std::string encode_rgbe(int width, int height, const float* rgb);

// One pixel, exposed for the tests: float -> RGBE bytes and back.
void float_to_rgbe(const float rgb[3], uint8_t out[4]);
void rgbe_to_float(const uint8_t rgbe[4], float out[3]);

}  // namespace brdfbake::io
