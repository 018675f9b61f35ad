// The prefiltered radiance mip chain on the device (kernels/cubemap.cl, kernels/prefilter.cl).
//
// Steps (docs/CONVENTIONS.md, "Environment maps", says what each level holds):
//   1. the environment becomes a cube of --size on the device: level 0, the mirror (roughness 0);
//   2. environment sampling: the brightest texels of level 0 (find_bright_texels) are taken out into
//      an explicit list; the rest, in padded faces, is reduced to a mip chain down to 1x1, each level
//      the solid-angle-weighted mean of the one above it;
//   3. every output level l >= 1 is filtered by importance sampling of its lobe with filtered
//      importance sampling from the rest's chain, plus the exact sum over the bright texels
//      (kernels/prefilter.cl derives the estimator).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <future>
#include <thread>

#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/math/sampling.hpp"
#include "brdfbake/version.hpp"
#include "env_internal.hpp"
#include "env_lobes.hpp"
#include "runtime/launch.hpp"
#include "runtime/program.hpp"

namespace brdfbake {
namespace {

using math::kPi;
constexpr int kMaxSize = kPrefilterMaxSize;
constexpr int kMaxSamples = kPrefilterMaxSamples;
constexpr int kVectorWidth = 8;  // BRDFBAKE_LANES: sample and point arrays are padded to a multiple
constexpr int kStripRows = 4;    // BRDFBAKE_STRIP_ROWS (kernels/prefilter.cl): blocks of 8 x 8 texels

// --max-error: sample counts tried per level, and the cap.
constexpr int kSearchStart = 32;
constexpr int kSearchMax = 8192;

std::string fmt(double v, const char* f = "%.6g") {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

double luminance(const float* rgb) {
  return 0.2126 * double(rgb[0]) + 0.7152 * double(rgb[1]) + 0.0722 * double(rgb[2]);
}

size_t face_texels(int size) { return 6u * static_cast<size_t>(size) * static_cast<size_t>(size); }

// The exact solid angle of every texel (i, j) of a face of `size`, row-major: math::cube_texel_solid_angle
// from one grid of its antiderivative F(a, b) = atan2(a b, sqrt(1 + a^2 + b^2)) at the texel corners
// ((size + 1)^2 atan2, not 4 size^2; the same values, summed in the same order).
std::vector<double> texel_solid_angles(int size) {
  const size_t n = size_t(size) + 1;
  std::vector<double> corner(n * n);
  for (size_t j = 0; j < n; ++j)
    for (size_t i = 0; i < n; ++i) {
      const double a = 2.0 * double(i) / size - 1.0, b = 2.0 * double(j) / size - 1.0;
      corner[j * n + i] = std::atan2(a * b, std::sqrt(1.0 + a * a + b * b));
    }
  std::vector<double> omega(size_t(size) * size_t(size));
  for (size_t j = 0; j < size_t(size); ++j)
    for (size_t i = 0; i < size_t(size); ++i)
      omega[j * size_t(size) + i] =
          corner[(j + 1) * n + i + 1] - corner[(j + 1) * n + i] - corner[j * n + i + 1] + corner[j * n + i];
  return omega;
}


// The lobe samples of one level in the frame (t, b, R), as the arrays x, y, z, weight, lod_k
// (kernels/prefilter.cl): N Hammersley points, h from D(h) (n.h), l = 2 (n.h) h - n, kept when
// n.l > 0, padded to a multiple of the vector width with weight 0.
std::vector<double> lobe_samples(EnvDistribution dist, double alpha, int n, int source_size, bool fis,
                                 double lod_bias, int* kept) {
  std::vector<double> x, y, z, w, lod;
  const double omega_texel = (2.0 / source_size) * (2.0 / source_size);
  for (int k = 0; k < n; ++k) {
    const math::Point2 u = math::hammersley(static_cast<uint32_t>(k), static_cast<uint32_t>(n));
    const double u1 = u.u, u2 = u.v;
    double cos_h, sin_h;
    if (dist == EnvDistribution::Ggx) {  // Walter et al. 2007, eq. 35: tan^2 = alpha^2 u / (1 - u)
      const double t2 = alpha * alpha * u1 / (1.0 - u1);
      cos_h = 1.0 / std::sqrt(1.0 + t2);
      sin_h = std::sqrt(t2) * cos_h;
    } else {  // Estevez & Kulla 2017: sin = u^(alpha / (2 alpha + 1))
      sin_h = std::pow(u1, alpha / (2.0 * alpha + 1.0));
      cos_h = std::sqrt(std::max(0.0, (1.0 - sin_h) * (1.0 + sin_h)));
    }
    const double phi = 2.0 * kPi * u2;
    const double lz = 2.0 * cos_h * cos_h - 1.0;
    if (lz <= 0.0) continue;
    const double d = detail::env_lobe_d(dist, cos_h, alpha);
    // p(l) = D / 4 (dl = 4 (n.h) dh with v = n); the sample covers 1 / (N p) = 4 / (N D)
    const double omega_sample = 4.0 / (n * d);
    x.push_back(2.0 * cos_h * sin_h * std::cos(phi));
    y.push_back(2.0 * cos_h * sin_h * std::sin(phi));
    z.push_back(lz);
    w.push_back(lz);
    // without filtered importance sampling every sample reads level 0, wherever it lands on the
    // face (a lod far below 0 survives the kernel's texel-size correction and clamps to 0)
    lod.push_back(fis ? 0.5 * std::log2(omega_sample / omega_texel) + lod_bias : -1e3);
  }
  *kept = static_cast<int>(x.size());
  while (x.size() % kVectorWidth != 0 || x.empty()) {
    x.push_back(0.0);
    y.push_back(0.0);
    z.push_back(1.0);
    w.push_back(0.0);
    lod.push_back(0.0);
  }
  std::vector<double> out;
  for (const auto* v : {&x, &y, &z, &w, &lod}) out.insert(out.end(), v->begin(), v->end());
  return out;
}

// Sub-cells per texel side of the bright texels' footprints (bright_texel_points): enough to resolve
// the lobe (4 texels across its width: 2 alpha for GGX, 1 rad for Charlie's ring), and 4 where the
// kernel's kink at the horizon matters (Charlie; GGX with K'(0) / K(1) = 4 alpha^4 / (1 + alpha^2)^2
// > 1e-3), so that a bright texel at a texel's horizon is cut where the reference cuts it; at most
// kMaxBrightPoints points in all.
constexpr int kMaxBrightPoints = 4096;
// The lobe's part alone: what a bright texel needs away from a texel's horizon (the strips kernel
// takes these "coarse" points there and the full subdivision only near the horizon).
int bright_lobe_subdivision(EnvDistribution dist, double alpha, int source_size) {
  const double width = dist == EnvDistribution::Ggx ? 2.0 * alpha : 1.0;
  return static_cast<int>(std::clamp(std::ceil(4.0 * (2.0 / source_size) / width), 1.0, 4.0));
}
// Whether one point a bright texel resolves the lobe: the tent's whole support (2 texels, 4 / S in
// face coordinates) at most a quarter of the lobe's width.
bool bright_single_point(EnvDistribution dist, double alpha, int source_size) {
  const double width = dist == EnvDistribution::Ggx ? 2.0 * alpha : 1.0;
  return 4.0 * (4.0 / source_size) <= width;
}
// Groups of `per` points (one bright texel's, bright_texel_points' layout with SoA stride `stride`)
// merged into one each: the sum of their values at their weighted mean direction (the weights,
// proportional to the sub-cells' solid angles within a texel, are the values' sums).
std::vector<double> merge_bright_points(const std::vector<double>& pts, size_t stride, size_t per, size_t texels) {
  const size_t n = std::max<size_t>(texels, 1);
  std::vector<double> out(6 * n, 0.0);
  if (texels == 0) out[2] = 1.0;  // a padding point as bright_texel_points leaves it
  for (size_t t = 0; t < texels; ++t) {
    double d[3] = {0, 0, 0}, v[3] = {0, 0, 0};
    for (size_t k = t * per; k < (t + 1) * per; ++k) {
      const double w = pts[3 * stride + k] + pts[4 * stride + k] + pts[5 * stride + k];
      for (size_t c = 0; c < 3; ++c) {
        d[c] += w * pts[c * stride + k];
        v[c] += pts[(3 + c) * stride + k];
      }
    }
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (size_t c = 0; c < 3; ++c) {
      out[c * n + t] = len > 0.0 ? d[c] / len : pts[c * stride + t * per];
      out[(3 + c) * n + t] = v[c];
    }
  }
  return out;
}

int bright_subdivision(EnvDistribution dist, double alpha, int source_size, size_t bright) {
  double q = bright_lobe_subdivision(dist, alpha, source_size);
  const double a4 = alpha * alpha * alpha * alpha;
  if (dist == EnvDistribution::Charlie || 4.0 * a4 / ((1.0 + alpha * alpha) * (1.0 + alpha * alpha)) > 1e-3) q = 4.0;
  q = std::min(q, std::floor(std::sqrt(double(kMaxBrightPoints) / (4.0 * double(std::max<size_t>(bright, 1))))));
  return static_cast<int>(std::clamp(q, 1.0, 4.0));
}

// The sampling estimator's default lobe samples per texel: its error is the mip blur of filtered
// importance sampling, which falls like 1/N (docs/BENCHMARKS.md: about 1-5% RMS at 1024 on the 256^2
// chain); the quadrature is the default estimator.
int default_samples(int level, int levels) {
  (void)level;
  (void)levels;
  return 1024;
}

cl::Buffer real_buffer(Device::Impl& dev, Precision p, const std::vector<double>& v) {
  if (p == Precision::Fp64)
    return cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(double),
                      const_cast<double*>(v.data()));
  std::vector<float> f(v.size());
  for (size_t k = 0; k < v.size(); ++k) f[k] = static_cast<float>(v[k]);
  return cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, f.size() * sizeof(float), f.data());
}

cl::Program program(Device::Impl& dev, const char* file, Precision p,
                    std::vector<std::pair<std::string, std::string>> defines = {}) {
  detail::ProgramSpec ps;
  ps.file = file;
  ps.precision = p;
  ps.defines = std::move(defines);
  return detail::build_program(dev, ps);
}

// Device buffers stay within CL_DEVICE_MAX_MEM_ALLOC_SIZE (GPUs allow a quarter of their memory or
// less in one allocation): a larger one is refused here with its size, not by the driver.
void check_allocation(const Device::Impl& dev, size_t bytes, const std::string& what) {
  if (dev.info.max_alloc == 0 || bytes <= dev.info.max_alloc) return;
  throw Error(what + " needs a device buffer of " + std::to_string(bytes >> 20) + " MiB, more than '" + dev.info.name +
              "' allocates at once (CL_DEVICE_MAX_MEM_ALLOC_SIZE, " + std::to_string(dev.info.max_alloc >> 20) +
              " MiB): give a smaller size or input, or another device");
}

// The filter's program (kernels/prefilter.cl) for a spec's lobe and precision.
cl::Program filter_program(Device::Impl& dev, const PrefilterSpec& s) {
  const char* lobe_define = s.distribution == EnvDistribution::Charlie ? "BRDFBAKE_ENV_CHARLIE" : "BRDFBAKE_ENV_GGX";
  return program(dev, "prefilter.cl", s.precision,
                 {{lobe_define, "1"}, {"BRDFBAKE_STRIP_ROWS", std::to_string(kStripRows)}});
}

cl::NDRange cube_range(int size) { return cl::NDRange(static_cast<size_t>(size), 6u * static_cast<size_t>(size)); }

// The padded source chain on the device: every level of the rest cube down to 1x1.
struct Chain {
  cl::Buffer buffer;
  std::vector<cl_int> info;  // offset, size per level
  int levels = 0;
  cl::Buffer info_buffer;
};

// Builds the chain from an unpadded RGBA cube already on the device; appends the kernel events.
Chain build_chain(Device::Impl& dev, cl::Program& cube_prog, const cl::Buffer& level0, int size,
                  std::vector<cl::Event>& events) {
  Chain c;
  size_t total = 0;
  for (int s = size;; s = std::max(1, s / 2)) {
    c.info.push_back(static_cast<cl_int>(total));
    c.info.push_back(s);
    total += 6u * static_cast<size_t>(s + 2) * static_cast<size_t>(s + 2);
    ++c.levels;
    if (s == 1) break;
  }
  if (total > static_cast<size_t>(std::numeric_limits<cl_int>::max()))
    throw Error("cube of size " + std::to_string(size) + " is too large for the source chain");
  c.buffer = cl::Buffer(dev.context, CL_MEM_READ_WRITE, total * sizeof(cl_float4));
  c.info_buffer = cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, c.info.size() * sizeof(cl_int),
                             c.info.data());
  cl::KernelFunctor<cl::Buffer, cl_int, cl::Buffer, cl_int> to_padded(cube_prog, "cube_to_padded");
  cl::KernelFunctor<cl::Buffer, cl_int, cl_int> fill_border(cube_prog, "cube_fill_border");
  cl::KernelFunctor<cl::Buffer, cl_int, cl_int, cl_int, cl_int> downsample(cube_prog, "cube_downsample");
  events.push_back(to_padded(cl::EnqueueArgs(dev.queue, cube_range(size)), level0, size, c.buffer, 0));
  for (int m = 0; m < c.levels; ++m) {
    const int s = c.info[size_t(2 * m + 1)];
    if (m > 0)
      events.push_back(downsample(cl::EnqueueArgs(dev.queue, cube_range(s)), c.buffer, c.info[size_t(2 * m - 2)],
                                  c.info[size_t(2 * m - 1)], c.info[size_t(2 * m)], s));
    events.push_back(fill_border(cl::EnqueueArgs(dev.queue, cube_range(s + 2)), c.buffer, c.info[size_t(2 * m)], s));
  }
  return c;
}

