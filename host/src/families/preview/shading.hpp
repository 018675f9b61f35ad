// Internal: the BRDF both renders use for a target (docs/PREVIEW.md, "The BRDF"): GGX single
// scattering with the height-correlated Smith V and Schlick's Fresnel (F0 from the material, F90 1),
// times the target's multiple-scattering compensation k(n.v), plus a Lambertian lobe of albedo
// w(n.v) x the diffuse colour:
//   f(v, l) = k(n.v) D V F(v.h) + w(n.v) / pi.
// k and w depend on v only, through the lobe's exact directional albedos A = int D V n.l and
// E_ss = F0 A + (1 - F0) B with B = int D V Fc n.l; the reference computes A and B by the DFG
// family's quadrature at each pixel's n.v, the split-sum render reads them from the bake's table as
// the engine does.
#pragma once

#include <string>
#include <vector>

#include "brdfbake/backend.hpp"
#include "brdfbake/engines.hpp"
#include "brdfbake/preview.hpp"

namespace brdfbake::detail::preview {

enum class DiffuseWeight {
  Plain,       // w = diffuse colour (generic, Babylon.js, glTF through Babylon.js)
  OneMinusE,   // w = diffuse colour (1 - E_ss) (Filament's evaluateIBL)
  FdezAguera,  // w = E_ms F_avg E_ss / (1 - F_avg E_ms) + diffuse colour (1 - E_ss + that)
               // (Fdez-Aguera 2019, the glTF-Sample-Viewer's getIBLRadianceLambertian), E_ms = 1 - A
};

struct TargetBrdf {
  bool compensation = true;  // k = 1 + F0 (1 / A - 1) (Kulla & Conty 2017 in Filament's form); else 1
  DiffuseWeight diffuse = DiffuseWeight::Plain;
  std::string text;  // the BRDF in words, for the JSON
};
// `multiscatter_table`: the bake's DFG table is ggx-multiscatter (generic applies the compensation
// only then, as docs/CONVENTIONS.md's runtime does).
TargetBrdf target_brdf(EngineTarget target, bool multiscatter_table);

// The reference radiance of one pixel from its integrals (S1, S2, Irr: kernel.hpp) and its exact
// albedos A, B, for a material. A clear coat (m.clearcoat > 0) takes `coat`, the pixel's integrals at
// the coat's alpha (its S1 = int D_coat V_coat n.l L), and the pixel's n.v for its Fresnel:
//   (1 - clearcoat Fcoat(n.v)) base + clearcoat Fcoat(n.v) S1_coat.
// A sheen (preview_has_sheen) takes `sheen`, the pixel's integrals of the Charlie lobe (S1_sheen =
// int D_Charlie V_sheen n.l L), and its exact albedo E(n.v): the base (before the coat) becomes
//   (1 - max(sheen_color) E(n.v)) base + sheen_color S1_sheen.
// An iridescent film (preview_has_iridescence) takes `film_dielectric` and `film_metal`, the pixel's
// integrals of the GGX lobe times the thin-film Fresnel over the dielectric's and the metal's F0
// (S1_film,c = int D V F_irid,c n.l L_c; iridescence.hpp's reference_films, nullptr where its weight is
// 0): the specular radiance becomes
//   (1 - iridescence) (F0 S1 + (F90 - F0) S2) + iridescence ((1 - metallic) specular S1_film,dielectric
//   + metallic S1_film,metal),
// the compensation and the diffuse weight as without the film.
Rgb reference_radiance(const TargetBrdf& brdf, const PreviewMaterial& m, double albedo, double bias,
                       const double integrals[9], double n_dot_v = 1.0, const double* coat = nullptr,
                       const double* sheen = nullptr, double sheen_albedo = 0.0,
                       const double* film_dielectric = nullptr, const double* film_metal = nullptr);

// The exact albedos (A, B) at every (n.v, roughness) pair of the grid n_dot_v x roughness, by the
// DFG family's quadrature on `backend` (bake_lut at explicit coordinates, ggx-multiscatter: the
// channels bias and albedo). Returns 2 values a pair, (n.v major... ) index (j * n_dot_v.size() + i).
std::vector<double> exact_albedos(Backend& backend, const std::vector<double>& n_dot_v,
                                  const std::vector<double>& roughness, double* device_seconds = nullptr);

// The sheen lobe's alpha: max(sheen_roughness^2, 1e-7) (the charlie table's floor, kMinAlpha).
double preview_sheen_alpha(double sheen_roughness);
// The sheen lobe's exact directional albedo E(n.v) = int D_Charlie V_sheen n.l (Estevez & Kulla's
// visibility) at every pair of n_dot_v x sheen_roughness (sheen_roughness-major), by the DFG
// family's charlie quadrature on `backend`.
std::vector<double> sheen_albedos(Backend& backend, const std::vector<double>& n_dot_v,
                                  const std::vector<double>& sheen_roughness, double* device_seconds = nullptr);

}  // namespace brdfbake::detail::preview
