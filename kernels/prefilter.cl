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

// ---- The same quadrature a block of texels at a time (prefilter_pyramid_strips, the default) ------
//
// Neighbouring texels refine almost the same pyramid texels. A work-item takes a block of
// 8 x (2 BRDFBAKE_STRIP_ROWS) texels of one face and walks the pyramid once for all of them, refining
// wherever any of them would: the thresholds of env_pyramid_sum widened by the block's angular radius
// rho (the largest angle between the block's centre direction and its corner texels' directions; the
// angle to a fixed direction over the block's geodesic quadrilateral is largest at a corner). Every
// texel's partition is then its own or finer, each pyramid texel is still counted once, and every
// summed pyramid texel is evaluated for 16 texels (8 x 2) at once (16 lanes: AVX-512 on a CPU), its
// data loaded once. A square block keeps rho, and so the widening, smallest for its texel count (8 x 8
// measured 3-4% less CPU time than 16 x 4). Where a refined list would overflow its capacity the block
// falls back to env_pyramid_sum per texel (the per-texel kernel's own result).
#ifndef BRDFBAKE_STRIP_ROWS
#define BRDFBAKE_STRIP_ROWS 4  // realw rows of 8 x 2 texels: blocks of 8 x 8
#endif
#ifndef BRDFBAKE_STRIP_CAPACITY
#define BRDFBAKE_STRIP_CAPACITY 2048  // refined texels per face and level of a block's walk
#endif

#ifdef BRDFBAKE_FP64
typedef double16 realw;
#define convert_realw convert_double16
#else
typedef float16 realw;
#define convert_realw convert_float16
#endif

// ENV_KERNEL_V on 16 lanes: GGX written out (the same operations as env_kernel_ggx_v), Charlie's
// D = (2 + 1/alpha) / (2 pi) (sin^2 theta_h)^(1 / (2 alpha)) by multiplication where 1/alpha is a whole
// number n (power2 = n > 0: the linear schedule's roughness 1/4 and 1/2 give 16 and 4, 1 gives 1), so
// that no exp or log is taken, else (power2 = 0) as env_kernel_charlie_v.
inline realw strip_kernel(realw c, real alpha, int power2) {
#if defined(BRDFBAKE_ENV_CHARLIE)
  if (power2 > 0) {
    const realw x = fmax(R(0.5) * (R(1.0) - c), R(0.0));  // sin^2 theta_h
    realw p = (power2 & 1) ? sqrt(x) : (realw)(R(1.0)), b = x;
    for (int e = power2 >> 1; e > 0; e >>= 1) {  // x^(power2 / 2) by squaring
      if (e & 1) p *= b;
      b *= b;
    }
    const real inv_a = R(1.0) / alpha;
    return fmax(c, R(0.0)) * ((R(2.0) + inv_a) * (R(0.5) * BRDFBAKE_INV_PI)) * p;
  }
#endif
#if defined(BRDFBAKE_ENV_CHARLIE) || defined(BRDFBAKE_ENV_COSINE)
  realw k;
  k.lo = ENV_KERNEL_V(c.lo, alpha);
  k.hi = ENV_KERNEL_V(c.hi, alpha);
  return k;
#else
  (void)power2;
  const real alpha2 = alpha * alpha;
  const realw t = fmax(R(0.5) * (R(1.0) - c), R(0.0)) + alpha2 * (R(0.5) * (R(1.0) + c));
  const realw it = R(1.0) / t;  // one division; t >= alpha^2 > 0
  return fmax(c, R(0.0)) * (alpha2 / BRDFBAKE_PI) * (it * it);
#endif
}

// cos(acos(c) + rho): a core threshold widened (c > 1.5: never refined, c < -1.5: always).
inline real strip_core(real c, real rho) {
  if (c > R(1.5) || c < R(-1.5)) return c;
  const real t = acos(clamp(c, R(-1.0), R(1.0))) + rho;
  return t >= BRDFBAKE_PI ? R(-2.0) : cos(t);
}

