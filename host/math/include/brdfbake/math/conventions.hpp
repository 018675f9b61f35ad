// The numerical conventions that the kernels, the engine and the reference must share exactly
// (docs/CONVENTIONS.md): floors and ranges that define what a table holds, not how it is computed.
#pragma once

namespace brdfbake::math {

inline constexpr double kPi = 3.14159265358979323846;

// Alpha floor of every microfacet width (the kernels' BRDFBAKE_MIN_ALPHA): at alpha = 0 GGX's D is
// a Dirac delta (0/0 at n.h = 1) and Charlie's exponent 1/alpha overflows.
inline constexpr double kMinAlpha = 1e-7;
// Burley 2012's own floor of the anisotropic GGX widths of the Disney BRDF (disney.brdf:
// max(.001, ...)).
inline constexpr double kDisneyMinAlpha = 1e-3;
// The floor of n.l and n.v above the horizon in BRDF evaluation: a direction within 1e-7 rad of
// the horizon is evaluated as if it were 1e-7 above it, so every term divided by a cosine stays
// finite in fp32 as in double (its contribution to any integral is below 1e-7 of the lobe's).
inline constexpr double kBrdfMinCosine = 1e-7;
// The largest Phong / Blinn-Phong exponent accepted; the lobe is then 0.1 degree wide.
inline constexpr double kMaxShininess = 1e6;

}  // namespace brdfbake::math
