// Fresnel reflectance tables: 1-D over cos_theta (channels r, g, b) or 2-D over cos_theta x one
// material parameter (F0 or IOR, one channel).
//
// Compile-time choices (host/src/families/fresnel/opencl.cpp defines exactly one model, the chunk and lane counts,
// and BRDFBAKE_FRESNEL_2D for 2-D tables). Per channel the model reads FRESNEL_NPARAMS parameters:
//   BRDFBAKE_FRESNEL_SCHLICK           f0, f90
//   BRDFBAKE_FRESNEL_SCHLICK_METALLIC  base_color, metallic, dielectric_f0
//   BRDFBAKE_FRESNEL_SCHLICK_IOR       ior_outside, ior          (F0 from the pair)
//   BRDFBAKE_FRESNEL_DIELECTRIC        ior_outside, ior          (eta = ior / ior_outside)
//   BRDFBAKE_FRESNEL_CONDUCTOR         n, k                      (seen from air)
//   BRDFBAKE_FRESNEL_F82_TINT          f0, f82_tint
//   BRDFBAKE_FRESNEL_EMPIRICAL         bias, scale, power
// `params` holds them channel after channel (3 x FRESNEL_NPARAMS for 1-D tables; 1 x for 2-D,
// where ys[j] replaces parameter FRESNEL_Y_PARAM of row j: F0 or IOR).
//
// Work decomposition: work-item (g, j) computes BRDFBAKE_FRESNEL_CHUNKS x BRDFBAKE_LANES
// consecutive cells of row j, one vector of lanes at a time: PoCL's CPU device reaches its peak
// only with explicit vector types (BRDFBAKE_LANES: 16 in fp32, 8 in fp64, common/real.clh). The host
// pads xs to a whole number of work-items (so every vload is in bounds); the stores stop at `width`.
// Output: floats, row-major, channels interleaved: out[(j * width + i) * channels + c].
#include "common/real.clh"
#include "common/fresnel.clh"

#if !defined(BRDFBAKE_FRESNEL_CHUNKS)
#error "the host defines BRDFBAKE_FRESNEL_CHUNKS (vectors of cells per work-item)"
#endif

#if defined(BRDFBAKE_FRESNEL_SCHLICK)
#define FRESNEL_NPARAMS 2
#define FRESNEL_Y_PARAM 0
inline realv fresnel_model(realv c, const real* p) { return fresnel_schlick_v(c, p[0], p[1]); }
#elif defined(BRDFBAKE_FRESNEL_SCHLICK_METALLIC)
#define FRESNEL_NPARAMS 3
#define FRESNEL_Y_PARAM 0
inline realv fresnel_model(realv c, const real* p) {
  return fresnel_schlick_v(c, schlick_metallic_f0(p[0], p[1], p[2]), R(1.0));
}
#elif defined(BRDFBAKE_FRESNEL_SCHLICK_IOR)
#define FRESNEL_NPARAMS 2
#define FRESNEL_Y_PARAM 1
inline realv fresnel_model(realv c, const real* p) {
  return fresnel_schlick_v(c, f0_from_ior(p[0], p[1]), R(1.0));
}
#elif defined(BRDFBAKE_FRESNEL_DIELECTRIC)
#define FRESNEL_NPARAMS 2
#define FRESNEL_Y_PARAM 1
inline realv fresnel_model(realv c, const real* p) { return fresnel_dielectric_v(c, p[1] / p[0]); }
#elif defined(BRDFBAKE_FRESNEL_CONDUCTOR)
#define FRESNEL_NPARAMS 2
#define FRESNEL_Y_PARAM 0
inline realv fresnel_model(realv c, const real* p) { return fresnel_conductor_v(c, p[0], p[1]); }
#elif defined(BRDFBAKE_FRESNEL_F82_TINT)
#define FRESNEL_NPARAMS 2
#define FRESNEL_Y_PARAM 0
inline realv fresnel_model(realv c, const real* p) { return fresnel_f82_tint_v(c, p[0], p[1]); }
#elif defined(BRDFBAKE_FRESNEL_EMPIRICAL)
#define FRESNEL_NPARAMS 3
#define FRESNEL_Y_PARAM 0
inline realv fresnel_model(realv c, const real* p) { return fresnel_empirical_v(c, p[0], p[1], p[2]); }
#else
#error "the host defines one BRDFBAKE_FRESNEL_<MODEL>"
#endif


