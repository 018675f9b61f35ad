// Scalar double-precision microfacet terms, one small function per physical term.
// alpha is the distribution's width (alpha = roughness^2); cosines are with the normal.
#pragma once

namespace brdfbake::reference {

// Trowbridge & Reitz 1975 / Walter et al. 2007 (GGX) normal distribution.
double D_GGX(double n_dot_h, double alpha);
// Heitz 2014, Smith Lambda of GGX for a direction at cosine n_dot_x with the normal.
double Lambda_GGX(double n_dot_x, double alpha);
// Heitz 2014 height-correlated masking-shadowing, G2 = 1 / (1 + Lambda(v) + Lambda(l)).
double G2_SmithGGXCorrelated(double n_dot_v, double n_dot_l, double alpha);
// The same divided by 4 n.l n.v, so that f_spec = D * V * F.
double V_SmithGGXCorrelated(double n_dot_v, double n_dot_l, double alpha);
// Schlick 1994, with F90.
double F_Schlick(double f0, double f90, double v_dot_h);
// Burley 2012 diffuse, including 1/pi.
double Fd_Burley(double n_dot_v, double n_dot_l, double l_dot_h, double roughness);
// Estevez & Kulla 2017 Charlie sheen distribution.
double D_Charlie(double n_dot_h, double alpha);
// Estevez & Kulla 2017 sheen visibility with their fitted Lambda, includes 1/(4 n.l n.v).
double V_CharlieEstevezKulla(double n_dot_v, double n_dot_l, double alpha);
// Neubelt & Pettineo 2013 cloth visibility, 1 / (4 (n.l + n.v - n.l n.v)).
double V_Neubelt(double n_dot_v, double n_dot_l);

}  // namespace brdfbake::reference