// A band lo < c < hi widened by rho on both sides ((2, 2): empty, kept).
inline real2 strip_band(real lo, real hi, real rho) {
  if (!(lo < hi)) return (real2)(lo, hi);
  const real t_in = acos(clamp(hi, R(-1.0), R(1.0))) - rho, t_out = acos(clamp(lo, R(-1.0), R(1.0))) + rho;
  return (real2)(t_out >= BRDFBAKE_PI ? R(-2.0) : cos(t_out), t_in <= R(0.0) ? R(2.0) : cos(t_in));
}

// Global size (size / 8, 6 size / (2 BRDFBAKE_STRIP_ROWS)), both dividing size; the pyramid's
// arguments as prefilter_pyramid, power2 for strip_kernel, and the bright texels (n_texels of them)
// as two lists of points grouped by texel (SoA as env_point_sum's, strides fine_n and coarse_n):
// fine_per points a texel at the full subdivision, coarse_per at the lobe's. A bright texel within
// `reach` (its footprint and a margin) of the horizon of some texel of the block takes its fine
// points, so that the kernel's kink there is cut where the per-texel estimators cut it; elsewhere
// the kernel is smooth across the footprint and the coarse points resolve it. bright_dir: the
// texels' directions (x, y, z arrays).
kernel void prefilter_pyramid_strips(global float4* out, int size, global const float* pyramid, constant int* info,
                                     int levels, constant real* cos_core, constant real* band, real alpha, int power2,
                                     global const real* fine, global const real* coarse, int fine_n, int coarse_n,
                                     int fine_per, int coarse_per, global const real* bright_dir, int n_texels,
                                     real reach) {
  const int i0 = 8 * (int)get_global_id(0), gj0 = 2 * BRDFBAKE_STRIP_ROWS * (int)get_global_id(1);
  if (i0 >= size || gj0 >= 6 * size) return;
  const int face = gj0 / size, j0 = gj0 % size;
  const int i1 = i0 + 7, j1 = j0 + 2 * BRDFBAKE_STRIP_ROWS - 1;

  // the texels' directions, 8 x 2 texels per realw (lane q: column i0 + q % 8, row j0 + 2 r + q / 8)
  const realw lane_i = (realw)(R(0.0), R(1.0), R(2.0), R(3.0), R(4.0), R(5.0), R(6.0), R(7.0), R(0.0), R(1.0), R(2.0),
                               R(3.0), R(4.0), R(5.0), R(6.0), R(7.0));
  const realw lane_j = (realw)(R(0.0), R(0.0), R(0.0), R(0.0), R(0.0), R(0.0), R(0.0), R(0.0), R(1.0), R(1.0), R(1.0),
                               R(1.0), R(1.0), R(1.0), R(1.0), R(1.0));
  const realw ta = R(2.0) * ((real)i0 + lane_i + R(0.5)) / (real)size - R(1.0);
  realw dx[BRDFBAKE_STRIP_ROWS], dy[BRDFBAKE_STRIP_ROWS], dz[BRDFBAKE_STRIP_ROWS];
  realw nr[BRDFBAKE_STRIP_ROWS], ng[BRDFBAKE_STRIP_ROWS], nb[BRDFBAKE_STRIP_ROWS], den[BRDFBAKE_STRIP_ROWS];
  for (int r = 0; r < BRDFBAKE_STRIP_ROWS; ++r) {
    const realw tb = R(2.0) * ((real)(j0 + 2 * r) + lane_j + R(0.5)) / (real)size - R(1.0);
    realw x, y, z;  // cube_plane_point, lane-wise
    switch (face) {
      case 0: x = (realw)(R(1.0)); y = -tb; z = -ta; break;
      case 1: x = (realw)(R(-1.0)); y = -tb; z = ta; break;
      case 2: x = ta; y = (realw)(R(1.0)); z = tb; break;
      case 3: x = ta; y = (realw)(R(-1.0)); z = -tb; break;
      case 4: x = ta; y = -tb; z = (realw)(R(1.0)); break;
      default: x = -ta; y = -tb; z = (realw)(R(-1.0)); break;
    }
    const realw inv = rsqrt(x * x + y * y + z * z);
    dx[r] = x * inv;
    dy[r] = y * inv;
    dz[r] = z * inv;
    nr[r] = ng[r] = nb[r] = den[r] = (realw)(R(0.0));
  }

  // the block's centre and angular radius
  const real3 centre = normalize(cube_plane_point(face, (real)(i0 + i1 + 1) / (real)size - R(1.0),
                                                  (real)(j0 + j1 + 1) / (real)size - R(1.0)));
  real min_cos = dot(centre, cube_texel_direction(face, size, i0, j0));
  min_cos = fmin(min_cos, dot(centre, cube_texel_direction(face, size, i1, j0)));
  min_cos = fmin(min_cos, dot(centre, cube_texel_direction(face, size, i0, j1)));
  min_cos = fmin(min_cos, dot(centre, cube_texel_direction(face, size, i1, j1)));
  const real rho = acos(clamp(min_cos, R(-1.0), R(1.0))) + R(1e-4);  // + the rounding of the directions

  int list_a[BRDFBAKE_STRIP_CAPACITY], list_b[BRDFBAKE_STRIP_CAPACITY];
  int mask_lanes[BRDFBAKE_LANES], idx_lanes[BRDFBAKE_LANES];
  real node[10][BRDFBAKE_LANES];
  const maskv lane8 = LANE_INDEX;
  const maskv quad = (maskv)(0, 1, 2, 3, 0, 1, 2, 3);
  const int top = levels - 1;
  int overflow = 0;
  for (int f = 0; f < 6 && !overflow; ++f) {
    int* cur = list_a;
    int* nxt = list_b;
    int n_cur = 0;
    for (int k = top; k >= 0 && !overflow; --k) {
      const int s = info[2 * k + 1];
      const int n_face = s * s;
      const size_t a = (size_t)6 * (size_t)n_face + 8;
      global const float* base = pyramid + info[2 * k] + (size_t)f * (size_t)n_face;
      const real cc = strip_core(cos_core[k], rho);
      const real2 bd = strip_band(band[2 * k], band[2 * k + 1], rho);
      const int chunks = k == top ? (n_face + BRDFBAKE_LANES - 1) / BRDFBAKE_LANES : (n_cur + 1) / 2;
      int n_next = 0;
      for (int q = 0; q < chunks; ++q) {
        maskv idx, valid;
        int pa = 0, pb = 0;
        realv v[10];
        if (k == top) {
          idx = lane8 + (maskv)(q * BRDFBAKE_LANES);
          valid = idx < (maskv)n_face;
          for (int m = 0; m < 10; ++m) v[m] = convert_realv(vload8(q, base + m * a));
        } else {
          pa = cur[2 * q];
          const bool has_b = 2 * q + 1 < n_cur;
          pb = has_b ? cur[2 * q + 1] : pa;
          idx = select((maskv)(4 * pa), (maskv)(4 * pb), lane8 >= (maskv)4) + quad;
          valid = has_b ? (maskv)(-1) : lane8 < (maskv)4;
          for (int m = 0; m < 10; ++m) v[m] = pyramid_load(base + m * a, pa, pb);
        }
        const realv c = centre.x * v[0] + centre.y * v[1] + centre.z * v[2];
        const maskv refined = valid & ((c > cc) | ((c > bd.x) & (c < bd.y)));
        if (any(refined)) {
          vstore8(convert_int8(refined), 0, mask_lanes);
          vstore8(convert_int8(idx), 0, idx_lanes);
          for (int l = 0; l < BRDFBAKE_LANES; ++l) {
            if (!mask_lanes[l]) continue;
            if (n_next < BRDFBAKE_STRIP_CAPACITY) nxt[n_next++] = idx_lanes[l];
            else overflow = 1;
          }
        }
        const maskv summed = valid & ~refined;
        if (!any(summed)) continue;
        vstore8(convert_int8(summed), 0, mask_lanes);
        for (int m = 0; m < 10; ++m) vstore_lanes(v[m], 0, node[m]);
        for (int l = 0; l < BRDFBAKE_LANES; ++l) {
          if (!mask_lanes[l]) continue;
          // this pyramid texel, for every texel of the block
          for (int r = 0; r < BRDFBAKE_STRIP_ROWS; ++r) {
            const realw cg = dx[r] * node[0][l] + dy[r] * node[1][l] + dz[r] * node[2][l];
            const realw cm = dx[r] * node[3][l] + dy[r] * node[4][l] + dz[r] * node[5][l];
            const realw km = strip_kernel(cm, alpha, power2);
            den[r] += strip_kernel(cg, alpha, power2) * node[6][l];
            nr[r] += km * node[7][l];
            ng[r] += km * node[8][l];
            nb[r] += km * node[9][l];
          }
        }
      }
      if (n_next == 0) break;
      int* t = cur;
      cur = nxt;
      nxt = t;
      n_cur = n_next;
    }
  }

  // the bright points, 16 texels at a time; a texel of the block is within rho of the centre, so a
  // bright texel near its horizon has |cos| to the centre below sin(rho + reach)
  realw sr[BRDFBAKE_STRIP_ROWS], sg[BRDFBAKE_STRIP_ROWS], sb[BRDFBAKE_STRIP_ROWS];
  for (int r = 0; r < BRDFBAKE_STRIP_ROWS; ++r) sr[r] = sg[r] = sb[r] = (realw)(R(0.0));
  const real horizon = sin(fmin(rho + reach, R(0.5) * BRDFBAKE_PI));
  for (int t = 0; t < n_texels; ++t) {
    const real c = centre.x * bright_dir[t] + centre.y * bright_dir[n_texels + t] + centre.z * bright_dir[2 * n_texels + t];
    const bool near_horizon = fabs(c) < horizon;
    global const real* p = near_horizon ? fine : coarse;
    const int stride = near_horizon ? fine_n : coarse_n, per = near_horizon ? fine_per : coarse_per;
    for (int k = t * per; k < (t + 1) * per; ++k) {
      const real px = p[k], py = p[stride + k], pz = p[2 * stride + k];
      const real pr = p[3 * stride + k], pg = p[4 * stride + k], pb = p[5 * stride + k];
      for (int r = 0; r < BRDFBAKE_STRIP_ROWS; ++r) {
        const realw w = strip_kernel(dx[r] * px + dy[r] * py + dz[r] * pz, alpha, power2);
        sr[r] += w * pr;
        sg[r] += w * pg;
        sb[r] += w * pb;
      }
    }
  }

  for (int r = 0; r < BRDFBAKE_STRIP_ROWS; ++r) {
    real o_nr[16], o_ng[16], o_nb[16], o_den[16], o_sr[16], o_sg[16], o_sb[16];
    vstore16(nr[r], 0, o_nr);
    vstore16(ng[r], 0, o_ng);
    vstore16(nb[r], 0, o_nb);
    vstore16(den[r], 0, o_den);
    vstore16(sr[r], 0, o_sr);
    vstore16(sg[r], 0, o_sg);
    vstore16(sb[r], 0, o_sb);
    for (int q = 0; q < 16; ++q) {
      const int i = i0 + q % 8, j = j0 + 2 * r + q / 8;
      real4 sums = (real4)(o_nr[q], o_ng[q], o_nb[q], o_den[q]);
      if (overflow) sums = env_pyramid_sum(cube_texel_direction(face, size, i, j), pyramid, info, levels, cos_core, band, alpha);
      const real3 sun = (real3)(o_sr[q], o_sg[q], o_sb[q]);
      const real3 p = sums.w > R(0.0) ? (sums.xyz + sun) / sums.w : (real3)(R(0.0));
      out[((size_t)face * (size_t)size + (size_t)j) * (size_t)size + (size_t)i] =
          (float4)((float)p.x, (float)p.y, (float)p.z, 1.0f);
    }
  }
}
