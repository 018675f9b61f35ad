// Scalar double-precision microfacet terms, one small function per physical term.
// alpha is the distribution's width (alpha = roughness^2); cosines are with the normal.
#pragma once

namespace brdfbake::reference {

// Alpha floor, the kernels' BRDFBAKE_MIN_ALPHA (docs/CONVENTIONS.md): at alpha = 0 GGX's D is a
// Dirac delta (0/0 at n.h = 1) and Charlie's exponent 1/alpha overflows.
inline constexpr double kMinAlpha = 1e-7;
// Cosine floor of the visibility terms, which all contain 1/(n.l n.v): GGX's and Neubelt's diverge
// only when both cosines vanish, Estevez-Kulla's whenever one does (its fitted Lambda saturates at
// exp(a + e) instead of growing like 1/cos). The floor only turns an exact 0 into a finite value:
// integrators evaluate these terms at cosines down to ~1e-25 next to the horizon, and a clamp
// there would put a kink into the integrand. Products of two floors stay normal doubles.
inline constexpr double kMinCosine = 1e-100;

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
// Schlick 1994, with F90.
double F_Schlick(double f0, double f90, double v_dot_h);
// Burley 2012 diffuse, including 1/pi.
double Fd_Burley(double n_dot_v, double n_dot_l, double l_dot_h, double roughness);
// Burley 2012 diffuse for a given grazing retro-reflection F_D90 (Fd_Burley computes
// F_D90 = 0.5 + 2 roughness (l.h)^2 and calls this), including 1/pi.
double Fd_BurleyF90(double n_dot_v, double n_dot_l, double f_d90);
// Estevez & Kulla 2017 Charlie sheen distribution.
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
