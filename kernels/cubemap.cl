// Cube map construction: an equirectangular image to a cube, cube to cube resampling, padded
// levels with seamless borders, and the source mip chain that filtered importance sampling reads.
// Addressing and the padded layout: common/cubemap.clh.
#include "common/real.clh"
#include "common/cubemap.clh"

// ---- Equirectangular to cube ---------------------------------------------------------------------
//
// docs/CONVENTIONS.md: pixel (x, y) of a W x H equirect has u = (x + 0.5) / W, v = (y + 0.5) / H;
// longitude phi = 2 pi (0.5 - u), latitude theta = pi (0.5 - v), and looks along
// (sin phi cos theta, sin theta, cos phi cos theta) (OpenEXR's LatLongMap orientation): the top row
// is +Y, the centre column +Z, u = 1/4 is +X. The inverse: u = 0.5 - atan2(x, z) / 2 pi,
// v = 0.5 - asin(y) / pi.

// Eight texels of a row of the cube, global id (chunk, face * size + j), texels i = 8 chunk + lane:
// each the mean of k x k bilinear samples of the equirect spread evenly over the texel in face
// coordinates, weighted by their solid angle (the area element), so that the texel holds the
// equirect's average over its own footprint. The direction maths runs BRDFBAKE_LANES texels at a
// time (PoCL vectorises only explicit vectors); the fetches are per lane.
// dst holds faces face0.. as packed RGB, three floats a texel (the host converts one face at a time:
// global id 1 is offset to the face, so that no device buffer is larger than a face; the host adds
// the alpha once the equirect is released, so that the two are never held whole at once).
kernel void equirect_to_cube(global const float* src, int width, int height, global float* dst,
                             int size, int k, int face0) {
  const int i0 = (int)get_global_id(0) * BRDFBAKE_LANES, gj = (int)get_global_id(1);
  if (i0 >= size || gj >= 6 * size) return;
  const int face = gj / size, j = gj % size;
  const realv lane = convert_realv(LANE_INDEX);
  realv sr = (realv)(R(0.0)), sg = (realv)(R(0.0)), sb = (realv)(R(0.0)), wsum = (realv)(R(0.0));
  for (int sy = 0; sy < k; ++sy)
    for (int sx = 0; sx < k; ++sx) {
      const realv a = R(2.0) * ((real)i0 + lane + ((real)sx + R(0.5)) / (real)k) / (real)size - R(1.0);
      const real b = R(2.0) * ((real)j + ((real)sy + R(0.5)) / (real)k) / (real)size - R(1.0);
      const realv r2 = R(1.0) + a * a + b * b;
      const realv inv = rsqrt(r2);
      const realv w = inv * inv * inv;  // the area element (1 + a^2 + b^2)^(-3/2)
      // the face's direction (cube_plane_point), normalised
      realv x, y, z;
      switch (face) {
        case 0: x = (realv)(R(1.0)); y = (realv)(-b); z = -a; break;
        case 1: x = (realv)(R(-1.0)); y = (realv)(-b); z = a; break;
        case 2: x = a; y = (realv)(R(1.0)); z = (realv)(b); break;
        case 3: x = a; y = (realv)(R(-1.0)); z = (realv)(-b); break;
        case 4: x = a; y = (realv)(-b); z = (realv)(R(1.0)); break;
        default: x = -a; y = (realv)(-b); z = (realv)(R(-1.0)); break;
      }
      const realv u = R(0.5) - atan2(x, z) * (R(0.5) * BRDFBAKE_INV_PI);
      const realv v = R(0.5) - asin(clamp(y * inv, R(-1.0), R(1.0))) * BRDFBAKE_INV_PI;
      // bilinear weights and addresses for all lanes at once; only the loads are per lane
      const realv fx = u * (real)width - R(0.5);
      const realv fy = clamp(v * (real)height - R(0.5), R(0.0), (real)(height - 1));
      const realv x0f = floor(fx), y0f = floor(fy);
      const realv tx = fx - x0f, ty = fy - y0f;
      intv x0 = convert_intv(x0f);  // u in [0, 1]: x0 in [-1, width - 1] (rounding: up to width)
      x0 = select(x0, x0 + width, x0 < 0);
      x0 = select(x0, x0 - width, x0 >= width);
      const intv x1 = select(x0 + 1, (intv)(0), x0 + 1 >= width);
      // min(vector, vector): Oclgrind 21.10 returns garbage lanes for the integer min(vector, scalar)
      const intv y0 = convert_intv(y0f), y1 = min(y0 + 1, (intv)(height - 1));
      const intv r0 = y0 * width, r1 = y1 * width;
      int a00[BRDFBAKE_LANES], a10[BRDFBAKE_LANES], a01[BRDFBAKE_LANES], a11[BRDFBAKE_LANES];
      vstore_lanes(r0 + x0, 0, a00);
      vstore_lanes(r0 + x1, 0, a10);
      vstore_lanes(r1 + x0, 0, a01);
      vstore_lanes(r1 + x1, 0, a11);
      float c[12][BRDFBAKE_LANES];
      for (int q = 0; q < BRDFBAKE_LANES; ++q) {
        const float3 t00 = vload3((size_t)a00[q], src), t10 = vload3((size_t)a10[q], src);
        const float3 t01 = vload3((size_t)a01[q], src), t11 = vload3((size_t)a11[q], src);
        c[0][q] = t00.x; c[1][q] = t00.y; c[2][q] = t00.z;
        c[3][q] = t10.x; c[4][q] = t10.y; c[5][q] = t10.z;
        c[6][q] = t01.x; c[7][q] = t01.y; c[8][q] = t01.z;
        c[9][q] = t11.x; c[10][q] = t11.y; c[11][q] = t11.z;
      }
      const realv w00 = w * (R(1.0) - tx) * (R(1.0) - ty), w10 = w * tx * (R(1.0) - ty);
      const realv w01 = w * (R(1.0) - tx) * ty, w11 = w * tx * ty;
      sr += w00 * convert_realv(vload_lanes(0, c[0])) + w10 * convert_realv(vload_lanes(0, c[3])) +
            w01 * convert_realv(vload_lanes(0, c[6])) + w11 * convert_realv(vload_lanes(0, c[9]));
      sg += w00 * convert_realv(vload_lanes(0, c[1])) + w10 * convert_realv(vload_lanes(0, c[4])) +
            w01 * convert_realv(vload_lanes(0, c[7])) + w11 * convert_realv(vload_lanes(0, c[10]));
      sb += w00 * convert_realv(vload_lanes(0, c[2])) + w10 * convert_realv(vload_lanes(0, c[5])) +
            w01 * convert_realv(vload_lanes(0, c[8])) + w11 * convert_realv(vload_lanes(0, c[11]));
      wsum += w;
    }
  real out_r[BRDFBAKE_LANES], out_g[BRDFBAKE_LANES], out_b[BRDFBAKE_LANES];
  vstore_lanes(sr / wsum, 0, out_r);
  vstore_lanes(sg / wsum, 0, out_g);
  vstore_lanes(sb / wsum, 0, out_b);
  const int n = min(BRDFBAKE_LANES, size - i0);
  for (int q = 0; q < n; ++q)
    vstore3((float3)((float)out_r[q], (float)out_g[q], (float)out_b[q]),
            ((size_t)(face - face0) * (size_t)size + (size_t)j) * (size_t)size + (size_t)(i0 + q), dst);
}

