// 8-bit RGBA PNG in memory through libpng, and Babylon.js's RGBD packing of HDR values into it
// (the format of .env faces and of EXT_lights_image_based's 4-channel PNGs).
//
// RGBD, as Babylon.js's helperFunctions.fx toRGBD/fromRGBD define it:
//   encode: m = max(max(r, g, b), 1e-7); D = clamp(floor(max(255 / m, 1)) / 255, 0, 1);
//           rgb' = clamp((rgb D)^(1/2.2), 0, 1); alpha = D
//   decode: rgb = rgb'^2.2 / alpha
// with every channel stored as round(255 x) in 8 bits. D = k / 255 is exact in 8 bits (k = 1..255),
// so the only rounding is that of the three gamma-encoded channels; values above 255 (where
// D = 1/255 and rgb D > 1) are clamped: the format's range is [0, 255].
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace brdfbake::io {

inline constexpr double kRgbdMaxValue = 255.0;

// PNG of width x height RGBA 8-bit pixels (row 0 first), no colour-space chunks (no gAMA, sRGB,
// iCCP: browsers must hand the bytes to WebGL unchanged). Throws Error on a libpng failure.
std::vector<uint8_t> encode_png_rgba8(int width, int height, const std::vector<uint8_t>& rgba);
// Decodes any 8-bit RGBA PNG (what encode_png_rgba8 writes); throws Error for anything else.
std::vector<uint8_t> decode_png_rgba8(const uint8_t* data, size_t size, int* width, int* height);

// One texel; `clamped` (when given) is set when a channel exceeded kRgbdMaxValue.
void rgbd_encode(const float rgb[3], uint8_t out[4], bool* clamped = nullptr);
void rgbd_decode(const uint8_t in[4], double rgb[3]);
// The largest error rounding can make in channel c of an encoded texel: half the step between the
// neighbouring 8-bit codes, decoded.
double rgbd_half_step(const uint8_t in[4], int channel);

}  // namespace brdfbake::io
