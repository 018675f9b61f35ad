// The floors of the reference's microfacet terms: the shared alpha floor (a convention of every
// table, docs/CONVENTIONS.md) and the visibility terms' cosine floor.
#pragma once

#include "brdfbake/math/conventions.hpp"

namespace brdfbake::reference {

// Alpha floor, the kernels' BRDFBAKE_MIN_ALPHA (brdfbake/math/conventions.hpp).
using math::kMinAlpha;
// Cosine floor of the visibility terms, which all contain 1/(n.l n.v): GGX's and Neubelt's diverge
// only when both cosines vanish, Estevez-Kulla's whenever one does (its fitted Lambda saturates at
// exp(a + e) instead of growing like 1/cos). The floor only turns an exact 0 into a finite value:
// integrators evaluate these terms at cosines down to ~1e-25 next to the horizon, and a clamp
// there would put a kink into the integrand. Products of two floors stay normal doubles.
inline constexpr double kMinCosine = 1e-100;

}  // namespace brdfbake::reference