// ---- Padded levels -------------------------------------------------------------------------------

// Copies an unpadded cube (6 faces of size x size, row-major) into the interior of a padded level.
kernel void cube_to_padded(global const float4* src, int size, global float4* chain, int offset) {
  const int i = (int)get_global_id(0), gj = (int)get_global_id(1);
  if (i >= size || gj >= 6 * size) return;
  const int face = gj / size, j = gj % size;
  chain[cube_padded_index((size_t)offset, size, face, i, j)] =
      src[((size_t)face * (size_t)size + (size_t)j) * (size_t)size + (size_t)i];
}

// Fills the one-texel border of every face of a padded level from the faces' interiors
// (cube_border_texel). Global id (x, face * (size + 2) + y) over the padded faces; interior
// positions do nothing.
kernel void cube_fill_border(global float4* chain, int offset, int size) {
  const int p = size + 2;
  const int x = (int)get_global_id(0), gy = (int)get_global_id(1);
  if (x >= p || gy >= 6 * p) return;
  const int face = gy / p, i = x - 1, j = gy % p - 1;
  if (i >= 0 && i < size && j >= 0 && j < size) return;
  chain[cube_padded_index((size_t)offset, size, face, i, j)] =
      cube_border_texel(chain, (size_t)offset, size, face, i, j);
}

