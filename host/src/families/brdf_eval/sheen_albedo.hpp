// Internal: KHR_materials_sheen's albedo E(mu) as the engine computes it for the kernels
// (kernels/common/brdf_params.clh): its own quadrature of the Charlie lobe's directional albedo, the
// Chebyshev series on the kernels' panels, and the cubic pieces the kernels evaluate. Independent of
// the reference's charlie_albedo (host/reference/src/dfg_lut.cpp), so that tests/device/test_brdf_eval.cpp
// (device against reference) can catch a mistake on either side.
#pragma once

#include <vector>

namespace brdfbake::detail {

// Estevez & Kulla 2017, "Production Friendly Microfacet Sheen BRDF", table 1: their fitted
// L(x) = a / (1 + b x^c) + d x + e of the sheen Lambda, the r = 0 and r = 1 sets interpolated with
// weight (1 - r)^2 on the r = 0 set, r = alpha (KHR_materials_sheen). Lambda(x) = exp(L(x)) below
// x = 1/2, exp(2 L(1/2) - L(1 - x)) above.
struct EstevezKullaFit {
  double a, b, c, d, e;
};
EstevezKullaFit estevez_kulla_fit(double alpha);

// E(mu) = int D_Charlie(h) V_EstevezKulla(l, v) (n.l) dl over the hemisphere (sheen colour 1), for
// n.v = mu in [1e-7, 1] (mu below 1e-7 is evaluated at 1e-7, the kernels' cosine floor) and
// alpha = max(sheen_roughness^2, 1e-7); converged to ~1e-13 relative (sheen_albedo.cpp says how).
double sheen_albedo_quadrature(double mu, double sheen_roughness);

// The kernels' table of E(mu) for one sheen roughness: BRDF_SHEEN_LOWER + BRDF_SHEEN_UPPER panels of
// BRDF_SHEEN_PIECES cubic pieces, 4 monomial coefficients each (common/brdf_params.clh), built from
// the Chebyshev series of E on each panel. Computed once per sheen roughness per process (~0.5 s on
// two cores) and cached; thread-safe.
const std::vector<double>& sheen_albedo_pieces(double sheen_roughness);

}  // namespace brdfbake::detail
