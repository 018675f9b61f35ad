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
#include "common/thin_film.clh"

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
