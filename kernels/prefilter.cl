// Prefiltered radiance of one output level: GGX (default) or Charlie (BRDFBAKE_ENV_CHARLIE).
//
// What a level holds (Karis 2013, with n = v = R):
//   P(R) = int L(l) K(R.l) dl / W,   K = D(h) (n.l)+,   W = int K dl.
// The environment is split in two by the host (host/src/prefilter.cpp): L = L_rest + L_bright, where
// L_bright holds the brightest texels of the source (the sun) and L_rest the others. Then
//   P(R) = [int L_rest K dl] / W  +  sum_t L_t int_(footprint of t) K dl / W.
// Two kernels estimate the first term, each adds the second.
//
// prefilter_pyramid (--estimator quadrature, the default): the deterministic hierarchical
// quadrature of common/env_sampling.clh (env_pyramid_sum), which also supplies W as its own sum of
// K Omega, so that a constant environment comes back exactly.
//
// prefilter_level (--estimator sampling): importance sampling of the lobe, self-normalised. Sample
// h with density D(h) (n.h) (Walter et al. 2007, eq. 35-36; Estevez & Kulla 2017 for Charlie) at
// Hammersley points, reflect l = 2 (n.h) h - n; with v = n the Jacobian is dl = 4 (n.h) dh, so l has
// density p(l) = D(h) / 4 and each sample weighs K / p = 4 (n.l)+. Normalising by the same
// samples' sum of weights,
//   P_rest(R) ~ sum_k (n.l_k)+ L_rest(l_k) / sum_k (n.l_k)+,
// gives a constant environment back exactly (the white furnace). Because n = v = R, the samples in
// the frame (t, b, R) are the same for every texel: the host computes them once per level, with
// their weights (n.l)+ and their filtered-importance-sampling level (below), and drops those below
// the horizon.
//   Filtered importance sampling (Krivanek & Colbert 2008): sample k stands for the solid angle
// Omega_s = 1 / (N p(l_k)) = 4 / (N D(h_k)), and reads the source mip level whose texels have that
// solid angle: lod = 0.5 log2(Omega_s / Omega_texel) + bias. A source texel of face size S at
// direction l covers Omega_texel = (2 / S)^2 |l_major|^3, so
//   lod_k(l) = lod_k - 1.5 log2 |l_major|,  lod_k = 0.5 log2(Omega_s / (2 / S)^2) + bias
// (the host's part, lod_k, is per sample; the kernel adds the texel's place on the face). Fetches
// are trilinear and seamless: bilinear in the padded faces of two adjacent levels.
//
// The bright texels: an explicit sum over points (env_point_sum), each texel's bilinear footprint
// split into sub-cells by the host (values L Omega, divided by W here for the sampling estimator).
// This is environment sampling with every bright texel taken once, combined with the lobe by the
// partition of unity "bright texels to the environment strategy, the rest to the lobe" (Veach
// 1997's multi-sample model with weights 1 and 0): unbiased, and with no fireflies, because no lobe
// sample or pyramid texel ever carries the sun.
#include "common/real.clh"
#include "common/cubemap.clh"
#include "common/env_sampling.clh"

// Duff et al. 2017, "Building an Orthonormal Basis, Revisited", listing 3: t, b with (t, b, n)
// orthonormal and right-handed, branch-free but for the sign.
inline void orthonormal_basis(real3 n, real3* t, real3* b) {
  const real sign = n.z >= R(0.0) ? R(1.0) : R(-1.0);
  const real a = R(-1.0) / (sign + n.z);
  const real c = n.x * n.y * a;
  *t = (real3)(R(1.0) + sign * n.x * n.x * a, sign * c, -sign * n.x);
  *b = (real3)(c, sign + n.y * n.y * a, -n.y);
}

// Bilinear fetch at face coordinates (a, b) of padded level m; chain_info holds (offset, size)
// per level.
inline real4 chain_bilinear(global const float4* chain, constant int* chain_info, int m, int face, real a,
                            real b) {
  const int size = chain_info[2 * m + 1];
  const size_t p = (size_t)(size + 2);
  // padded coordinates: the face interior starts at 1, texel centres at i + 1.5
  const real x = R(0.5) * (a + R(1.0)) * (real)size + R(0.5);
  const real y = R(0.5) * (b + R(1.0)) * (real)size + R(0.5);
  const int x0 = min((int)x, size), y0 = min((int)y, size);
  const real tx = x - (real)x0, ty = y - (real)y0;
  const size_t at = (size_t)chain_info[2 * m] + ((size_t)face * p + (size_t)y0) * p + (size_t)x0;
  return (R(1.0) - ty) * ((R(1.0) - tx) * convert_real4(chain[at]) + tx * convert_real4(chain[at + 1])) +
         ty * ((R(1.0) - tx) * convert_real4(chain[at + p]) + tx * convert_real4(chain[at + p + 1]));
}

