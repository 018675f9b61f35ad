// Thin-film interference Fresnel (KHR_materials_iridescence): a table over (cos_theta, thickness).
//
// Belcour & Barla 2017, "A Practical Extension to Microfacet Theory for the Modeling of Varying
// Iridescence", in the formulation of the KHR_materials_iridescence specification (Schlick
// amplitudes at both interfaces, unpolarised, Airy series to m = 2, the spectral integral in
// Fourier space against Gaussian fits of the CIE 1931 matching functions, linear Rec. 709, clamped
// at 0). The derivation is written out above host/reference/src/thin_film.cpp, the oracle.
//
// params (real): outside_ior, film_ior, base_f0 r, g, b.
// Work-item (i, j) computes cell (xs[i], ys[j]): cos_theta, thickness in nm.
// Output: floats, row-major, channels r, g, b interleaved: out[(j * width + i) * 3 + c].
#include "common/real.clh"
#include "common/fresnel.clh"

// The index whose normal-incidence reflectance against 1 is f0 (the inverse of f0_from_ior),
// f0 capped below 1.
inline real thin_film_f0_to_ior(real f0) {
  const real s = sqrt(clamp(f0, R(0.0), R(0.9999)));
  return (R(1.0) + s) / (R(1.0) - s);
}

// The XYZ matching functions' Gaussian fits, Fourier transformed at the optical path difference,
// normalised to Y(0, 0) = 1, to linear Rec. 709.
inline real3 thin_film_sensitivity(real opd_nm, real3 shift) {
  const real phase = R(2.0) * BRDFBAKE_PI * opd_nm * R(1.0e-9);
  const real3 val = (real3)(R(5.4856e-13), R(4.4201e-13), R(5.2481e-13));
  const real3 pos = (real3)(R(1.6810e+06), R(1.7953e+06), R(2.2084e+06));
  const real3 var = (real3)(R(4.3278e+09), R(9.3046e+09), R(6.6121e+09));
  real3 xyz = val * sqrt(R(2.0) * BRDFBAKE_PI * var) * cos(pos * phase + shift) * exp(-(phase * phase) * var);
  xyz.x += R(9.7470e-14) * sqrt(R(2.0) * BRDFBAKE_PI * R(4.5282e+09)) * cos(R(2.2399e+06) * phase + shift.x) *
           exp(R(-4.5282e+09) * phase * phase);
  xyz /= R(1.0685e-7);
  return (real3)(R(3.2404542) * xyz.x - R(1.5371385) * xyz.y - R(0.4985314) * xyz.z,
                 R(-0.9692660) * xyz.x + R(1.8760108) * xyz.y + R(0.0415560) * xyz.z,
                 R(0.0556434) * xyz.x - R(0.2040259) * xyz.y + R(1.0572252) * xyz.z);
}

inline real3 thin_film_fresnel(real cos1, real thickness, real outside_ior, real film_ior_in, real3 base_f0) {
  cos1 = clamp(cos1, R(0.0), R(1.0));
  // The film fades into the outside medium over its first 0.03 nm (no interference at 0).
  const real film_ior = mix(outside_ior, film_ior_in, smoothstep(R(0.0), R(0.03), thickness));
  const real ratio = outside_ior / film_ior;
  const real cos2_sq = R(1.0) - ratio * ratio * (R(1.0) - cos1 * cos1);
  if (cos2_sq < R(0.0)) return (real3)(R(1.0), R(1.0), R(1.0));  // total internal reflection
  const real cos2 = sqrt(cos2_sq);

  const real r12 = fresnel_schlick(cos1, f0_from_ior(film_ior, outside_ior), R(1.0));
  const real t121 = R(1.0) - r12;
  const real phi21 = film_ior < outside_ior ? R(0.0) : BRDFBAKE_PI;  // pi - phi12

  const real3 base_ior = (real3)(thin_film_f0_to_ior(base_f0.x), thin_film_f0_to_ior(base_f0.y), thin_film_f0_to_ior(base_f0.z));
  const real3 r23 = (real3)(fresnel_schlick(cos2, f0_from_ior(base_ior.x, film_ior), R(1.0)),
                            fresnel_schlick(cos2, f0_from_ior(base_ior.y, film_ior), R(1.0)),
                            fresnel_schlick(cos2, f0_from_ior(base_ior.z, film_ior), R(1.0)));
  const real3 phi23 = (real3)(base_ior.x < film_ior ? BRDFBAKE_PI : R(0.0),
                              base_ior.y < film_ior ? BRDFBAKE_PI : R(0.0),
                              base_ior.z < film_ior ? BRDFBAKE_PI : R(0.0));

  const real opd = R(2.0) * film_ior * thickness * cos2;
  const real3 phi = phi21 + phi23;
  const real3 r123 = clamp(r12 * r23, R(1e-5), R(0.9999));
  const real3 amplitude = sqrt(r123);
  const real3 rs = t121 * t121 * r23 / (R(1.0) - r123);
  real3 intensity = r12 + rs;  // C0, the incoherent sum
  real3 cm = rs - t121;
  for (int m = 1; m <= 2; ++m) {
    cm *= amplitude;
    intensity += cm * R(2.0) * thin_film_sensitivity((real)m * opd, (real)m * phi);
  }
  return fmax(intensity, (real3)(R(0.0), R(0.0), R(0.0)));
}

kernel void thin_film_table(global float* out, global const real* xs, global const real* ys, const int width,
                            const int height, global const real* params) {
  const int i = (int)get_global_id(0), j = (int)get_global_id(1);
  if (i >= width || j >= height) return;
  const real3 base_f0 = (real3)(params[2], params[3], params[4]);
  const real3 f = thin_film_fresnel(xs[i], ys[j], params[0], params[1], base_f0);
  const size_t at = ((size_t)j * (size_t)width + (size_t)i) * 3;
  out[at + 0] = (float)f.x;
  out[at + 1] = (float)f.y;
  out[at + 2] = (float)f.z;
}
