// The double reference of a prefiltered chain's bound on the device (host/src/families/prefilter/
// bound_device.cpp): for a list of sample directions R, the reference's own sum
// (host/reference/src/prefilter.cpp, prefilter_directions; envmap.cpp's sub-cells and cube_bilinear),
//   P(R) = sum_m K(R.d_m) L(d_m) Omega_m / sum_m K(R.d_m) Omega_m   over the sub-cells m with R.d_m > 0,
// in double, term by term as the reference writes it: every source texel of level 0 split into q x q
// sub-cells, d_m the unit direction of a sub-cell's centre, Omega_m its exact solid angle (the
// antiderivative F(a, b) = atan2(a b, sqrt(1 + a^2 + b^2)) at its corners, a table the host computes
// in double as math::cube_rect_solid_angle does), L the seamless bilinear interpolation of level 0
// (its float texels read in place, as double) and K the lobe's kernel D(n.h) (n.l)+ with
// n.h = sqrt((1 + c) / 2) (env_lobe_kernel, D_GGX or D_Charlie of the reference).
//
// What differs from the reference: the order of the sums (a work-item sums one row of sub-cells of
// one face for up to BOUND_BLOCKS x BRDFBAKE_LANES directions, one lane each, and the host adds the
// rows' partial sums in order), and a rounding here and there: the lobe from (1 + c) / 2 without
// the reference's square root and its square (bound_lobe_kernel), a sub-cell's direction scaled by
// its reciprocal length, its bilinear weights from its face coordinates (not from its direction),
// and the lanes' multiply-adds contracted. tests/device/test_prefilter_bound.cpp holds the values to
// the reference's within 1e-10 relative (2e-14 measured).
//
// The part of a row where no lane of a block can see a sub-cell (R.d <= 0) is skipped for that
// block: R.d is linear in a along a row (d is the plane point (a, b) over a positive length), so
// each lane's positive part is an interval of a, and the union of the lanes' intervals (widened by a
// sub-cell) holds every term the reference counts (c <= 0 adds nothing there either).
//
// Built in fp64 only (BRDFBAKE_FP64: the host keeps its own reference where the device has no
// cl_khr_fp64), with contraction off but in the lanes' sums: the reference is compiled with
// -ffp-contract=off, and the solid angles and bilinear weights here are rounded as it rounds them.
#pragma OPENCL FP_CONTRACT OFF
#include "common/real.clh"
#include "common/cubemap.clh"

#if !defined(BRDFBAKE_FP64)
#error "prefilter_bound.cl is the double reference: build it with BRDFBAKE_FP64"
#endif

// The texel (i, j) of `face` for i, j in [-1, size], as the reference's cube_fetch_extended: inside
// the face the texel; one index outside the neighbouring face's texel nearest to the extended centre;
// both outside (a corner) the mean of the three texels around it.
inline double3 bound_texel(global const float4* level0, int size, int face, int i, int j) {
  const size_t s = (size_t)size;
  return convert_double3(level0[((size_t)face * s + (size_t)j) * s + (size_t)i].xyz);
}

inline double3 bound_fetch_edge(global const float4* level0, int size, int face, int i, int j) {
  const double3 p = cube_plane_point(face, 2.0 * ((double)i + 0.5) / (double)size - 1.0,
                                     2.0 * ((double)j + 0.5) / (double)size - 1.0);
  double a, b;
  const int f = cube_face_coords(p, &a, &b);
  const int ni = clamp((int)floor(0.5 * (a + 1.0) * (double)size), 0, size - 1);
  const int nj = clamp((int)floor(0.5 * (b + 1.0) * (double)size), 0, size - 1);
  return bound_texel(level0, size, f, ni, nj);
}

inline double3 bound_fetch_extended(global const float4* level0, int size, int face, int i, int j) {
  const bool in_i = i >= 0 && i < size, in_j = j >= 0 && j < size;
  if (in_i && in_j) return bound_texel(level0, size, face, i, j);
  if (in_i || in_j) return bound_fetch_edge(level0, size, face, i, j);
  const int ci = clamp(i, 0, size - 1), cj = clamp(j, 0, size - 1);
  const double3 p = bound_fetch_edge(level0, size, face, ci, j);
  const double3 q = bound_fetch_edge(level0, size, face, i, cj);
  const double3 r = bound_texel(level0, size, face, ci, cj);
  return (double3)((p.x + q.x + r.x) / 3.0, (p.y + q.y + r.y) / 3.0, (p.z + q.z + r.z) / 3.0);
}