// Lanes [8 * g, 8 * g + 8) of a result, as floats.
inline float8 lanes8(realv v, int g) {
#if BRDFBAKE_LANES == 16
  const real8 h = g == 0 ? v.lo : v.hi;
#else
  const real8 h = v;
  (void)g;
#endif
#ifdef BRDFBAKE_FP64
  return convert_float8(h);
#else
  return h;
#endif
}

// n (<= 8) cells of one channel from `row + i0`.
inline void store_f8(global float* row, int i0, float8 f, int n) {
  if (n == 8) {
    vstore8(f, 0, row + i0);
  } else {
    const float lanes[8] = {f.s0, f.s1, f.s2, f.s3, f.s4, f.s5, f.s6, f.s7};
    for (int l = 0; l < n; ++l) row[i0 + l] = lanes[l];
  }
}

// n (<= 8) cells of r, g, b interleaved from `cell`: 8 full cells are three float8 stores.
inline void store_rgb8(global float* cell, float8 r, float8 g, float8 b, int n) {
  if (n == 8) {
    vstore8((float8)(r.s0, g.s0, b.s0, r.s1, g.s1, b.s1, r.s2, g.s2), 0, cell);
    vstore8((float8)(b.s2, r.s3, g.s3, b.s3, r.s4, g.s4, b.s4, r.s5), 1, cell);
    vstore8((float8)(g.s5, b.s5, r.s6, g.s6, b.s6, r.s7, g.s7, b.s7), 2, cell);
  } else {
    const float rl[8] = {r.s0, r.s1, r.s2, r.s3, r.s4, r.s5, r.s6, r.s7};
    const float gl[8] = {g.s0, g.s1, g.s2, g.s3, g.s4, g.s5, g.s6, g.s7};
    const float bl[8] = {b.s0, b.s1, b.s2, b.s3, b.s4, b.s5, b.s6, b.s7};
    for (int l = 0; l < n; ++l) vstore3((float3)(rl[l], gl[l], bl[l]), 0, cell + 3 * l);
  }
}

#ifdef BRDFBAKE_FRESNEL_2D

kernel void fresnel_table(global float* out, global const real* xs, global const real* ys,
                          const int width, const int height, constant real* params) {
  const int j = (int)get_global_id(1);
  if (j >= height) return;
  real p[FRESNEL_NPARAMS];
  for (int k = 0; k < FRESNEL_NPARAMS; ++k) p[k] = params[k];
  p[FRESNEL_Y_PARAM] = ys[j];
  global float* row = out + (size_t)j * (size_t)width;
  const int first = (int)get_global_id(0) * BRDFBAKE_FRESNEL_CHUNKS * BRDFBAKE_LANES;
  for (int chunk = 0; chunk < BRDFBAKE_FRESNEL_CHUNKS; ++chunk) {
    const int i0 = first + chunk * BRDFBAKE_LANES;
    if (i0 >= width) return;
    const realv f = fresnel_model(vload_lanes(0, xs + i0), p);
    for (int g = 0; g < BRDFBAKE_LANES / 8 && i0 + 8 * g < width; ++g)
      store_f8(row, i0 + 8 * g, lanes8(f, g), min(8, width - i0 - 8 * g));
  }
}

#else  // 1-D, RGB

kernel void fresnel_table(global float* out, global const real* xs, global const real* ys,
                          const int width, const int height, constant real* params) {
  (void)ys;
  (void)height;
  real pr[FRESNEL_NPARAMS], pg[FRESNEL_NPARAMS], pb[FRESNEL_NPARAMS];
  for (int k = 0; k < FRESNEL_NPARAMS; ++k) {
    pr[k] = params[k];
    pg[k] = params[FRESNEL_NPARAMS + k];
    pb[k] = params[2 * FRESNEL_NPARAMS + k];
  }
  const int first = (int)get_global_id(0) * BRDFBAKE_FRESNEL_CHUNKS * BRDFBAKE_LANES;
  for (int chunk = 0; chunk < BRDFBAKE_FRESNEL_CHUNKS; ++chunk) {
    const int i0 = first + chunk * BRDFBAKE_LANES;
    if (i0 >= width) return;
    const realv c = vload_lanes(0, xs + i0);
    const realv r = fresnel_model(c, pr);
    const realv g = fresnel_model(c, pg);
    const realv b = fresnel_model(c, pb);
    for (int h = 0; h < BRDFBAKE_LANES / 8 && i0 + 8 * h < width; ++h)
      store_rgb8(out + 3 * (size_t)(i0 + 8 * h), lanes8(r, h), lanes8(g, h), lanes8(b, h),
                 min(8, width - i0 - 8 * h));
  }
}

#endif