double sum_seconds(const std::vector<cl::Event>& events) {
  double s = 0.0;
  for (const auto& e : events) s += detail::event_seconds(e);
  return s;
}

// One filtered level: a launch of prefilter_level, with the real-typed alpha argument.
template <class Real>
cl::Event launch_level(cl::Program& prog, const cl::Buffer& out, int size, const Chain& chain,
                       const cl::Buffer& samples, int n_samples, const cl::Buffer& bright, int n_bright, double alpha,
                       const cl::EnqueueArgs& rows) {
  cl::KernelFunctor<cl::Buffer, cl_int, cl::Buffer, cl::Buffer, cl_int, cl::Buffer, cl_int, cl::Buffer, cl_int, Real>
      level(prog, "prefilter_level");
  return level(rows, out, size, chain.buffer, chain.info_buffer, chain.levels, samples, n_samples, bright, n_bright,
               static_cast<Real>(alpha));
}

// ---- The quadrature's pyramid (kernels/common/env_sampling.clh, env_pyramid_sum) ----------------

struct Pyramid {
  std::vector<float> data;   // every level's ten arrays (gx gy gz mx my mz omega r g b)
  std::vector<cl_int> info;  // offset (floats) and face size per level
  std::vector<int> sizes;
  int levels = 0;
};

// Quadtree order within a face (kernels/common/env_sampling.clh): texel (i, j) of a level `depth`
// levels below the top level (face size top_size) has index root * 4^depth + interleave(i, j) of
// its position in its root's block, with root = (j >> depth) top_size + (i >> depth); the four
// children of texel p are 4p .. 4p + 3.
size_t quadtree_index(int i, int j, int depth, int top_size) {
  const size_t root = size_t(j >> depth) * size_t(top_size) + size_t(i >> depth);
  size_t local = 0;
  for (int bit = 0; bit < depth; ++bit)
    local |= size_t((i >> bit) & 1) << (2 * bit) | size_t((j >> bit) & 1) << (2 * bit + 1);
  return (root << (2 * depth)) | local;
}

// Face sizes of the full pyramid of a cube of face size s0: s0, s0 / 2, ... down to 1 or the first
// odd size (the top level).
std::vector<int> pyramid_sizes(int s0) {
  std::vector<int> sizes = {s0};
  while (sizes.back() > 1 && sizes.back() % 2 == 0) sizes.push_back(sizes.back() / 2);
  return sizes;
}

