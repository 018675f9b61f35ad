// Scalar double-precision Fresnel reflectance, one small function per model.
//
// Written from the physics, independently of kernels/fresnel.cl. Conventions (docs/CONVENTIONS.md):
// angles are named by their cosine with the normal; a cosine a hair outside [0, 1] from upstream
// rounding is clamped into it (never NaN). Reflectances are unpolarised (the mean of the s and p
// intensities) unless the name says otherwise. `eta` is always the index of the far side relative
// to the side the light comes from: eta = n_t / n_i (so eta < 1 is internal reflection).
#pragma once

#include <functional>

#include "brdfbake/math/types.hpp"

namespace brdfbake::reference {

// Intensity reflectances for s- (TE, perpendicular) and p- (TM, parallel) polarisation.
struct Polarized {
  double s, p;
};

// ---- Schlick and its parameterisations -------------------------------------------------------

// Schlick 1994, "An Inexpensive BRDF Model for Physically-based Rendering", eq. 24, with F90.
double fresnel_schlick(double cos_theta, double f0, double f90 = 1.0);
Rgb fresnel_schlick(double cos_theta, const Rgb& f0, const Rgb& f90 = Rgb{1.0, 1.0, 1.0});
// The same term with the argument order of the shading-model code (Filament's F_Schlick(f0, f90,
// VoH)), as the BRDF models compose it.
double F_Schlick(double f0, double f90, double v_dot_h);

// Normal-incidence reflectance between two dielectrics: ((n1 - n2) / (n1 + n2))^2.
double f0_from_ior(double n1, double n2);

// Burley 2012 / glTF 2.0 core metallic-roughness: F0 = mix(dielectric_f0, base_color, metallic).
Rgb schlick_metallic_f0(const Rgb& base_color, double metallic, double dielectric_f0 = 0.04);

// ---- Exact Fresnel equations -----------------------------------------------------------------

// Born & Wolf, "Principles of Optics", sec. 1.5.2: exact reflectance of a smooth interface between
// two dielectrics, eta = n_t / n_i > 0. eta < 1 includes total internal reflection (exactly 1
// past the critical angle, continuous at it); eta == 1 is no interface (exactly 0).
Polarized fresnel_dielectric_sp(double cos_theta_i, double eta);
double fresnel_dielectric(double cos_theta_i, double eta);

// Born & Wolf sec. 14.2: exact reflectance of an absorbing medium with complex relative index
// eta + i k (k >= 0), seen from a dielectric. k = 0 and eta >= 1 equals fresnel_dielectric.
Polarized fresnel_conductor_sp(double cos_theta_i, double eta, double k);
double fresnel_conductor(double cos_theta_i, double eta, double k);
Rgb fresnel_conductor(double cos_theta_i, const Rgb& eta, const Rgb& k);

// ---- Artist-facing approximations --------------------------------------------------------------

// Hoffman 2023, "Generalization of Adobe's Fresnel Model" (the "F82-tint" model of OpenPBR's metal
// and the Adobe Standard Material): Schlick (F90 = 1) minus a correction a cos(1 - cos)^6 chosen so
// that F(1/7) = f82_tint * Schlick(1/7); 1/7 is cos 81.8 deg. f82_tint = 1 is plain Schlick.
double fresnel_f82_tint(double cos_theta, double f0, double f82_tint);
Rgb fresnel_f82_tint(double cos_theta, const Rgb& f0, const Rgb& f82_tint);

// The cosine the F82-tint model is pinned at, 1/7 (about 82 degrees).
inline constexpr double kF82Cos = 1.0 / 7.0;

// Fernando & Kilgard 2003, "The Cg Tutorial", eq. 7-3:
// R = max(0, min(1, bias + scale (1 + I.N)^power)), with I.N = -cos_theta (I points at the surface).
double fresnel_empirical(double cos_theta, double bias, double scale, double power);

// ---- Fits --------------------------------------------------------------------------------------

// The Schlick F0 that reproduces a conductor at normal incidence: ((n-1)^2 + k^2) / ((n+1)^2 + k^2).
double schlick_f0_from_conductor(double eta, double k);
Rgb schlick_f0_from_conductor(const Rgb& eta, const Rgb& k);

// The f82_tint that makes fresnel_f82_tint(cos, schlick_f0_from_conductor(eta, k), tint) equal the
// exact conductor at cos = 1/7. It exceeds 1 where the conductor is above Schlick there.
double fit_f82_tint(double eta, double k);
Rgb fit_f82_tint(const Rgb& eta, const Rgb& k);

// Error left by an approximation against an exact model, over cos_theta on a uniform grid of
// `samples` points covering [0, 1] including both ends (samples >= 2).
struct FresnelFitError {
  double max_abs;     // max |approx - exact| over the grid
  double mean_abs;    // arithmetic mean of |approx - exact| over the grid points
  double cos_at_max;  // the grid cosine where max_abs occurs (the first, on ties)
};
inline constexpr int kFitErrorSamples = 4097;
FresnelFitError fresnel_fit_error(const std::function<double(double)>& approx,
                                  const std::function<double(double)>& exact, int samples = kFitErrorSamples);

}  // namespace brdfbake::reference