// The seamless bilinear interpolation of level 0 at the point (a, b) of `face` (cube_bilinear, which
// finds them from the direction: a sub-cell's centre is inside its face, and the reference's face
// coordinates of its direction are its own up to a rounding), at x = i0 + fx, y = j0 + fy in texels.
inline double3 bound_interpolate(double3 t00, double3 t10, double3 t01, double3 t11, double fx, double fy) {
  return (1.0 - fy) * ((1.0 - fx) * t00 + fx * t10) + fy * ((1.0 - fx) * t01 + fx * t11);
}

// The same where a texel of the four lies past the face's edge (bound_fetch_extended's).
double3 bound_bilinear_extended(global const float4* level0, int size, int face, int i0, int j0, double fx,
                                double fy) {
  const double3 t00 = bound_fetch_extended(level0, size, face, i0, j0);
  const double3 t10 = bound_fetch_extended(level0, size, face, i0 + 1, j0);
  const double3 t01 = bound_fetch_extended(level0, size, face, i0, j0 + 1);
  const double3 t11 = bound_fetch_extended(level0, size, face, i0 + 1, j0 + 1);
  return bound_interpolate(t00, t10, t01, t11, fx, fy);
}

// K(c) = D(n.h) c for c = R.l > 0 with n.h = sqrt((1 + c) / 2), per lane (env_lobe_kernel); a: the
// lane's alpha floored at kMinAlpha, a2 = a * a (both from the host, as the reference computes them).
// The lobes take (n.h)^2 = (1 + c) / 2 and sin^2 = 1 - (n.h)^2 = (1 - c) / 2 as they are, without
// the reference's square root and its square (a rounding or two of difference, no cancellation:
// (1 - c) / 2 is exact where the reference's (1 - n.h)(1 + n.h) carries n.h's rounding).
inline realv bound_lobe_kernel(realv c, realv a, realv a2) {
  const realv cm = fmin(c, 1.0);
  const realv h2 = 0.5 * (1.0 + cm), sin2 = 0.5 * (1.0 - cm);
#ifdef BRDFBAKE_ENV_CHARLIE
  // D_Charlie: (2 + 1/a) sin^(1/a) / (2 pi) (n.h >= sqrt(1/2) for c > 0: the reference's log branch)
  const realv inv_a = 1.0 / a;
  const realv d = (2.0 + inv_a) * exp(0.5 * inv_a * log(sin2)) / (2.0 * BRDFBAKE_PI);
  (void)a2;
  (void)h2;
#else
  // D_GGX: a^2 / (pi denom^2), denom = a^2 (n.h)^2 + sin^2
  const realv denom = a2 * h2 + sin2;
  const realv d = a2 / (BRDFBAKE_PI * denom * denom);
  (void)a;
#endif
  return d * cm;
}

// The antiderivative of a face's solid angle, F(a, b) = atan2(a b, sqrt(1 + a^2 + b^2))
// (math::cube_rect_solid_angle's).
inline double bound_corner(double a, double b) { return atan2(a * b, sqrt(1.0 + a * a + b * b)); }

// Directions a launch takes: BOUND_BLOCKS blocks of BRDFBAKE_LANES; sub-cells prepared at a time.
#define BOUND_BLOCKS 8
#define BOUND_CHUNK 64