// The pyramid of an RGBA cube, in double, from level `base` of the full pyramid up (the levels
// below it are never visited: pyramid_base_level): each texel of the base level sums its
// 2^base x 2^base texels of level 0 (the moments Omega d and lum Omega d, Omega, L Omega, with each
// texel's exact solid angle and centre direction; texels marked in `skip`, the bright ones, add their
// solid angle but no radiance), each coarser level sums 2 x 2 children, down to the top level.
// Directions are normalised on output. A face at a time (the faces' pyramids are independent), so
// that only one face's moments are held in double: a 1024^2 cube with base 2 needs 5 MiB for them.
Pyramid build_pyramid(const std::vector<float>& rgba, int s0, int base, const std::vector<uint8_t>& skip) {
  struct Moments {
    std::vector<double> g, m, w, l;  // 3, 3, 1, 3 per texel of one face, row-major
    void assign(size_t n) {
      g.assign(3 * n, 0.0);
      m.assign(3 * n, 0.0);
      w.assign(n, 0.0);
      l.assign(3 * n, 0.0);
    }
  };
  const std::vector<int> full = pyramid_sizes(s0);
  base = std::clamp(base, 0, static_cast<int>(full.size()) - 1);
  Pyramid p;
  p.sizes.assign(full.begin() + base, full.end());
  p.levels = static_cast<int>(p.sizes.size());
  const int top_size = p.sizes.back();
  size_t total = 0;
  for (int sk : p.sizes) {
    p.info.push_back(static_cast<cl_int>(total));
    p.info.push_back(sk);
    total += 10 * (6 * size_t(sk) * size_t(sk) + 8);
  }
  if (total > static_cast<size_t>(std::numeric_limits<cl_int>::max()))
    throw Error("cube of size " + std::to_string(s0) + " is too large for the quadrature's pyramid");
  p.data.assign(total, 0.0f);

  const std::vector<double> omega = texel_solid_angles(s0);
  // faces 0-2 on a second thread, 3-5 here (independent moments, disjoint parts of p.data)
  auto faces = [&](int f_begin, int f_end) {
  std::vector<Moments> moments(size_t(p.levels));
  for (int f = f_begin; f < f_end; ++f) {
    // the base level: sums over blocks of level 0
    const int sb = p.sizes[0];
    Moments& b = moments[0];
    b.assign(size_t(sb) * size_t(sb));
    for (int j = 0; j < s0; ++j)
      for (int i = 0; i < s0; ++i) {
        const size_t t = (size_t(f) * size_t(s0) + size_t(j)) * size_t(s0) + size_t(i);
        const size_t u = size_t(j >> base) * size_t(sb) + size_t(i >> base);
        const Vec3 d = math::cube_texel_direction(f, s0, i, j);
        const double w = omega[size_t(j) * size_t(s0) + size_t(i)];
        const double dv[3] = {d.x, d.y, d.z};
        b.w[u] += w;
        for (size_t c = 0; c < 3; ++c) b.g[3 * u + c] += w * dv[c];
        if (!skip.empty() && skip[t]) continue;
        const double lum = luminance(&rgba[4 * t]) * w;
        for (size_t c = 0; c < 3; ++c) {
          b.m[3 * u + c] += lum * dv[c];
          b.l[3 * u + c] += double(rgba[4 * t + c]) * w;
        }
      }
    // coarser levels: 2 x 2 children each
    for (int k = 1; k < p.levels; ++k) {
      const int sc = p.sizes[size_t(k - 1)], h = p.sizes[size_t(k)];
      const Moments& cur = moments[size_t(k - 1)];
      Moments& next = moments[size_t(k)];
      next.assign(size_t(h) * size_t(h));
      for (int j = 0; j < sc; ++j)
        for (int i = 0; i < sc; ++i) {
          const size_t t = size_t(j) * size_t(sc) + size_t(i);
          const size_t u = size_t(j / 2) * size_t(h) + size_t(i / 2);
          for (size_t c = 0; c < 3; ++c) {
            next.g[3 * u + c] += cur.g[3 * t + c];
            next.m[3 * u + c] += cur.m[3 * t + c];
            next.l[3 * u + c] += cur.l[3 * t + c];
          }
          next.w[u] += cur.w[t];
        }
    }
    // this face of every level, in quadtree order, as floats
    for (int k = 0; k < p.levels; ++k) {
      const int sk = p.sizes[size_t(k)];
      const size_t n_face = size_t(sk) * size_t(sk), a = 6 * n_face + 8, offset = size_t(p.info[2 * size_t(k)]);
      const Moments& cur = moments[size_t(k)];
      for (int j = 0; j < sk; ++j)
        for (int i = 0; i < sk; ++i) {
          const size_t t = size_t(j) * size_t(sk) + size_t(i);
          const size_t at = offset + size_t(f) * n_face + quadtree_index(i, j, p.levels - 1 - k, top_size);
          const double* g = &cur.g[3 * t];
          const double* m = &cur.m[3 * t];
          const double gn = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
          const double mn = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
          for (size_t c = 0; c < 3; ++c) {
            p.data[at + c * a] = static_cast<float>(g[c] / gn);
            p.data[at + (3 + c) * a] = static_cast<float>(mn > 0.0 ? m[c] / mn : g[c] / gn);
            p.data[at + (7 + c) * a] = static_cast<float>(cur.l[3 * t + c]);
          }
          p.data[at + 6 * a] = static_cast<float>(cur.w[t]);
        }
    }
  }
  };
  if (s0 >= 64) {
    std::exception_ptr failed;
    std::thread second([&] {
      try {
        faces(0, 3);
      } catch (...) {
        failed = std::current_exception();
      }
    });
    faces(3, 6);
    second.join();
    if (failed) std::rethrow_exception(failed);
  } else {
    faces(0, 6);
  }
  return p;
}

// The refinement thresholds of one output level (env_pyramid_sum). Texel angular size
// h_k = 2 / S_k (its largest, at a face's centre).
//   GGX: the core is the lobe of width w = 2 alpha around R; levels coarser than m0 (the coarsest
//        with h <= w / core_refinement) refine within refinement * h of R: cos_core[k] =
//        cos(refinement h_k). Where the kernel's kink at n.l = 0 matters (K'(0) / K(1) =
//        4 alpha^4 / (1 + alpha^2)^2 > 1e-3), levels with h_k > horizon_texel also refine the band
//        |c| < 2 h_k.
//   Charlie: no core (D_Charlie vanishes at R); its lobe is a ring at R.l = c* (the maximum of K).
//        Levels coarser than m0 (h <= 4 half-maximum widths / core_refinement) refine the band where
//        K > 1e-3 K_max, widened by 2 h_k, joined with the horizon band.
// band holds (lo, hi) per level; (2, 2) is empty.
void pyramid_thresholds(const Pyramid& p, EnvDistribution dist, double alpha, const PrefilterSpec& s, double refinement,
                        std::vector<double>& cos_core, std::vector<double>& band) {
  cos_core.assign(size_t(p.levels), 2.0);
  band.assign(2 * size_t(p.levels), 2.0);
  auto finest_level = [&](double width) {
    int m0 = 0;
    while (m0 + 1 < p.levels && 2.0 / p.sizes[size_t(m0 + 1)] <= width / s.core_refinement) ++m0;
    return m0;
  };
  if (dist == EnvDistribution::Ggx) {
    const int m0 = finest_level(2.0 * alpha);
    const double a4 = alpha * alpha * alpha * alpha;
    const bool horizon = 4.0 * a4 / ((1.0 + alpha * alpha) * (1.0 + alpha * alpha)) > 1e-3;
    for (int k = 1; k < p.levels; ++k) {
      const double h = 2.0 / p.sizes[size_t(k)];
      if (k > m0) cos_core[size_t(k)] = refinement * h >= kPi ? -2.0 : std::cos(refinement * h);
      if (horizon && h > s.horizon_texel) {
        band[2 * size_t(k)] = -2.0 * h;
        band[2 * size_t(k) + 1] = 2.0 * h;
      }
    }
    return;
  }
  // Charlie: the ring's extent in theta from the kernel's profile
  constexpr int kSteps = 4096;
  double k_max = 0.0;
  std::vector<double> profile(kSteps + 1);
  for (int t = 0; t <= kSteps; ++t) {
    profile[size_t(t)] = detail::env_lobe_kernel(dist, alpha, std::cos(0.5 * kPi * t / kSteps));
    k_max = std::max(k_max, profile[size_t(t)]);
  }
  double theta_lo = 0.5 * kPi, theta_hi = 0.0, half_lo = 0.5 * kPi, half_hi = 0.0;
  for (int t = 0; t <= kSteps; ++t) {
    const double theta = 0.5 * kPi * t / kSteps;
    if (profile[size_t(t)] > 1e-3 * k_max) {
      theta_lo = std::min(theta_lo, theta);
      theta_hi = std::max(theta_hi, theta);
    }
    if (profile[size_t(t)] > 0.5 * k_max) {
      half_lo = std::min(half_lo, theta);
      half_hi = std::max(half_hi, theta);
    }
  }
  // the ring is broad and smooth on the scale of its half-maximum width: a quarter of the core
  // refinement resolves it (docs/BENCHMARKS.md)
  int m0 = 0;
  while (m0 + 1 < p.levels &&
         2.0 / p.sizes[size_t(m0 + 1)] <= std::max(half_hi - half_lo, 1e-3) * 4.0 / s.core_refinement)
    ++m0;
  for (int k = 1; k < p.levels; ++k) {
    const double h = 2.0 / p.sizes[size_t(k)];
    double lo = 2.0, hi = 2.0;
    if (k > m0) {
      lo = std::cos(std::min(0.5 * kPi, theta_hi + 2.0 * h));
      hi = std::cos(std::max(0.0, theta_lo - 2.0 * h));
    }
    if (h > s.horizon_texel) {
      lo = lo > 1.5 ? -2.0 * h : std::min(lo, -2.0 * h);
      hi = hi > 1.5 ? 2.0 * h : std::max(hi, 2.0 * h);
    }
    band[2 * size_t(k)] = lo;
    band[2 * size_t(k) + 1] = hi;
  }
  (void)refinement;
}