// One texel of a coarser level from the finer one: the solid-angle-weighted mean of the finer
// texels under its footprint (fractional coverage where the sizes are not in a 2:1 ratio), so that
// every level holds the same radiant power as the level above it. Interior only; the border is
// filled afterwards. Global id (i, face * dst_size + j).
kernel void cube_downsample(global float4* chain, int src_offset, int src_size, int dst_offset, int dst_size) {
  const int i = (int)get_global_id(0), gj = (int)get_global_id(1);
  if (i >= dst_size || gj >= 6 * dst_size) return;
  const int face = gj / dst_size, j = gj % dst_size;
  const real r = (real)src_size / (real)dst_size;
  const real x0 = (real)i * r, x1 = (real)(i + 1) * r, y0 = (real)j * r, y1 = (real)(j + 1) * r;
  const int sx0 = (int)floor(x0), sx1 = min((int)ceil(x1), src_size);
  const int sy0 = (int)floor(y0), sy1 = min((int)ceil(y1), src_size);
  real4 sum = (real4)(R(0.0));
  real wsum = R(0.0);
  for (int sy = sy0; sy < sy1; ++sy) {
    const real cy = fmin(y1, (real)(sy + 1)) - fmax(y0, (real)sy);
    const real b = R(2.0) * ((real)sy + R(0.5)) / (real)src_size - R(1.0);
    for (int sx = sx0; sx < sx1; ++sx) {
      const real cx = fmin(x1, (real)(sx + 1)) - fmax(x0, (real)sx);
      const real a = R(2.0) * ((real)sx + R(0.5)) / (real)src_size - R(1.0);
      const real w = cx * cy * cube_area_element(a, b);
      sum += w * convert_real4(chain[cube_padded_index((size_t)src_offset, src_size, face, sx, sy)]);
      wsum += w;
    }
  }
  const real4 texel = sum / wsum;
  chain[cube_padded_index((size_t)dst_offset, dst_size, face, i, j)] =
      (float4)((float)texel.x, (float)texel.y, (float)texel.z, 1.0f);
}

// One texel of a cube of dst_size from a padded cube level of src_size: the mean of k x k seamless
// bilinear samples over the texel's footprint, weighted by solid angle (cube inputs of another
// size than --size).
kernel void cube_resample(global const float4* chain, int src_offset, int src_size, global float4* dst,
                          int dst_size, int k) {
  const int i = (int)get_global_id(0), gj = (int)get_global_id(1);
  if (i >= dst_size || gj >= 6 * dst_size) return;
  const int face = gj / dst_size, j = gj % dst_size;
  const int p = src_size + 2;
  real4 sum = (real4)(R(0.0));
  real wsum = R(0.0);
  for (int sy = 0; sy < k; ++sy)
    for (int sx = 0; sx < k; ++sx) {
      const real a = R(2.0) * ((real)i + ((real)sx + R(0.5)) / (real)k) / (real)dst_size - R(1.0);
      const real b = R(2.0) * ((real)j + ((real)sy + R(0.5)) / (real)k) / (real)dst_size - R(1.0);
      const real w = cube_area_element(a, b);
      real na, nb;
      const int nf = cube_face_coords(cube_plane_point(face, a, b), &na, &nb);
      const real x = R(0.5) * (na + R(1.0)) * (real)src_size + R(0.5);
      const real y = R(0.5) * (nb + R(1.0)) * (real)src_size + R(0.5);
      const int x0 = clamp((int)x, 0, src_size), y0 = clamp((int)y, 0, src_size);
      const real tx = x - (real)x0, ty = y - (real)y0;
      const size_t at = (size_t)src_offset + ((size_t)nf * (size_t)p + (size_t)y0) * (size_t)p + (size_t)x0;
      const real4 v = (R(1.0) - ty) * ((R(1.0) - tx) * convert_real4(chain[at]) + tx * convert_real4(chain[at + 1])) +
                      ty * ((R(1.0) - tx) * convert_real4(chain[at + (size_t)p]) +
                            tx * convert_real4(chain[at + (size_t)p + 1]));
      sum += w * v;
      wsum += w;
    }
  const real4 texel = sum / wsum;
  dst[((size_t)face * (size_t)dst_size + (size_t)j) * (size_t)dst_size + (size_t)i] =
      (float4)((float)texel.x, (float)texel.y, (float)texel.z, 1.0f);
}
