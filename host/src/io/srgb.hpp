// The sRGB transfer functions (IEC 61966-2-1:1999, the piecewise curve, not a 2.2 power): the one
// definition that every reader decoding an 8-bit sRGB image, the preview's texture means and the
// pictures' encoders use.
#pragma once

#include <cmath>

namespace brdfbake::io {

// An encoded value in [0, 1] to linear.
inline double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }
// A linear value in [0, 1] to its encoding.
inline double linear_to_srgb(double c) { return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055; }

}  // namespace brdfbake::io