// The finest level of the full pyramid of a cube of face size s0 that the quadrature visits for
// any of the lobes `alphas`: one below the finest level it refines (core, horizon band or Charlie's
// ring). Levels below it are never read, so build_pyramid starts there; the thresholds do not
// depend on the refinement's value (only on the lobe, core_refinement and horizon_texel), so every
// run of a --max-error search visits the same levels.
int pyramid_base_level(int s0, EnvDistribution dist, const std::vector<double>& alphas, const PrefilterSpec& s) {
  Pyramid shape;
  shape.sizes = pyramid_sizes(s0);
  shape.levels = static_cast<int>(shape.sizes.size());
  int base = shape.levels - 1;
  std::vector<double> cos_core, band;
  for (double alpha : alphas) {
    pyramid_thresholds(shape, dist, alpha, s, s.refinement, cos_core, band);
    for (int k = 1; k < shape.levels; ++k)
      if (cos_core[size_t(k)] <= 1.0 || band[2 * size_t(k)] < band[2 * size_t(k) + 1]) {
        base = std::min(base, k - 1);
        break;
      }
  }
  return base;
}

template <class Real>
cl::Event launch_pyramid(cl::Program& prog, const cl::Buffer& out, int size, const cl::Buffer& pyramid,
                         const cl::Buffer& info, int levels, const cl::Buffer& cos_core, const cl::Buffer& band,
                         const cl::Buffer& bright, int n_bright, double alpha, const cl::EnqueueArgs& rows) {
  cl::KernelFunctor<cl::Buffer, cl_int, cl::Buffer, cl::Buffer, cl_int, cl::Buffer, cl::Buffer, cl::Buffer, cl_int, Real>
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

}  // namespace

// Biased, opt-in: luminance above `limit` is compressed to limit (1 + log(lum / limit)).
void detail::clamp_luminance(std::vector<float>& rgba, double limit) {
  for (size_t t = 0; t < rgba.size(); t += 4) {
    const double lum = luminance(&rgba[t]);
    if (lum <= limit) continue;
    const double scale = limit * (1.0 + std::log(lum / limit)) / lum;
    for (size_t c = 0; c < 3; ++c) rgba[t + c] = static_cast<float>(double(rgba[t + c]) * scale);
  }
}

std::string detail::comma_join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& e : v) s += (s.empty() ? "" : ",") + e;
  return s;
}

void detail::cube_conventions_metadata(CubeLevels& cube) {
  cube.set_meta("generator", std::string("brdfbake ") + kVersion);
  cube.set_meta("faces", "+X,-X,+Y,-Y,+Z,-Z (KTX / OpenGL cube map order)");
  cube.set_meta("face_orientation",
                "OpenGL cube map convention (OpenGL 4.6 table 8.19): texel (i, j), row j = 0 stored first, "
                "a = 2 (i + 0.5) / S - 1, b = 2 (j + 0.5) / S - 1 look along +X: (1, -b, -a), -X: (-1, -b, a), "
                "+Y: (a, 1, b), -Y: (a, -1, -b), +Z: (a, -b, 1), -Z: (-a, -b, -1)");
  cube.set_meta("up", "+Y");
  cube.set_meta("equirect_mapping",
                "u = (x + 0.5) / W, v = (y + 0.5) / H, phi = 2 pi (0.5 - u), theta = pi (0.5 - v), "
                "direction (sin phi cos theta, sin theta, cos phi cos theta): top row +Y, centre +Z, u = 1/4 +X "
                "(OpenEXR LatLongMap orientation)");
  cube.set_meta("texels", "linear radiance (RGB, alpha 1)");
}

void detail::prefilter_metadata(CubeLevels& out, const PrefilterSpec& s, const std::vector<double>& roughness) {
  const int levels = static_cast<int>(roughness.size());
  cube_conventions_metadata(out);
  out.set_meta("kind", "prefiltered radiance");
  out.set_meta("distribution", env_distribution_name(s.distribution));
  out.set_meta("definition",
               "level l holds P(R) = int L(l) D(h) (n.l)+ dl / int D(h) (n.l)+ dl with n = v = R (Karis 2013), "
               "D = " + std::string(s.distribution == EnvDistribution::Ggx ? "GGX (Walter et al. 2007)"
                                                                           : "Charlie (Estevez & Kulla 2017)") +
                   ", alpha = roughness^2, L the seamless bilinear interpolation of level 0; level 0 is "
                   "the source itself (roughness 0)");
  out.set_meta("levels", std::to_string(levels));
  out.set_meta("size", std::to_string(s.size));
  out.set_meta("min_size", std::to_string(out.level_size(levels - 1)));
  out.set_meta("roughness_schedule", roughness_schedule_name(s.schedule));
  out.set_meta("roughness_of_level",
               s.schedule == RoughnessSchedule::Linear     ? "roughness = l / (levels - 1)"
               : s.schedule == RoughnessSchedule::Filament ? "roughness = 1 - sqrt(1 - l / (levels - 1))"
               : s.schedule == RoughnessSchedule::Sqrt
                   ? "roughness = (l / (levels - 1))^2"
                   : "roughness = min(1, sqrt(2^(l / 0.8) / size)), 0 at level 0 (Babylon.js HDRFiltering)");
  out.set_meta("lod_from_roughness", schedule_lod_formula(s.schedule) + " (levels = " + std::to_string(levels) + ")");
  std::vector<std::string> r_text;
  for (double r : roughness) r_text.push_back(fmt(r, "%.9g"));
  out.set_meta("roughness_per_level", comma_join(r_text));
}

void detail::environment_source_metadata(CubeLevels& out, const EnvImage& env) {
  out.set_meta("source", env.source);
  if (!env.description.empty()) out.set_meta("source_description", env.description);
  if (env.sanitize.replaced)
    out.set_meta("sanitized", std::to_string(env.sanitize.nan) + " NaN, " + std::to_string(env.sanitize.infinite) +
                                  " infinite, " + std::to_string(env.sanitize.negative) + " negative values replaced");
}

// ---- Names and schedules ---------------------------------------------------------------------

EnvDistribution env_distribution_from_name(const std::string& n) {
  if (n == "ggx") return EnvDistribution::Ggx;
  if (n == "charlie") return EnvDistribution::Charlie;
  throw Error("unknown distribution '" + n + "' (expected ggx or charlie)");
}
const char* env_distribution_name(EnvDistribution d) { return d == EnvDistribution::Charlie ? "charlie" : "ggx"; }

EnvEstimator env_estimator_from_name(const std::string& n) {
  if (n == "quadrature") return EnvEstimator::Quadrature;
  if (n == "sampling") return EnvEstimator::Sampling;
  throw Error("unknown estimator '" + n + "' (expected quadrature or sampling)");
}
const char* env_estimator_name(EnvEstimator e) { return e == EnvEstimator::Sampling ? "sampling" : "quadrature"; }

RoughnessSchedule roughness_schedule_from_name(const std::string& n) {
  if (n == "linear") return RoughnessSchedule::Linear;
  if (n == "filament") return RoughnessSchedule::Filament;
  if (n == "sqrt") return RoughnessSchedule::Sqrt;
  if (n == "babylon") return RoughnessSchedule::Babylon;
  throw Error("unknown schedule '" + n + "' (expected linear, filament, sqrt or babylon)");
}
const char* roughness_schedule_name(RoughnessSchedule s) {
  switch (s) {
    case RoughnessSchedule::Filament: return "filament";
    case RoughnessSchedule::Sqrt: return "sqrt";
    case RoughnessSchedule::Babylon: return "babylon";
    case RoughnessSchedule::Linear: break;
  }
  return "linear";
}

double schedule_roughness(RoughnessSchedule s, int level, int levels) {
  if (levels <= 1) return 0.0;
  const double t = static_cast<double>(level) / (levels - 1);
  switch (s) {
    case RoughnessSchedule::Linear: return t;
    case RoughnessSchedule::Filament: return 1.0 - std::sqrt(1.0 - t);
    case RoughnessSchedule::Sqrt: return t * t;
    case RoughnessSchedule::Babylon: {
      // Babylon.js HDRFiltering: alphaG = 2^((lod - offset) / scale) / width, 0 at lod 0.
      if (level == 0) return 0.0;
      const double alpha = std::pow(2.0, level / kBabylonLodGenerationScale) / std::ldexp(1.0, levels - 1);
      return std::min(1.0, std::sqrt(alpha));
    }
  }
  return t;
}

