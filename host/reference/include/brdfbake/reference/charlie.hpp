// The Charlie sheen distribution (Estevez & Kulla 2017) and the sheen visibilities, one small
// function per term. Scalar double, written from the papers, independently of the kernels
// (kernels/common/charlie.clh). alpha = sheen_roughness^2 (floored at kMinAlpha); cosines are with
// the normal. tests/reference/test_charlie.cpp checks each against a closed form or an integral.
#pragma once

#include "brdfbake/reference/floors.hpp"

namespace brdfbake::reference {

// Estevez & Kulla 2017 Charlie sheen distribution of a half vector at cosine n_dot_h.
double D_Charlie(double n_dot_h, double alpha);
// Estevez & Kulla 2017 fitted sheen Lambda: exp(L(cos)) below cos = 1/2, exp(2 L(1/2) - L(1 - cos))
// above, L(x) = a / (1 + b x^c) + d x + e with (a..e) interpolated by (1 - alpha)^2.
double Lambda_CharlieEstevezKulla(double n_dot_x, double alpha);
// The exponent c of that fit at this alpha: Lambda is analytic in x^c, not in x, at x = n.x -> 0 and
// at 1 - n.x -> 0, so quadratures map their panels there with powers of 1/c.
double SheenFitExponent(double alpha);
// Estevez & Kulla 2017 sheen visibility with their fitted Lambda, includes 1/(4 n.l n.v).
double V_CharlieEstevezKulla(double n_dot_v, double n_dot_l, double alpha);
// Neubelt & Pettineo 2013 cloth visibility, 1 / (4 (n.l + n.v - n.l n.v)).
double V_Neubelt(double n_dot_v, double n_dot_l);

}  // namespace brdfbake::reference
