// Burley's (Disney 2012) diffuse lobes, one small function per term, including 1/pi. Scalar double,
// written from the paper and disney.brdf, independently of the kernels. tests/reference/test_burley.cpp
// checks them against spot values and closed-form albedos.
#pragma once

namespace brdfbake::reference {

// Burley 2012 diffuse, F_D90 = 0.5 + 2 roughness (l.h)^2, roughness perceptual.
double Fd_Burley(double n_dot_v, double n_dot_l, double l_dot_h, double roughness);
// Burley 2012 diffuse for a given grazing retro-reflection F_D90 (Fd_Burley computes F_D90 and
// calls this).
double Fd_BurleyF90(double n_dot_v, double n_dot_l, double f_d90);
// Burley 2012 (disney.brdf): the Hanrahan-Krueger-inspired subsurface lobe,
// (1.25/pi) (F_ss (1/(n.l + n.v) - 0.5) + 0.5), F_ss90 = roughness (l.h)^2.
double Fd_DisneySubsurface(double n_dot_v, double n_dot_l, double l_dot_h, double roughness);

}  // namespace brdfbake::reference