double schedule_lod(RoughnessSchedule s, double r, int levels) {
  const double m = levels - 1;
  switch (s) {
    case RoughnessSchedule::Linear: return m * r;
    case RoughnessSchedule::Filament: return m * r * (2.0 - r);
    case RoughnessSchedule::Sqrt: return m * std::sqrt(r);
    case RoughnessSchedule::Babylon: {
      // Babylon.js pbrBlockReflection: getLodFromAlphaG(size, alphaG) * lodGenerationScale, with
      // alphaG = roughness^2 + MINIMUMVARIANCE; textureLod clamps to the chain.
      const double lod = kBabylonLodGenerationScale *
                         std::log2(std::ldexp(1.0, levels - 1) * (r * r + kBabylonMinimumVariance));
      return std::clamp(lod, 0.0, m);
    }
  }
  return m * r;
}

std::string schedule_lod_formula(RoughnessSchedule s) {
  switch (s) {
    case RoughnessSchedule::Linear: return "lod = (levels - 1) * roughness";
    case RoughnessSchedule::Filament: return "lod = (levels - 1) * roughness * (2 - roughness)";
    case RoughnessSchedule::Sqrt: return "lod = (levels - 1) * sqrt(roughness)";
    case RoughnessSchedule::Babylon:
      return "lod = clamp(0.8 * log2(size * (roughness^2 + 0.0005)), 0, levels - 1), size = 2^(levels - 1)";
  }
  return "";
}

// ---- Specs ----------------------------------------------------------------------------------------

PrefilterSpec resolve_prefilter_spec(const PrefilterSpec& in) {
  PrefilterSpec s = in;
  if (s.size < 1 || s.size > kMaxSize)
    throw Error("size must be in 1.." + std::to_string(kMaxSize) + " (got " + std::to_string(s.size) + ")");
  if (s.min_size < 1 || s.min_size > s.size)
    throw Error("min-size must be in 1..size (got " + std::to_string(s.min_size) + " for size " +
                std::to_string(s.size) + ")");
  if (s.samples < 0 || s.samples > kMaxSamples)
    throw Error("samples must be in 1.." + std::to_string(kMaxSamples) + " (got " + std::to_string(s.samples) + ")");
  if (!std::isfinite(s.max_error) || s.max_error < 0.0) throw Error("max-error must be a positive number");
  if (s.max_error > 0.0 && s.samples > 0) throw Error("give either samples or max-error, not both");
  if (!std::isfinite(s.lod_bias)) throw Error("lod bias must be finite");
  if (!std::isfinite(s.clamp_luminance) || s.clamp_luminance < 0.0) throw Error("clamp must be a positive number");
  if (s.bright_texels < -1) throw Error("bright texel count must be >= 0 (or -1: automatic)");
  if (!(s.refinement >= 1.5 && s.refinement <= 64.0)) throw Error("refinement must be in 1.5..64");
  if (!(s.core_refinement >= 1.0 && s.core_refinement <= 256.0)) throw Error("core refinement must be in 1..256");
  if (!(s.horizon_texel > 0.0)) throw Error("horizon texel size must be positive");
  if (s.estimator == EnvEstimator::Quadrature && s.samples > 0)
    throw Error("samples apply to the sampling estimator; the quadrature takes a refinement (or max-error)");
  return s;
}

int prefilter_level_count(const PrefilterSpec& spec) {
  int levels = 0;
  for (int l = 0;; ++l) {
    const int s = std::max(1, spec.size >> l);
    if (s < spec.min_size || (l > 0 && (spec.size >> l) == 0)) break;
    ++levels;
    if (s == 1) break;
  }
  return std::max(levels, 1);
}

// ---- Bright texels ---------------------------------------------------------------------------------

std::vector<BrightTexel> find_bright_texels(const CubeLevels& cube, int max_count, double ratio) {
  std::vector<BrightTexel> out;
  if (max_count <= 0 || cube.levels.empty()) return out;
  const int s = cube.size;
  const size_t face = static_cast<size_t>(s) * static_cast<size_t>(s);
  const std::vector<double> omega = texel_solid_angles(s);
  const size_t n = face_texels(s);
  const std::vector<float>& level = cube.levels[0];
  double mean = 0.0;
  for (size_t t = 0; t < n; ++t) mean += luminance(&level[4 * t]) * omega[t % face];
  mean /= 4.0 * kPi;
  // Only the texels above ratio x mean can be chosen: their luminances alone are ranked (the
  // (max_count + 1)-th brightest of them is the (max_count + 1)-th brightest of all whenever there
  // are more than max_count), not a copy of every texel's.
  double threshold = ratio * mean;
  std::vector<double> above;
  for (size_t t = 0; t < n; ++t) {
    const double lum = luminance(&level[4 * t]);
    if (lum > threshold) above.push_back(lum);
  }
  if (above.size() > static_cast<size_t>(max_count)) {
    std::nth_element(above.begin(), above.begin() + max_count, above.end(), std::greater<double>());
    threshold = std::max(threshold, above[size_t(max_count)]);  // the (max_count + 1)-th brightest
  }
  above = {};
  for (size_t t = 0; t < n; ++t) {
    if (!(luminance(&level[4 * t]) > threshold)) continue;
    BrightTexel b;
    b.face = static_cast<int>(t / face);
    b.j = static_cast<int>(t % face / size_t(s));
    b.i = static_cast<int>(t % size_t(s));
    for (size_t c = 0; c < 3; ++c) b.rgb[c] = level[4 * t + c];
    out.push_back(b);
  }
  return out;
}

std::vector<double> bright_texel_points(const std::vector<BrightTexel>& bright, int size, int q, double scale,
                                        int* count) {
  std::vector<double> px, py, pz, pr, pg, pb;
  const double h = 2.0 / size;  // a texel in face coordinates
  for (const BrightTexel& t : bright) {
    const double ca = -1.0 + h * (t.i + 0.5), cb = -1.0 + h * (t.j + 0.5);  // the texel's centre
    for (int sj = 0; sj < 2 * q; ++sj)
      for (int si = 0; si < 2 * q; ++si) {
        // sub-cell [x0, x1] x [y0, y1] of the tent's support [-1, 1]^2 (in texels from the centre)
        const double x0 = -1.0 + double(si) / q, x1 = x0 + 1.0 / q, y0 = -1.0 + double(sj) / q, y1 = y0 + 1.0 / q;
        const double xm = 0.5 * (x0 + x1), ym = 0.5 * (y0 + y1);
        // the tent's exact mean over the sub-cell (it is linear there: the cells do not straddle 0)
        const double tent = (1.0 - std::fabs(xm)) * (1.0 - std::fabs(ym));
        const Vec3 p = math::cube_plane_point(t.face, ca + h * xm, cb + h * ym);
        const double len = std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
        const double omega =
            math::cube_rect_solid_angle(ca + h * x0, cb + h * y0, ca + h * x1, cb + h * y1) * tent * scale;
        px.push_back(p.x / len);
        py.push_back(p.y / len);
        pz.push_back(p.z / len);
        pr.push_back(double(t.rgb[0]) * omega);
        pg.push_back(double(t.rgb[1]) * omega);
        pb.push_back(double(t.rgb[2]) * omega);
      }
  }
  *count = static_cast<int>(px.size());
  while (px.size() % kVectorWidth != 0 || px.empty()) {
    px.push_back(0.0);
    py.push_back(0.0);
    pz.push_back(1.0);
    pr.push_back(0.0);
    pg.push_back(0.0);
    pb.push_back(0.0);
  }
  std::vector<double> out;
  for (const auto* v : {&px, &py, &pz, &pr, &pg, &pb}) out.insert(out.end(), v->begin(), v->end());
  return out;
}

// ---- Conversion ---------------------------------------------------------------------------------

namespace {
CubeLevels convert_to_cube(Device& device, const EnvImage& env, int size, double* device_seconds,
                           const std::function<void()>& program_built);
}

CubeLevels environment_to_cube(Device& device, const EnvImage& env, int size, double* device_seconds) {
  return convert_to_cube(device, env, size, device_seconds, {});
}

