// The reference render of a material preview by brute force (the double reference that checks
// kernels/preview.cl): for one pixel, a normal n and a view direction v, the integrals
//   S1 = int D V (n.l)+ L dl,   S2 = int D V (1 - v.h)^5 (n.l)+ L dl,   Irr = int (n.l)+ L dl
// over an equirect environment whose pixels are constant over their cells of longitude x latitude
// (docs/CONVENTIONS.md's mapping), with GGX's D and the height-correlated Smith V
// (brdfbake/reference/ggx.hpp). Every pixel of the image is visited, split into q x q sub-cells
// where the lobe or the horizon of n needs it, and each sub-cell is summed at its centre in (u, v)
// with its exact solid angle: a different quadrature from the kernel's quadtree walk, sharing no
// code with it. `sheen`: the Charlie lobe (D_Charlie, V_CharlieEstevezKulla: brdfbake/reference/
// charlie.hpp) instead of GGX, S2 = 0, no refinement near r (the lobe lies along the horizon, where
// the pixels across it are split). alpha = 0 is the mirror: S1 = L(r), S2 = (1 - n.v)^5 L(r), exactly.
// `film` (KHR_materials_iridescence): the GGX lobe times the thin-film Fresnel per channel,
// S1_c = int D V F_irid,c(v.h) (n.l)+ L_c dl with F_irid = thin_film_fresnel(v.h, thickness, film)
// (brdfbake/reference/thin_film.hpp), S2 = 0; the mirror S1_c = F_irid,c(n.v) L_c(r).
#pragma once

#include <array>

#include "brdfbake/math/types.hpp"
#include "brdfbake/reference/thin_film.hpp"

namespace brdfbake::reference {

struct PreviewIntegrals {
  std::array<double, 3> s1{}, s2{}, irr{};
};

// rgb: width x height x 3 linear floats, row 0 first (width = 2 height). n, v any length (normalised
// here), n.v > 0.
// `subdivision` sets the sub-cells: a pixel within the lobe is split until a sub-cell is below
// max(2 alpha, its distance to r) / subdivision, a pixel across the horizon of n into
// subdivision x subdivision; doubling it measures the convergence (tests/reference).
struct PreviewFilm {
  ThinFilm film;
  double thickness_nm = 400.0;
};
PreviewIntegrals preview_integrals(const float* rgb, int width, int height, const Vec3& n, const Vec3& v, double alpha,
                                   double subdivision = 16.0, bool sheen = false, const PreviewFilm* film = nullptr);

// The number of lobe evaluations preview_integrals makes for one pixel (its work).
double preview_integrals_work(int width, int height, double alpha, double subdivision = 16.0, bool sheen = false);

}  // namespace brdfbake::reference
