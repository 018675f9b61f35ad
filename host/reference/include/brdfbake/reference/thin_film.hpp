// Scalar double thin-film interference Fresnel (KHR_materials_iridescence).
//
// Belcour & Barla 2017, "A Practical Extension to Microfacet Theory for the Modeling of Varying
// Iridescence" (ACM TOG 36(4)), in the formulation of the KHR_materials_iridescence specification's
// implementation section, which glTF renderers follow: Schlick amplitudes at both interfaces,
// unpolarised, the Airy series to its second order, and the spectral integral done in Fourier space
// against Gaussian fits of the CIE 1931 colour matching functions, giving linear Rec. 709 RGB with
// negative values (out of gamut) clamped to 0. Written independently of kernels/thin_film.cl.
#pragma once

#include "brdfbake/reference/fresnel.hpp"

namespace brdfbake::reference {

struct ThinFilm {
  double outside_ior = 1.0;       // the medium the light comes from (air)
  double film_ior = 1.3;          // iridescenceIor (the extension's default)
  Rgb base_f0{0.04, 0.04, 0.04};  // the base under the film, by its F0 seen from air
};

// ((n_t - n_i) / (n_t + n_i))^2: the normal-incidence reflectance of an interface.
double thin_film_ior_to_f0(double n_t, double n_i);
// The index whose F0 against air is f0: (1 + sqrt f0) / (1 - sqrt f0), f0 clamped to [0, 0.9999]
// (the specification's guard: F0 = 1 would be an infinite index).
double thin_film_f0_to_ior(double f0);

// The colour of a phase-shifted unit spectrum: sum over the XYZ matching functions' Gaussian fits of
// their Fourier transform at the optical path difference `opd_nm`, phase `shift` per component,
// normalised so that Y(0, 0) = 1 (the integral of y-bar), then XYZ -> linear Rec. 709.
Rgb thin_film_sensitivity(double opd_nm, const Rgb& shift);

// The reflectance of the film of `thickness_nm` on the base at incidence cos_theta (from outside).
// Past the film's critical angle (film_ior < outside_ior), total internal reflection: 1.
Rgb thin_film_fresnel(double cos_theta, double thickness_nm, const ThinFilm& film);

// The m = 0 term alone: R12 + T121^2 R23 / (1 - R12 R23), the incoherent sum of the two
// interfaces, which thin_film_fresnel reaches when the film is many wavelengths thick.
Rgb thin_film_incoherent(double cos_theta, double thickness_nm, const ThinFilm& film);

}  // namespace brdfbake::reference