namespace {

// environment_to_cube; program_built runs once the conversion's program is built, before its
// kernels (prefilter_environment builds the filter's program meanwhile).
CubeLevels convert_to_cube(Device& device, const EnvImage& env, int size, double* device_seconds,
                           const std::function<void()>& program_built) {
  if (size < 1 || size > kMaxSize)
    throw Error("cube size must be in 1.." + std::to_string(kMaxSize) + " (got " + std::to_string(size) + ")");
  if (env.width < 1 || env.height < 1 || env.rgb.empty()) throw Error("empty environment");
  auto& dev = device.impl();
  CubeLevels cube;
  cube.size = size;
  cube.levels.resize(1);
  cube.levels[0].resize(4 * face_texels(size));  // in place: assign(1, vector) would hold two copies
  const std::string what = "converting '" + env.source + "' to a cube on '" + dev.info.name + "'";
  {
    // Device limits (docs/RELIABILITY.md): the source and the cube must fit the device's memory.
    const double source_bytes = 12.0 * double(env.rgb.size() / 3), cube_bytes = 16.0 * double(face_texels(size));
    detail::check_device_memory(dev, std::max(source_bytes, cube_bytes), 2.5 * (source_bytes + cube_bytes),
                                "converting '" + env.source + "' to a cube of " + std::to_string(size) + "^2");
  }
  const double seconds = detail::cl_call(what, [&] {
    cl::Program prog = program(dev, "cubemap.cl", Precision::Fp32);
    if (program_built) program_built();
    std::vector<cl::Event> events;
    if (env.layout == EnvImage::Layout::Equirect) {
      // the packed RGB pixels as they are (the kernel reads three floats a pixel): on a CPU device
      // no copy at all, elsewhere one upload
      const size_t bytes = env.rgb.size() * sizeof(float);
      check_allocation(dev, bytes, "the " + std::to_string(env.width) + "x" + std::to_string(env.height) + " environment");
      cl::Buffer src(dev.context, CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR, bytes, const_cast<float*>(env.rgb.data()));
      // k x k samples per texel: about two per equirect pixel along the equator
      const int k = std::clamp((env.width + 2 * size - 1) / (2 * size), 1, 16);
      cl::KernelFunctor<cl::Buffer, cl_int, cl_int, cl::Buffer, cl_int, cl_int, cl_int> convert(prog, "equirect_to_cube");
      // one work-item per 8 texels of a row (kernels/cubemap.cl), one face at a time into a face buffer
      const size_t face_bytes = 4 * static_cast<size_t>(size) * static_cast<size_t>(size) * sizeof(float);
      check_allocation(dev, face_bytes, "a face of the " + std::to_string(size) + "^2 cube");
      cl::Buffer face_buf(dev.context, CL_MEM_WRITE_ONLY, face_bytes);
      const cl::NDRange rows(static_cast<size_t>((size + kVectorWidth - 1) / kVectorWidth), static_cast<size_t>(size));
      for (int f = 0; f < 6; ++f) {
        const cl::EnqueueArgs range(dev.queue, cl::NDRange(0, size_t(f) * size_t(size)), rows, cl::NullRange);
        events.push_back(convert(range, src, env.width, env.height, face_buf, size, k, f));
        dev.queue.enqueueReadBuffer(face_buf, CL_TRUE, 0, face_bytes, cube.levels[0].data() + (face_bytes / sizeof(float)) * size_t(f));
      }
      return sum_seconds(events);
    } else {
      cl::Buffer dst(dev.context, CL_MEM_READ_WRITE, 4 * face_texels(size) * sizeof(float));
      const int s = env.width;
      std::vector<float> rgba(4 * face_texels(s), 1.0f);
      for (size_t t = 0; t < face_texels(s); ++t)
        for (size_t c = 0; c < 3; ++c) rgba[4 * t + c] = env.rgb[3 * t + c];
      if (s == size) {
        dev.queue.enqueueWriteBuffer(dst, CL_TRUE, 0, rgba.size() * sizeof(float), rgba.data());
      } else {
        cl::Buffer src(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, rgba.size() * sizeof(float), rgba.data());
        Chain chain = build_chain(dev, prog, src, s, events);
        // resample from the chain level closest above the target size
        int m = 0;
        while (m + 1 < chain.levels && chain.info[size_t(2 * m + 3)] >= size) ++m;
        const int ms = chain.info[size_t(2 * m + 1)];
        const int k = std::clamp((ms + size - 1) / size, 1, 16);
        cl::KernelFunctor<cl::Buffer, cl_int, cl_int, cl::Buffer, cl_int, cl_int> resample(prog, "cube_resample");
        events.push_back(resample(cl::EnqueueArgs(dev.queue, cube_range(size)), chain.buffer,
                                  chain.info[size_t(2 * m)], ms, dst, size, k));
      }
      dev.queue.enqueueReadBuffer(dst, CL_TRUE, 0, cube.levels[0].size() * sizeof(float), cube.levels[0].data());
    }
    return sum_seconds(events);
  });
  if (device_seconds) *device_seconds = seconds;
  detail::cube_conventions_metadata(cube);
  cube.set_meta("source", env.source);
  return cube;
}

}  // namespace

// ---- The chain ------------------------------------------------------------------------------------

