// What a device can do at best, measured on itself: the peak rate of fused multiply-adds and the
// streaming bandwidth of global memory (`brdfbake report --kinds kernels`, host/src/report/kernels.cpp,
// docs/REPORT.md "Kernels against the device's peak"). The roofline the hot kernels are placed on.
//
// peak_fma: each work-item runs 8 independent chains of x = x * b + c on wide vectors (float16, or
// double16 with BRDFBAKE_FP64): PoCL's CPU device reaches its peak only with explicit vectors (43
// GFLOP/s with scalar loops against 257 with float16 on the project's 2 cores), and independent
// chains keep the FMA pipelines full on every device. b < 1 and c = 1 - b keep every lane at 1 (no
// overflow, no denormals, which would be slow on a CPU). Flops: 2 x 16 lanes x 8 chains x
// iterations per work-item, exactly (the host multiplies; no division, no transcendental).
#ifdef BRDFBAKE_FP64
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
typedef double real;
typedef double2 real2;
typedef double4 real4;
typedef double8 real8;
typedef double16 realw;
#else
typedef float real;
typedef float2 real2;
typedef float4 real4;
typedef float8 real8;
typedef float16 realw;
#endif

kernel void peak_fma(global real* out, const int iterations, const real b) {
  const real c = (real)1 - b;
  const realw bw = (realw)(b), cw = (realw)(c);
  const realw start = (realw)((real)get_global_id(0) * (real)1e-9 + (real)1);
  realw x0 = start, x1 = start + (realw)(1e-3), x2 = start + (realw)(2e-3), x3 = start + (realw)(3e-3);
  realw x4 = start - (realw)(1e-3), x5 = start - (realw)(2e-3), x6 = start - (realw)(3e-3), x7 = start * bw;
  for (int i = 0; i < iterations; ++i) {
    x0 = fma(x0, bw, cw);
    x1 = fma(x1, bw, cw);
    x2 = fma(x2, bw, cw);
    x3 = fma(x3, bw, cw);
    x4 = fma(x4, bw, cw);
    x5 = fma(x5, bw, cw);
    x6 = fma(x6, bw, cw);
    x7 = fma(x7, bw, cw);
  }
  const realw s = ((x0 + x1) + (x2 + x3)) + ((x4 + x5) + (x6 + x7));
  const real8 h = s.lo + s.hi;
  const real4 q = h.lo + h.hi;
  const real2 d = q.lo + q.hi;
  out[get_global_id(0)] = d.x + d.y;  // kept, so that no compiler drops the chains
}

// STREAM's triad on float4: a = b + s c. Bytes: 3 x 16 per work-item (two reads and a write; a
// write-allocate cache may read a too, which is not counted: the figure is what the kernel asks for).
kernel void stream_triad(global float4* a, global const float4* b, global const float4* c, const float s) {
  const size_t i = get_global_id(0);
  a[i] = b[i] + s * c[i];
}
