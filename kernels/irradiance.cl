// Diffuse irradiance: spherical-harmonic projection with a work-group reduction, and the irradiance
// cube by direct cosine convolution.
//
// The host defines BRDFBAKE_SH_ORDER (3 or 5 bands: 9 or 25 coefficients). The cosine convolution
// takes BRDFBAKE_ENV_COSINE, so env_point_sum's kernel is (n.l)+ / pi.
#include "common/real.clh"
#include "common/cubemap.clh"
#include "common/env_sampling.clh"

#ifndef BRDFBAKE_SH_ORDER
#define BRDFBAKE_SH_ORDER 3
#endif
#define SH_COUNT (BRDFBAKE_SH_ORDER * BRDFBAKE_SH_ORDER)
// Per work-item accumulators: 3 channels per coefficient, then the sum of solid angles.
#define SH_ACC (3 * SH_COUNT + 1)

// Real spherical harmonics without the Condon-Shortley phase (Ramamoorthi & Hanrahan 2001), index
// l (l + 1) + m, as polynomials of the unit direction; the table is in docs/CONVENTIONS.md.
inline void sh_basis(real3 d, real* y) {
  const real x = d.x, yy = d.y, z = d.z;
  const real x2 = x * x, y2 = yy * yy, z2 = z * z;
  y[0] = R(0.28209479177387814);
  y[1] = R(0.4886025119029199) * yy;
  y[2] = R(0.4886025119029199) * z;
  y[3] = R(0.4886025119029199) * x;
  y[4] = R(1.0925484305920792) * x * yy;
  y[5] = R(1.0925484305920792) * yy * z;
  y[6] = R(0.31539156525252005) * (R(3.0) * z2 - R(1.0));
  y[7] = R(1.0925484305920792) * x * z;
  y[8] = R(0.5462742152960396) * (x2 - y2);
#if BRDFBAKE_SH_ORDER > 3
  y[9] = R(0.5900435899266435) * yy * (R(3.0) * x2 - y2);
  y[10] = R(2.890611442640554) * x * yy * z;
  y[11] = R(0.4570457994644658) * yy * (R(5.0) * z2 - R(1.0));
  y[12] = R(0.3731763325901154) * z * (R(5.0) * z2 - R(3.0));
  y[13] = R(0.4570457994644658) * x * (R(5.0) * z2 - R(1.0));
  y[14] = R(1.445305721320277) * z * (x2 - y2);
  y[15] = R(0.5900435899266435) * x * (x2 - R(3.0) * y2);
  y[16] = R(2.5033429417967046) * x * yy * (x2 - y2);
  y[17] = R(1.7701307697799304) * yy * z * (R(3.0) * x2 - y2);
  y[18] = R(0.9461746957575601) * x * yy * (R(7.0) * z2 - R(1.0));
  y[19] = R(0.6690465435572892) * yy * z * (R(7.0) * z2 - R(3.0));
  y[20] = R(0.10578554691520431) * (R(35.0) * z2 * z2 - R(30.0) * z2 + R(3.0));
  y[21] = R(0.6690465435572892) * x * z * (R(7.0) * z2 - R(3.0));
  y[22] = R(0.47308734787878004) * (x2 - y2) * (R(7.0) * z2 - R(1.0));
  y[23] = R(1.7701307697799304) * x * z * (x2 - R(3.0) * y2);
  y[24] = R(0.6258357354491761) * (x2 * (x2 - R(3.0) * y2) - y2 * (R(3.0) * x2 - y2));
#endif
}

// Stage 1 of the projection L_lm = int L Y_lm dl, as the sum over the texels of an unpadded cube of
// face size `size` of L Y_lm Omega (omega: the exact solid angle of texel (i, j), the same on
// every face). Each work-item sums a strided share of the texels; the work-group then reduces its
// items' sums in local memory, and writes SH_ACC partial sums per group.
kernel void sh_project(global const float4* cube, int size, global const real* omega, global real* partials,
                       local real* scratch) {
  const int lid = (int)get_local_id(0), lsize = (int)get_local_size(0);
  const int n = 6 * size * size;
  real acc[SH_ACC];
  for (int c = 0; c < SH_ACC; ++c) acc[c] = R(0.0);
  real y[SH_COUNT];
  for (int t = (int)get_global_id(0); t < n; t += (int)get_global_size(0)) {
    const int face = t / (size * size), r = t % (size * size), j = r / size, i = r % size;
    const real w = omega[r];
    const real3 d = cube_texel_direction(face, size, i, j);
    const real4 l = convert_real4(cube[t]) * w;
    sh_basis(d, y);
    for (int k = 0; k < SH_COUNT; ++k) {
      acc[3 * k] += l.x * y[k];
      acc[3 * k + 1] += l.y * y[k];
      acc[3 * k + 2] += l.z * y[k];
    }
    acc[3 * SH_COUNT] += w;
  }
  for (int c = 0; c < SH_ACC; ++c) scratch[lid * SH_ACC + c] = acc[c];
  barrier(CLK_LOCAL_MEM_FENCE);
  // Tree reduction over the work-items: pairwise sums keep the rounding at O(log n).
  for (int half_size = lsize / 2; half_size > 0; half_size /= 2) {
    if (lid < half_size)
      for (int c = 0; c < SH_ACC; ++c) scratch[lid * SH_ACC + c] += scratch[(lid + half_size) * SH_ACC + c];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  for (int c = lid; c < SH_ACC; c += lsize) partials[get_group_id(0) * SH_ACC + (size_t)c] = scratch[c];
}

// Stage 2: the groups' partial sums, pairwise, into SH_ACC totals (the host then scales them by
// 4 pi / sum Omega, which is 1 up to rounding, so that a constant environment gives exactly its
// L_00). One work-item per total; `groups` a power of two.
kernel void sh_reduce(global real* partials, int groups, global real* out) {
  const int c = (int)get_global_id(0);
  if (c >= SH_ACC) return;
  for (int half_size = groups / 2; half_size > 0; half_size /= 2)
    for (int g = 0; g < half_size; ++g) partials[g * SH_ACC + c] += partials[(g + half_size) * SH_ACC + c];
  out[c] = partials[c];
}

// One texel of the irradiance cube, E(n) / pi = (1 / pi) int L(l) (n.l)+ dl, as a sum over points
// (the source's texels at a resolution where the cosine lobe is smooth, plus its bright texels at
// full resolution; values L Omega). Global id (i, face * size + j).
kernel void irradiance_cube(global float4* out, int size, global const real* points, int n_points) {
  const int i = (int)get_global_id(0), gj = (int)get_global_id(1);
  if (i >= size || gj >= 6 * size) return;
  const int face = gj / size, j = gj % size;
  const real3 e = env_point_sum(cube_texel_direction(face, size, i, j), points, n_points, R(1.0));
  out[((size_t)face * (size_t)size + (size_t)j) * (size_t)size + (size_t)i] =
      (float4)((float)e.x, (float)e.y, (float)e.z, 1.0f);
}
