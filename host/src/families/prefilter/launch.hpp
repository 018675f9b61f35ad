// Internal: the prefilter's three kernels (kernels/prefilter.cl) with their typed arguments, Real
// being the precision's cl_float or cl_double: prefilter_level (the sampling estimator),
// prefilter_pyramid (the quadrature, a walk per texel) and prefilter_pyramid_strips (the quadrature,
// blocks of 8 x 8 texels).
#pragma once

#include <cmath>

#include "env/cube.hpp"
#include "runtime/cl.hpp"

namespace brdfbake::detail {

// One filtered level: a launch of prefilter_level, with the real-typed alpha argument.
template <class Real>
cl::Event launch_level(cl::Program& prog, const cl::Buffer& out, int size, const PaddedChain& chain,
                       const cl::Buffer& samples, int n_samples, const cl::Buffer& bright, int n_bright, double alpha,
                       const cl::EnqueueArgs& rows) {
  cl::KernelFunctor<cl::Buffer, cl_int, cl::Buffer, cl::Buffer, cl_int, cl::Buffer, cl_int, cl::Buffer, cl_int, Real>
      level(prog, "prefilter_level");
  return level(rows, out, size, chain.buffer, chain.info_buffer, chain.levels, samples, n_samples, bright, n_bright,
               static_cast<Real>(alpha));
}

template <class Real>
cl::Event launch_pyramid(cl::Program& prog, const cl::Buffer& out, int size, const cl::Buffer& pyramid,
                         const cl::Buffer& info, int levels, const cl::Buffer& cos_core, const cl::Buffer& band,
                         const cl::Buffer& bright, int n_bright, double alpha, const cl::EnqueueArgs& rows) {
  cl::KernelFunctor<cl::Buffer, cl_int, cl::Buffer, cl::Buffer, cl_int, cl::Buffer, cl::Buffer, cl::Buffer, cl_int,
                    Real>
      level(prog, "prefilter_pyramid");
  return level(rows, out, size, pyramid, info, levels, cos_core, band, bright, n_bright, static_cast<Real>(alpha));
}

// The bright texels as the strips kernel reads them: each texel's points at the full subdivision
// (fine, near a texel's horizon) and at the lobe's (coarse, elsewhere), both grouped by texel, and
// the texels' directions.
struct StripBright {
  cl::Buffer fine, coarse, dirs;
  int fine_stride = 0, coarse_stride = 0;  // the padded point counts (the lists' SoA strides)
  int fine_per = 0, coarse_per = 0;        // points per texel
  int texels = 0;
  double reach = 0.0;  // a bright texel's footprint radius and a margin, in radians
};

// The strips' launch (prefilter_pyramid_strips): prefilter_pyramid's arguments and power2, 1/alpha
// where it is a whole number up to 64 (Charlie's D by multiplication), else 0.
template <class Real>
cl::Event launch_strips(cl::Program& prog, const cl::Buffer& out, int size, const cl::Buffer& pyramid,
                        const cl::Buffer& info, int levels, const cl::Buffer& cos_core, const cl::Buffer& band,
                        const StripBright& b, double alpha, const cl::EnqueueArgs& rows) {
  cl::KernelFunctor<cl::Buffer, cl_int, cl::Buffer, cl::Buffer, cl_int, cl::Buffer, cl::Buffer, Real, cl_int,
                    cl::Buffer, cl::Buffer, cl_int, cl_int, cl_int, cl_int, cl::Buffer, cl_int, Real>
      level(prog, "prefilter_pyramid_strips");
  const double n = std::round(1.0 / alpha);
  const cl_int power2 = n >= 1.0 && n <= 64.0 && std::fabs(1.0 / alpha - n) < 1e-9 * n ? static_cast<cl_int>(n) : 0;
  return level(rows, out, size, pyramid, info, levels, cos_core, band, static_cast<Real>(alpha), power2, b.fine,
               b.coarse, b.fine_stride, b.coarse_stride, b.fine_per, b.coarse_per, b.dirs, b.texels,
               static_cast<Real>(b.reach));
}

}  // namespace brdfbake::detail