namespace {

// The chain from a source cube it owns: level 0 moves into the output, no copy (a 1024^2 cube is
// 96 MiB).
CubeLevels prefilter_chain(Device& device, CubeLevels source, const PrefilterSpec& in, PrefilterTiming* timing,
                           const EnvProgress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  const PrefilterSpec s = resolve_prefilter_spec(in);
  if (source.levels.empty() || source.size != s.size)
    throw Error("prefilter_cube: the source cube must have size " + std::to_string(s.size));
  auto& dev = device.impl();
  const int levels = prefilter_level_count(s);
  const int s0 = s.size;
  const bool quadrature = s.estimator == EnvEstimator::Quadrature;
  std::vector<std::pair<std::string, double>> stages;
  auto stage_mark = std::chrono::steady_clock::now();
  auto stage = [&](std::string name) {
    const auto now = std::chrono::steady_clock::now();
    stages.emplace_back(std::move(name), std::chrono::duration<double>(now - stage_mark).count());
    stage_mark = now;
  };

  CubeLevels out;
  out.size = s0;
  out.metadata = std::move(source.metadata);
  out.levels.resize(size_t(levels));
  out.levels[0] = std::move(source.levels[0]);
  source.levels.clear();
  if (s.clamp_luminance > 0.0) detail::clamp_luminance(out.levels[0], s.clamp_luminance);

  // Environment sampling: the bright texels leave the rest.
  const int max_bright = s.bright_texels < 0 ? kDefaultBrightTexels : s.bright_texels;
  const std::vector<BrightTexel> bright = find_bright_texels(out, max_bright, kBrightRatio);
  stage("bright texels");

  std::vector<double> roughness(static_cast<size_t>(levels)), seconds(static_cast<size_t>(levels), 0.0);
  std::vector<double> refinement(static_cast<size_t>(levels), s.refinement);
  std::vector<int> samples(static_cast<size_t>(levels), 0);
  std::vector<double> measured(static_cast<size_t>(levels), 0.0);  // max_error: the last difference per level
  for (int l = 0; l < levels; ++l) {
    roughness[size_t(l)] = schedule_roughness(s.schedule, l, levels);
    if (l > 0 && !quadrature) samples[size_t(l)] = s.samples > 0 ? s.samples : default_samples(l, levels);
  }

  double device_seconds = 0.0;
  const std::string what = "prefiltering on '" + dev.info.name + "'";
  detail::cl_call(what, [&] {
    cl::Program filter_prog = filter_program(dev, s);
    stage("program");
    // The source: the quadrature's pyramid (built here, on the host, in double), or the sampling
    // estimator's padded mip chain (built on the device).
    Pyramid pyramid;
    cl::Buffer pyramid_buf, pyramid_info;
    Chain chain;
    if (quadrature) {
      std::vector<double> alphas;
      for (int l = 1; l < levels; ++l)
        alphas.push_back(std::max(roughness[size_t(l)] * roughness[size_t(l)], math::kMinAlpha));
      std::vector<uint8_t> skip;
      if (!bright.empty()) {
        skip.assign(face_texels(s0), 0);
        for (const BrightTexel& b : bright) skip[(size_t(b.face) * size_t(s0) + size_t(b.j)) * size_t(s0) + size_t(b.i)] = 1;
      }
      pyramid = build_pyramid(out.levels[0], s0, pyramid_base_level(s0, s.distribution, alphas, s), skip);
      check_allocation(dev, pyramid.data.size() * sizeof(float), "the quadrature's pyramid");
      // USE_HOST_PTR: a CPU device reads the host's copy (it outlives every level), a GPU uploads it
      pyramid_buf = cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR, pyramid.data.size() * sizeof(float),
                               pyramid.data.data());
      pyramid_info = cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                pyramid.info.size() * sizeof(cl_int), pyramid.info.data());
    } else {
      cl::Program cube_prog = program(dev, "cubemap.cl", s.precision);
      std::vector<cl::Event> chain_events;
      std::vector<float> rest = out.levels[0];
      for (const BrightTexel& b : bright) {
        float* t = &rest[4 * ((size_t(b.face) * size_t(s0) + size_t(b.j)) * size_t(s0) + size_t(b.i))];
        t[0] = t[1] = t[2] = 0.0f;
      }
      cl::Buffer level0(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, rest.size() * sizeof(float), rest.data());
      chain = build_chain(dev, cube_prog, level0, s0, chain_events);
      for (auto& e : chain_events) e.wait();
      seconds[0] = sum_seconds(chain_events);
      device_seconds += seconds[0];
    }
    stage(quadrature ? "pyramid" : "source chain");

    // One level into `dst` with n samples (sampling) or refinement r (quadrature); waits, returns
    // its device seconds.
    // Rows of a level are launched in chunks (global id offsets) so that progress can follow
    // within a level: the first levels hold most of the texels and take most of the time.
    auto run_level = [&](int l, int n, double r, std::vector<float>& dst, const std::function<void(double)>& step) {
      const int size = out.level_size(l);
      const double alpha = std::max(roughness[size_t(l)] * roughness[size_t(l)], math::kMinAlpha);
      int n_points = 0;
      // Bright points carry L Omega; the sampling estimator divides them by W = int K dl here,
      // the quadrature by its own sum of K Omega in the kernel.
      const double scale = quadrature ? 1.0 : 1.0 / detail::env_lobe_normalization(s.distribution, alpha);
      const std::vector<double> pts = bright_texel_points(bright, s0, bright_subdivision(s.distribution, alpha, s0, bright.size()), scale, &n_points);
      const int n_pts = n_points > 0 ? static_cast<int>(pts.size() / 6) : 0;
      cl::Buffer pts_buf = real_buffer(dev, s.precision, pts);
      // the level is written into dst through USE_HOST_PTR and mapped back: no second copy on a
      // CPU device
      dst.assign(4 * face_texels(size), 0.0f);
      check_allocation(dev, dst.size() * sizeof(float), "level " + std::to_string(l));
      cl::Buffer dst_buf(dev.context, CL_MEM_WRITE_ONLY | CL_MEM_USE_HOST_PTR, dst.size() * sizeof(float), dst.data());
      const bool fp64 = s.precision == Precision::Fp64;
      const int rows = 6 * size;
      std::vector<double> cos_core, band, table;
      cl::Buffer core_buf, band_buf, table_buf;
      int n_padded = 0;
      if (quadrature) {
        pyramid_thresholds(pyramid, s.distribution, alpha, s, r, cos_core, band);
        core_buf = real_buffer(dev, s.precision, cos_core);
        band_buf = real_buffer(dev, s.precision, band);
      } else {
        int n_kept = 0;
        table = lobe_samples(s.distribution, alpha, n, s0, s.filtered_importance_sampling, s.lod_bias, &n_kept);
        table_buf = real_buffer(dev, s.precision, table);
        n_padded = static_cast<int>(table.size() / 5);
      }
      // The quadrature a block of 8 x 8 texels at a time where the block divides the level
      // (prefilter_pyramid_strips), else (and with s.strips off) a walk per texel
      // (prefilter_pyramid).
      const bool strips = quadrature && s.strips && size % 8 == 0 && size % (2 * kStripRows) == 0;
      const int unit = strips ? 2 * kStripRows : 1;
      StripBright sb;
      if (strips) {
        const int q_fine = bright_subdivision(s.distribution, alpha, s0, bright.size());
        const int q_coarse = std::min(q_fine, bright_lobe_subdivision(s.distribution, alpha, s0));
        sb.fine = pts_buf;
        sb.fine_stride = static_cast<int>(pts.size() / 6);
        sb.fine_per = 4 * q_fine * q_fine;
        sb.coarse_per = 4 * q_coarse * q_coarse;
        if (bright_single_point(s.distribution, alpha, s0) && !bright.empty()) {
          // one point a texel: the merged coarse (or fine) points
          const bool from_fine = q_coarse == q_fine;
          int n_coarse = 0;
          const std::vector<double> cp = from_fine ? std::vector<double>{} : bright_texel_points(bright, s0, q_coarse, scale, &n_coarse);
          const std::vector<double>& src = from_fine ? pts : cp;
          const std::vector<double> merged =
              merge_bright_points(src, src.size() / 6, size_t(4 * q_coarse * q_coarse), bright.size());
          sb.coarse = real_buffer(dev, s.precision, merged);
          sb.coarse_stride = static_cast<int>(merged.size() / 6);
          sb.coarse_per = 1;
        } else if (q_coarse == q_fine) {
          sb.coarse = pts_buf;
          sb.coarse_stride = sb.fine_stride;
        } else {
          int n_coarse = 0;
          const std::vector<double> coarse = bright_texel_points(bright, s0, q_coarse, scale, &n_coarse);
          sb.coarse = real_buffer(dev, s.precision, coarse);
          sb.coarse_stride = static_cast<int>(coarse.size() / 6);
        }
        std::vector<double> dirs(3 * std::max<size_t>(bright.size(), 1), 0.0);
        for (size_t t = 0; t < bright.size(); ++t) {
          const Vec3 d = math::cube_texel_direction(bright[t].face, s0, bright[t].i, bright[t].j);
          dirs[t] = d.x;
          dirs[bright.size() + t] = d.y;
          dirs[2 * bright.size() + t] = d.z;
        }
        sb.dirs = real_buffer(dev, s.precision, dirs);
        sb.texels = n_pts > 0 ? static_cast<int>(bright.size()) : 0;
        // the tent's support reaches a texel diagonal (2 / s0 in face coordinates, at most as many
        // radians) from the centre; one more texel as margin
        sb.reach = (std::sqrt(2.0) + 1.0) * 2.0 / double(s0);
      }
      // Launches over bands of `unit` rows (whole blocks), each sized from the speed the previous
      // ones measured to take about 50 ms (runtime/launch.hpp: no display watchdog is approached on
      // a GPU, a stop waits for one launch, progress follows the parts). A band's cost in
      // LaunchSizer's units: its texels times ~64 evaluations (pyramid texels or samples) each.
      const size_t bands = size_t(rows / unit);
      const double band_cost = double(size) * double(unit) * 64.0;
      const double level_seconds = detail::launch_in_parts(
          bands, band_cost,
          [&](size_t first, size_t count) -> cl::Event {
            const size_t row0 = first * size_t(unit), n_rows = count * size_t(unit);
            const cl::EnqueueArgs range =
                strips ? cl::EnqueueArgs(dev.queue, cl::NDRange(0, first), cl::NDRange(size_t(size / 8), count), cl::NDRange(1, 1))
                       : cl::EnqueueArgs(dev.queue, cl::NDRange(0, row0), cl::NDRange(size_t(size), n_rows), cl::NullRange);
            if (strips)
              return fp64 ? launch_strips<cl_double>(filter_prog, dst_buf, size, pyramid_buf, pyramid_info, pyramid.levels,
                                                     core_buf, band_buf, sb, alpha, range)
                          : launch_strips<cl_float>(filter_prog, dst_buf, size, pyramid_buf, pyramid_info, pyramid.levels,
                                                    core_buf, band_buf, sb, alpha, range);
            if (quadrature)
              return fp64 ? launch_pyramid<cl_double>(filter_prog, dst_buf, size, pyramid_buf, pyramid_info, pyramid.levels,
                                                      core_buf, band_buf, pts_buf, n_pts, alpha, range)
                          : launch_pyramid<cl_float>(filter_prog, dst_buf, size, pyramid_buf, pyramid_info, pyramid.levels,
                                                     core_buf, band_buf, pts_buf, n_pts, alpha, range);
            return fp64 ? launch_level<cl_double>(filter_prog, dst_buf, size, chain, table_buf, n_padded, pts_buf, n_pts,
                                                  alpha, range)
                        : launch_level<cl_float>(filter_prog, dst_buf, size, chain, table_buf, n_padded, pts_buf, n_pts,
                                                 alpha, range);
          },
          step, step ? 4 : 1);  // a progress line moves within a level
      void* mapped = dev.queue.enqueueMapBuffer(dst_buf, CL_TRUE, CL_MAP_READ, 0, dst.size() * sizeof(float));
      dev.queue.enqueueUnmapMemObject(dst_buf, mapped);
      dev.queue.finish();
      return level_seconds;
    };

    // RMS relative difference of two levels (luminance), the measured error estimate of --max-error.
    auto rms_difference = [](const std::vector<float>& a, const std::vector<float>& b) {
      double sum = 0.0;
      size_t count = 0;
      for (size_t t = 0; t < a.size(); t += 4) {
        const double la = luminance(&a[t]), lb = luminance(&b[t]);
        const double d = std::fabs(la - lb) / std::max(std::fabs(lb), 1e-30);
        sum += d * d;
        ++count;
      }
      return std::sqrt(sum / double(std::max<size_t>(count, 1)));
    };

    // Progress by texel count (the cost per texel is about the same on every level).
    double total_work = 0.0, done_work = 0.0;
    for (int l = 1; l < levels; ++l) total_work += double(face_texels(out.level_size(l)));
    for (int l = 1; l < levels; ++l) {
      const std::string label = "level " + std::to_string(l) + "/" + std::to_string(levels - 1);
      if (progress) progress(total_work > 0 ? done_work / total_work : 0.0, label);
      // Within the level's share of the work: run k of a search (refinement or sample count, each
      // dearer than the last) fills [1 - 2^-k, 1 - 2^-(k+1)) of it, so the line moves on and never back.
      const double share = total_work > 0 ? double(face_texels(out.level_size(l))) / total_work : 0.0;
      const double start = total_work > 0 ? done_work / total_work : 0.0;
      int run = 0;
      std::string step_label = label;
      auto step = [&](double f) {
        if (!progress) return;
        const double a = 1.0 - std::ldexp(1.0, -run), b = 1.0 - std::ldexp(1.0, -(run + 1));
        progress(start + share * (s.max_error > 0.0 ? a + (b - a) * f : f), step_label);
      };
      std::function<void(double)> stepper;
      if (progress) stepper = step;
      auto search_run = [&](int n, double r, std::vector<float>& dst) {
        step_label = label + (quadrature ? ", refinement " + fmt(r) : ", " + std::to_string(n) + " samples");
        const double t = run_level(l, n, r, dst, stepper);
        ++run;
        return t;
      };
      double& sec = seconds[size_t(l)];
      if (s.max_error > 0.0 && quadrature) {
        // Refinement 2, 3, 4, 6, 8, 12, 16: each result is compared with the next; the first
        // pair closer than max_error keeps the finer result (its error is a fraction of the
        // difference).
        static const double kSteps[] = {2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0};
        std::vector<float> a, b;
        sec += search_run(0, kSteps[0], a);
        for (size_t k = 1; k < std::size(kSteps); ++k) {
          sec += search_run(0, kSteps[k], b);
          refinement[size_t(l)] = kSteps[k];
          measured[size_t(l)] = rms_difference(a, b);
          const bool done = measured[size_t(l)] <= s.max_error;
          a.swap(b);
          if (done) break;
        }
        out.levels[size_t(l)] = std::move(a);
      } else if (s.max_error > 0.0) {
        // Sampling: the difference of n and 4n samples estimates the error of n; n doubles from
        // kSearchStart until it is below max_error, and the 4n result is kept.
        std::vector<float> a, b;
        int n = kSearchStart;
        sec += search_run(n, 0.0, a);
        for (;;) {
          sec += search_run(4 * n, 0.0, b);
          measured[size_t(l)] = rms_difference(a, b);
          if (measured[size_t(l)] <= s.max_error || 4 * n >= kSearchMax) {
            samples[size_t(l)] = 4 * n;
            out.levels[size_t(l)] = std::move(b);
            break;
          }
          n *= 2;
          sec += search_run(n, 0.0, a);
        }
      } else {
        sec = run_level(l, samples[size_t(l)], refinement[size_t(l)], out.levels[size_t(l)], stepper);
      }
      device_seconds += sec;
      done_work += double(face_texels(out.level_size(l)));
      stage("level " + std::to_string(l));
    }
    if (progress) progress(1.0, "done");
    return 0;
  });

  // Metadata: what the levels hold, how they were made.
  detail::prefilter_metadata(out, s, roughness);
  std::vector<std::string> n_text;
  for (int l = 0; l < levels; ++l) {
    n_text.push_back(quadrature ? (l == 0 ? std::string("0") : fmt(refinement[size_t(l)], "%g"))
                                : std::to_string(samples[size_t(l)]));
  }
  out.set_meta("estimator", env_estimator_name(s.estimator));
  if (quadrature) {
    out.set_meta("refinement_per_level", detail::comma_join(n_text));
    out.set_meta("estimator_description",
                 "deterministic hierarchical quadrature: a solid-angle pyramid of level 0 (per texel: solid angle, "
                 "L Omega, centroid and radiance centroid directions), texels refined within refinement x texel "
                 "size of R (core to texel size <= 2 alpha / " + fmt(s.core_refinement) +
                     ") and across the horizon (to " + fmt(s.horizon_texel) +
                     " rad); K at the radiance centroid, normalised by the sum of K Omega; plus " +
                     std::to_string(bright.size()) + " bright texels summed exactly (environment sampling)");
  } else {
    out.set_meta("samples_per_level", detail::comma_join(n_text));
    out.set_meta("estimator_description",
                 std::string("lobe importance sampling, N = V = R, Hammersley points, ") +
                     (s.filtered_importance_sampling
                          ? "filtered importance sampling (Krivanek & Colbert 2008; lod = 0.5 log2(4 / (N D) / texel "
                            "solid angle) + " + fmt(s.lod_bias) + ") "
                          : "no filtered importance sampling ") +
                     "from a solid-angle-weighted mip chain, self-normalised weights (n.l)+; plus " +
                     std::to_string(bright.size()) + " bright texels summed exactly (environment sampling)");
  }
  if (s.max_error > 0.0) {
    // A level that reached the largest refinement (or sample count) without meeting the target makes
    // the chain fail: no file may claim a bound it does not meet.
    double worst = 0.0;
    int worst_level = 0;
    std::vector<std::string> m_text;
    for (int l = 0; l < levels; ++l) {
      m_text.push_back(fmt(measured[size_t(l)], "%.3g"));
      if (measured[size_t(l)] > worst) {
        worst = measured[size_t(l)];
        worst_level = l;
      }
    }
    if (worst > s.max_error)
      throw Error("max-error " + fmt(s.max_error) + " is not reached: level " + std::to_string(worst_level) + " still differs by " +
                  fmt(worst, "%.3g") + " (RMS) between its two finest " +
                  (quadrature ? "refinements (the largest is 16)" : "sample counts (the largest is " + std::to_string(kSearchMax) + ")") +
                  "; ask for max-error " + fmt(worst * 1.5, "%.2g") + " or more");
    out.set_meta("max_error", "measured per level: RMS relative luminance difference between successive " +
                                  std::string(quadrature ? "refinements" : "sample counts (N, 4N)") + " <= " +
                                  fmt(s.max_error) + " (the finer result is kept)");
    out.set_meta("measured_error_per_level", detail::comma_join(m_text));
    out.set_meta("measured_error", fmt(worst, "%.3g"));
  }
  if (s.clamp_luminance > 0.0)
    out.set_meta("clamp", "BIASED: source luminance above " + fmt(s.clamp_luminance) +
                              " compressed to limit (1 + log(lum / limit))");
  out.set_meta("precision", precision_name(s.precision));
  out.set_meta("device", dev.info.name + " (" + dev.info.platform_name + ", " + dev.info.driver_version + ")");
  if (timing) {
    timing->stage_seconds.insert(timing->stage_seconds.end(), stages.begin(), stages.end());
    timing->device_seconds += device_seconds;
    timing->level_device_seconds = seconds;
    if (s.max_error > 0.0) {
      timing->measured_error_per_level = measured;
      timing->measured_error = *std::max_element(measured.begin(), measured.end());
    }
    timing->wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return out;
}

}  // namespace