// One work-item: row `row` of sub-cells (face = row / n, sub-cell row sj = row % n, n = size q
// sub-cells a face side) for every block's BRDFBAKE_LANES directions: each sub-cell's direction,
// solid angle and radiance once, then its terms for every block whose lanes can see it.
//   dirs:    per block 4 x BRDFBAKE_LANES doubles: x, y, z of each lane's unit R, then its floored
//            alpha; at most BOUND_BLOCKS blocks
//   corner:  with `table`, F at the (n + 1)^2 corners of a face's sub-cells, corner (i, j) at
//            j (n + 1) + i, for a_i = -1 + 2 i / n (the same on every face); without, F is computed
//            here along the row (the host gives no table larger than level 0)
//   out:     per row and block 4 x BRDFBAKE_LANES doubles: sum K Omega L (r, g, b), sum K Omega
kernel void prefilter_bound_reference(global double* out, global const float4* level0, int size, int q,
                                      global const double* corner, int table, global const double* dirs,
                                      int blocks) {
  const int row = (int)get_global_id(0);
  const int n = size * q;
  if (row >= 6 * n || blocks > BOUND_BLOCKS) return;
  const int face = row / n, sj = row - face * n;
  const double b0 = -1.0 + 2.0 * sj / n, b1 = -1.0 + 2.0 * (sj + 1) / n, bc = 0.5 * (b0 + b1);

  // Each block's part of the row where some lane's R.d can be positive: the plane point
  // p(a) = p0 + a e, R.p = s0 + a s1, so a > -s0 / s1 (s1 > 0), a < -s0 / s1 (s1 < 0), everywhere
  // or nowhere (s1 = 0); in sub-cells i = (a + 1) n / 2, widened by one.
  const double3 p0 = cube_plane_point(face, 0.0, bc);
  const double3 e = cube_plane_point(face, 1.0, bc) - p0;
  realv rx[BOUND_BLOCKS], ry[BOUND_BLOCKS], rz[BOUND_BLOCKS], ra[BOUND_BLOCKS], ra2[BOUND_BLOCKS];
  int first[BOUND_BLOCKS], last[BOUND_BLOCKS];
  int row_first = n, row_last = 0;
  for (int bl = 0; bl < blocks; ++bl) {
    global const double* bd = dirs + (size_t)bl * 4 * BRDFBAKE_LANES;
    rx[bl] = vload_lanes(0, bd);
    ry[bl] = vload_lanes(1, bd);
    rz[bl] = vload_lanes(2, bd);
    ra[bl] = vload_lanes(3, bd);
    ra2[bl] = ra[bl] * ra[bl];
    const realv s0 = rx[bl] * p0.x + ry[bl] * p0.y + rz[bl] * p0.z;
    const realv s1 = rx[bl] * e.x + ry[bl] * e.y + rz[bl] * e.z;
    const realv cut = (-s0 / s1 + 1.0) * (0.5 * (double)n);
    const realv zero = (realv)0.0, cells = (realv)(double)n;
    const realv lo = select(select(select(cells, zero, s0 > 0.0), zero, s1 < 0.0), floor(cut) - 1.0, s1 > 0.0);
    const realv hi = select(select(select(zero, cells, s0 > 0.0), cells, s1 > 0.0), ceil(cut) + 1.0, s1 < 0.0);
    double lo_s[BRDFBAKE_LANES], hi_s[BRDFBAKE_LANES];
    vstore_lanes(lo, 0, lo_s);
    vstore_lanes(hi, 0, hi_s);
    double f = (double)n, l = 0.0;
    for (int k = 0; k < BRDFBAKE_LANES; ++k) {
      f = fmin(f, lo_s[k]);
      l = fmax(l, hi_s[k]);
    }
    first[bl] = (int)clamp(f, 0.0, (double)n);
    last[bl] = (int)clamp(l, 0.0, (double)n);
    row_first = min(row_first, first[bl]);
    row_last = max(row_last, last[bl]);
  }

  // the bilinear's rows: y = 0.5 (b + 1) size - 0.5 is the row's (cube_bilinear)
  const double y = 0.5 * (bc + 1.0) * (double)size - 0.5, y0 = floor(y), fy = y - y0;
  const int j0 = (int)y0;
  const bool rows_inside = j0 >= 0 && j0 + 1 < size;
  global const float4* r0 = level0 + ((size_t)face * (size_t)size + (size_t)(rows_inside ? j0 : 0)) * (size_t)size;
  global const float4* r1 = r0 + (rows_inside ? size : 0);

  realv acc[4 * BOUND_BLOCKS];
  for (int k = 0; k < 4 * BOUND_BLOCKS; ++k) acc[k] = (realv)0.0;
  global const double* c0 = corner + (table ? (size_t)sj * (size_t)(n + 1) : 0);
  global const double* c1 = c0 + (table ? n + 1 : 0);
  // without the table: F(a0, b0) and F(a0, b1) carried along the row
  const double a_first = -1.0 + 2.0 * row_first / n;
  double f00 = table ? 0.0 : bound_corner(a_first, b0), f01 = table ? 0.0 : bound_corner(a_first, b1);
  // BOUND_CHUNK sub-cells at a time: their directions, solid angles and radiances, then every
  // block's terms of them (the block's lanes and sums held in registers over the chunk)
  double cx[BOUND_CHUNK], cy[BOUND_CHUNK], cz[BOUND_CHUNK], cw[BOUND_CHUNK];
  double cr[BOUND_CHUNK], cg[BOUND_CHUNK], cb[BOUND_CHUNK];
  for (int start = row_first; start < row_last; start += BOUND_CHUNK) {
    const int end = min(start + BOUND_CHUNK, row_last);
    for (int si = start; si < end; ++si) {
      const int k = si - start;
      const double a0 = -1.0 + 2.0 * si / n, a1 = -1.0 + 2.0 * (si + 1) / n;
      // cube_rect_solid_angle: F(a1, b1) - F(a0, b1) - F(a1, b0) + F(a0, b0)
      if (table) {
        cw[k] = c1[si + 1] - c1[si] - c0[si + 1] + c0[si];
      } else {
        const double f10 = bound_corner(a1, b0), f11 = bound_corner(a1, b1);
        cw[k] = f11 - f01 - f10 + f00;
        f00 = f10;
        f01 = f11;
      }
      // the sub-cell's centre, normalised (the reference's normalized() divides by the length: a
      // rounding apart)
      const double ac = 0.5 * (a0 + a1);
      const double3 p = cube_plane_point(face, ac, bc);
      const double3 d = p * (1.0 / sqrt(p.x * p.x + p.y * p.y + p.z * p.z));
      const double x = 0.5 * (ac + 1.0) * (double)size - 0.5, x0 = floor(x), fx = x - x0;
      const int i0 = (int)x0;
      const double3 l = rows_inside && i0 >= 0 && i0 + 1 < size
                            ? bound_interpolate(convert_double3(r0[i0].xyz), convert_double3(r0[i0 + 1].xyz),
                                                convert_double3(r1[i0].xyz), convert_double3(r1[i0 + 1].xyz), fx, fy)
                            : bound_bilinear_extended(level0, size, face, i0, j0, fx, fy);
      cx[k] = d.x;
      cy[k] = d.y;
      cz[k] = d.z;
      cr[k] = l.x;
      cg[k] = l.y;
      cb[k] = l.z;
    }
    for (int bl = 0; bl < blocks; ++bl) {
#pragma OPENCL FP_CONTRACT ON
      const int lo = max(first[bl], start), hi = min(last[bl], end);
      if (lo >= hi) continue;
      const realv x = rx[bl], y = ry[bl], z = rz[bl], a = ra[bl], a2 = ra2[bl];
      realv s0 = acc[4 * bl], s1 = acc[4 * bl + 1], s2 = acc[4 * bl + 2], s3 = acc[4 * bl + 3];
      for (int k = lo - start; k < hi - start; ++k) {
        const realv c = x * cx[k] + y * cy[k] + z * cz[k];
        const realv kw = select((realv)0.0, bound_lobe_kernel(c, a, a2) * cw[k], c > 0.0);
        s0 += kw * cr[k];
        s1 += kw * cg[k];
        s2 += kw * cb[k];
        s3 += kw;
      }
      acc[4 * bl] = s0;
      acc[4 * bl + 1] = s1;
      acc[4 * bl + 2] = s2;
      acc[4 * bl + 3] = s3;
    }
  }
  for (int bl = 0; bl < blocks; ++bl) {
    global double* o = out + ((size_t)row * (size_t)blocks + (size_t)bl) * 4 * BRDFBAKE_LANES;
    for (int k = 0; k < 4; ++k) vstore_lanes(acc[4 * bl + k], k, o);
  }
}