// One texel of an output level of face size `size`: global id (i, face * size + j).
//   samples: n_samples (a multiple of BRDFBAKE_LANES) as arrays x, y, z (local frame, z along R),
//            weight (n.l)+ (0 for padding), lod_k
//   bright:  n_bright points as for env_point_sum (values L Omega / W)
kernel void prefilter_level(global float4* out, int size, global const float4* chain, constant int* chain_info,
                            int chain_levels, global const real* samples, int n_samples,
                            global const real* bright, int n_bright, real alpha) {
  const int i = (int)get_global_id(0), gj = (int)get_global_id(1);
  if (i >= size || gj >= 6 * size) return;
  const int face = gj / size, j = gj % size;
  const real3 n = cube_texel_direction(face, size, i, j);
  real3 t, b;
  orthonormal_basis(n, &t, &b);
  const real max_lod = (real)(chain_levels - 1);

  real4 acc = (real4)(R(0.0));
  realv wsum = (realv)(R(0.0));
  for (int k = 0; k < n_samples; k += BRDFBAKE_LANES) {
    const realv lx = vload_lanes(0, samples + k), ly = vload_lanes(0, samples + n_samples + k);
    const realv lz = vload_lanes(0, samples + 2 * n_samples + k);
    const realv w = vload_lanes(0, samples + 3 * n_samples + k);
    const realv lod_k = vload_lanes(0, samples + 4 * n_samples + k);
    const realv dx = lx * t.x + ly * b.x + lz * n.x;
    const realv dy = lx * t.y + ly * b.y + lz * n.y;
    const realv dz = lx * t.z + ly * b.z + lz * n.z;
    realv fa, fb, ma;
    const maskv fv = cube_face_coords_v(dx, dy, dz, &fa, &fb, &ma);
    const realv lod = clamp(lod_k - R(1.5) * log2(ma), R(0.0), max_lod);
    const realv lf = floor(lod);
    real la[BRDFBAKE_LANES], lb[BRDFBAKE_LANES], lw[BRDFBAKE_LANES], lt[BRDFBAKE_LANES], lm[BRDFBAKE_LANES];
    int lface[BRDFBAKE_LANES];
    vstore_lanes(fa, 0, la);
    vstore_lanes(fb, 0, lb);
    vstore_lanes(w, 0, lw);
    vstore_lanes(lod - lf, 0, lt);
    vstore_lanes(lf, 0, lm);
    vstore_lanes(convert_intv(fv), 0, lface);
    for (int q = 0; q < BRDFBAKE_LANES; ++q) {
      const int m0 = (int)lm[q];
      real4 v = chain_bilinear(chain, chain_info, m0, (int)lface[q], la[q], lb[q]);
      if (lt[q] > R(0.0))
        v = mix(v, chain_bilinear(chain, chain_info, min(m0 + 1, chain_levels - 1), (int)lface[q], la[q], lb[q]),
                lt[q]);
      acc += lw[q] * v;
    }
    wsum += w;
  }
  const real total = lanes_sum(wsum);
  const real3 rest = total > R(0.0) ? acc.xyz / total : (real3)(R(0.0));
  const real3 sun = n_bright > 0 ? env_point_sum(n, bright, n_bright, alpha) : (real3)(R(0.0));
  const real3 p = rest + sun;
  out[((size_t)face * (size_t)size + (size_t)j) * (size_t)size + (size_t)i] =
      (float4)((float)p.x, (float)p.y, (float)p.z, 1.0f);
}

// One texel of an output level by the deterministic estimator (--estimator quadrature, the
// default): the hierarchical quadrature of env_pyramid_sum over the rest, plus the bright points
// (values L Omega), divided by the pyramid's sum of K Omega. Global id (i, face * size + j).
kernel void prefilter_pyramid(global float4* out, int size, global const float* pyramid, constant int* info,
                              int levels, constant real* cos_core, constant real* band, global const real* bright,
                              int n_bright, real alpha) {
  const int i = (int)get_global_id(0), gj = (int)get_global_id(1);
  if (i >= size || gj >= 6 * size) return;
  const int face = gj / size, j = gj % size;
  const real3 n = cube_texel_direction(face, size, i, j);
  const real4 sums = env_pyramid_sum(n, pyramid, info, levels, cos_core, band, alpha);
  const real3 sun = n_bright > 0 ? env_point_sum(n, bright, n_bright, alpha) : (real3)(R(0.0));
  const real3 p = sums.w > R(0.0) ? (sums.xyz + sun) / sums.w : (real3)(R(0.0));
  out[((size_t)face * (size_t)size + (size_t)j) * (size_t)size + (size_t)i] =
      (float4)((float)p.x, (float)p.y, (float)p.z, 1.0f);
}
