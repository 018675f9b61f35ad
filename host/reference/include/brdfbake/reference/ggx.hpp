// The GGX (Trowbridge-Reitz) microfacet distribution, one small function per term: D, Smith Lambda,
// G1, the height-correlated G2 and the visibility V = G2 / (4 n.l n.v), isotropic and anisotropic.
// Scalar double, written from the papers, independently of the kernels (kernels/common/ggx.clh).
// alpha is the distribution's width (alpha = roughness^2, floored at kMinAlpha); cosines are with
// the normal. tests/reference/test_ggx.cpp checks each against a closed form or an integral.
#pragma once

#include "brdfbake/math/types.hpp"
#include "brdfbake/reference/floors.hpp"

namespace brdfbake::reference {

// Trowbridge & Reitz 1975 / Walter et al. 2007 (GGX) normal distribution.
double D_GGX(double n_dot_h, double alpha);
// Heitz 2014, Smith Lambda of GGX for a direction at cosine n_dot_x with the normal.
double Lambda_GGX(double n_dot_x, double alpha);
// Heitz 2014, Smith masking of GGX, G1 = 1 / (1 + Lambda).
double G1_SmithGGX(double n_dot_x, double alpha);
// Heitz 2014 height-correlated masking-shadowing, G2 = 1 / (1 + Lambda(v) + Lambda(l)).
double G2_SmithGGXCorrelated(double n_dot_v, double n_dot_l, double alpha);
// The same divided by 4 n.l n.v, so that f_spec = D * V * F.
double V_SmithGGXCorrelated(double n_dot_v, double n_dot_l, double alpha);

// Burley 2012, appendix B eq. 13: anisotropic GGX (GTR2) for a unit half vector h in tangent space
// (normal +z, alpha_x along +x).
double D_GGXAniso(const Vec3& h, double alpha_x, double alpha_y);
// Heitz 2014, eq. 86: anisotropic GGX Smith masking of a direction with cosine n_dot_x (floored by
// the caller) and tangent-plane components t_dot_x, b_dot_x.
double G1_SmithGGXAniso(double n_dot_x, double t_dot_x, double b_dot_x, double alpha_x, double alpha_y);

}  // namespace brdfbake::reference