CubeLevels prefilter_cube(Device& device, const CubeLevels& source, const PrefilterSpec& in, PrefilterTiming* timing,
                          const EnvProgress& progress) {
  return prefilter_chain(device, source, in, timing, progress);
}

CubeLevels prefilter_environment(Device& device, const EnvImage& env, const PrefilterSpec& in, PrefilterTiming* timing,
                                 const EnvProgress& progress, const std::function<void()>& source_done) {
  const auto t0 = std::chrono::steady_clock::now();
  const PrefilterSpec s = resolve_prefilter_spec(in);
  if (progress) progress(0.0, "converting to a cube");
  double convert_seconds = 0.0;
  // the filter's program is built (or read from the cache) while the conversion runs
  std::future<void> filter_built;
  CubeLevels source = convert_to_cube(device, env, s.size, &convert_seconds, [&] {
    filter_built = std::async(std::launch::async, [&device, &s] {
      detail::cl_call("building kernels/prefilter.cl", [&] { return filter_program(device.impl(), s), 0; });
    });
  });
  if (filter_built.valid()) filter_built.get();
  if (source_done) source_done();  // the pixels are not read again
  PrefilterTiming t;
  t.device_seconds = convert_seconds;
  t.stage_seconds.emplace_back("convert", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  CubeLevels out = prefilter_chain(device, std::move(source), s, &t, progress);
  detail::environment_source_metadata(out, env);
  if (timing) {
    *timing = t;
    if (!timing->level_device_seconds.empty()) timing->level_device_seconds[0] += convert_seconds;
    timing->wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return out;
}

}  // namespace brdfbake
