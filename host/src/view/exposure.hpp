// The exposure a picture of HDR radiance is shown at when none is asked for (`brdfbake view`, the
// preview family): chosen from the picture's own content, so that a map with a sun (rooitou_park:
// luminance 65 000 over a sky near 1) is neither blown out at its blurred levels nor black at its
// sharp one.
//
// Rule: the photographic key of Reinhard et al. 2002 ("Photographic Tone Reproduction for Digital
// Images", section 3.1): the exposure that brings the log-average luminance (Rec. 709 weights,
// the geometric mean over the texels, each floored at 1e-4 of the 99th percentile so that black
// texels do not pull it to zero) to middle grey, 0.18 — unless that would push the 99th percentile
// above 1.0 (what the ACES curve shows at 80 % of white, 232 of 255 in sRGB), when the exposure is
// lowered until it is 1.0, so the brightest percent keeps its shading. Rounded down to a tenth of an EV, so that the
// caption states it exactly. Why both: the log-average follows what most of the picture holds (the sky of a sharp
// level, the glow of a blurred one), and a sun that covers far less than 1 % of a sharp level clips, as in a photograph
// of it; the 99th-percentile limit keeps the top percent readable where a glow or a bright side dominates (a blurred
// level, the sunny side of an SH sphere), where a key alone would paint it white.
//
// It is chosen per picture (a cube level, an SH sphere pair, an HDR image), not per sheet: the
// levels of one chain differ by orders of magnitude in their top percent (the sun's energy is
// concentrated at level 0 and spread at the last), and one exposure for all would show either the
// sharp levels black or the blurred ones white. Each caption says the EV it was drawn at.
#pragma once

#include <cstddef>

namespace brdfbake::view {

inline constexpr double kAutoExposureKey = 0.18;   // the log-average luminance is shown as middle grey
inline constexpr double kAutoExposureWhite = 1.0;  // the 99th percentile is shown at most this bright
// The automatic exposure lies in [-kAutoExposureLimit, kAutoExposureLimit] EV.
inline constexpr double kAutoExposureLimit = 32.0;

// The automatic exposure in EV of `texels` RGB texels starting at `rgb`, `stride` floats apart
// (3 for RGB, 4 for RGBA); non-finite and negative luminances are left out. 0 when no texel is
// brighter than zero.
double auto_exposure(const float* rgb, size_t texels, size_t stride);

}  // namespace brdfbake::view
