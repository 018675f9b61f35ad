// The DFG tables on an OpenCL device (kernels/dfg_lut.cl): the kernel's compile-time choices, its
// quadrature nodes, bounded launches, and the family's OpenCL kernel (kernel.hpp).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "brdfbake/dfg_lut.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/math/gauss_legendre.hpp"
#include "families/dfg_lut/kernel.hpp"
#include "families/dfg_lut/model.hpp"
#include "runtime/launch.hpp"
#include "runtime/program.hpp"

namespace brdfbake {

namespace {

// The quadrature's split of `samples` evaluations per texel: n_xi nodes in the polar variable and
// n_phi in azimuth, on each of the two panels (2 n_xi n_phi evaluations). The azimuth converges
// much faster than the polar angle (docs/BENCHMARKS.md), so n_phi stays small until the polar rule
// is long. The kernel runs 8 polar nodes at once: n_xi is rounded up to a multiple of 8.
void quadrature_shape(LutKind kind, int samples, int& n_xi, int& n_phi) {
  constexpr int kWidth = 8;  // BRDFBAKE_LANES: n_xi is a multiple of it
  // GGX's azimuth rule limits it to ~1e-5 with 8 nodes (grazing, low roughness), so it doubles
  // them early; Charlie's band needs polar nodes first (measured: docs/BENCHMARKS.md).
  const int to16 = kind == LutKind::Charlie ? 2048 : 768;
  const int to32 = kind == LutKind::Charlie ? 8192 : 4096;
  n_phi = samples < 128 ? std::max(1, samples / (2 * kWidth)) : samples < to16 ? 8 : samples < to32 ? 16 : 32;
  n_xi = std::max(kWidth, (samples / (2 * n_phi) + kWidth - 1) / kWidth * kWidth);
}

int evaluations(const LutSpec& s) {
  if (s.estimator != Estimator::Quadrature) return s.samples;
  int n_xi = 0, n_phi = 0;
  quadrature_shape(s.kind, s.samples, n_xi, n_phi);
  return 2 * n_xi * n_phi;
}

// A Gauss-Legendre rule mapped to [0, 1].
struct Rule01 {
  std::vector<double> x, w;
};
Rule01 rule01(int n) {
  const auto& r = math::gauss_legendre(n);
  Rule01 out;
  for (size_t k = 0; k < r.nodes.size(); ++k) {
    out.x.push_back(0.5 * (1.0 + r.nodes[k]));
    out.w.push_back(0.5 * r.weights[k]);
  }
  return out;
}

// The GPU shape's work-group a cell (docs/DEVICES.md, "Kernel shapes"): 32 work-items (a warp),
// each taking every 32nd chunk of 8 polar nodes (or every 32nd sample), within the device's limit and
// a power of two (the kernel's sum over the group halves it); 0 in the CPU shape (a work-item a cell).
size_t cell_group(const DeviceInfo& d) {
  if (d.kernel_shape != "gpu") return 0;
  size_t g = 32;
  while (g > 1 && g > d.max_work_group_size) g /= 2;
  return g;
}

// The program of a resolved spec: one kind, one estimator, the Charlie visibility; the GPU shape's
// group.
detail::ProgramSpec program_spec(const LutSpec& s, size_t group) {
  detail::ProgramSpec ps;
  ps.file = "dfg_lut.cl";
  ps.precision = s.precision;
  ps.defines.push_back({s.kind == LutKind::Ggx               ? "BRDFBAKE_LUT_GGX"
                        : s.kind == LutKind::GgxMultiscatter ? "BRDFBAKE_LUT_GGX_MULTISCATTER"
                                                             : "BRDFBAKE_LUT_CHARLIE",
                        "1"});
  const char* est = s.estimator == Estimator::Quadrature ? "BRDFBAKE_EST_QUADRATURE"
                    : s.estimator == Estimator::Vndf     ? "BRDFBAKE_EST_VNDF"
                    : s.estimator == Estimator::Ndf      ? "BRDFBAKE_EST_NDF"
                                                         : "BRDFBAKE_EST_UNIFORM";
  ps.defines.push_back({est, "1"});
  if (s.kind == LutKind::Charlie && s.sheen_visibility == SheenVisibility::Neubelt)
    ps.defines.push_back({"BRDFBAKE_SHEEN_NEUBELT", "1"});
  if (group > 0) {
    ps.defines.push_back({"BRDFBAKE_DFG_GROUPS", "1"});
    ps.defines.push_back({"BRDFBAKE_DFG_GROUP", std::to_string(group)});
  }
  return ps;
}

// The quadrature's nodes and weights, in the layout kernels/dfg_lut.cl documents.
std::vector<double> quadrature_nodes(int n_xi, int n_phi) {
  std::vector<double> q;
  const Rule01 gl_xi = rule01(n_xi), gl_phi = rule01(n_phi), gl_d = rule01(8);
  q.insert(q.end(), gl_xi.x.begin(), gl_xi.x.end());
  q.insert(q.end(), gl_xi.w.begin(), gl_xi.w.end());
  for (double x : gl_xi.x) q.push_back(0.5 * (1.0 - std::cos(M_PI * x)));
  for (size_t k = 0; k < gl_xi.x.size(); ++k) q.push_back(0.5 * M_PI * std::sin(M_PI * gl_xi.x[k]) * gl_xi.w[k]);
  q.insert(q.end(), gl_phi.x.begin(), gl_phi.x.end());
  q.insert(q.end(), gl_phi.w.begin(), gl_phi.w.end());
  for (int m = 0; m < n_phi; ++m) q.push_back(std::cos((m + 0.5) * M_PI / n_phi));
  q.insert(q.end(), gl_d.x.begin(), gl_d.x.end());
  q.insert(q.end(), gl_d.w.begin(), gl_d.w.end());
  return q;
}

class OpenClDfgLut final : public detail::DfgLutKernel {
 public:
  explicit OpenClDfgLut(Device& device) : device_(device) {}
  Table bake(const LutSpec& spec, LutTiming* timing, const Progress& progress) override {
    return bake_lut(device_, spec, timing, progress);
  }

 private:
  Device& device_;
};

}  // namespace

std::unique_ptr<detail::DfgLutKernel> detail::make_opencl_dfg_lut(Device& device) {
  return std::make_unique<OpenClDfgLut>(device);
}

Table bake_lut(Device& device, const LutSpec& in, LutTiming* timing, const Progress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  const LutSpec s = resolve_lut_spec(in);
  auto& dev = device.impl();

  const size_t group = cell_group(dev.info);
  cl::Program program = detail::build_program(dev, program_spec(s, group));
  int n_xi = 1, n_phi = 1;
  if (s.estimator == Estimator::Quadrature) quadrature_shape(s.kind, s.samples, n_xi, n_phi);
  const std::vector<double> q = quadrature_nodes(n_xi, n_phi);

  Table t = detail::make_lut_table(s);
  const std::string what = "kernel dfg_lut on '" + dev.info.name + "'";
  double device_seconds = detail::cl_call(what, [&] {
    auto real_buffer = [&](const std::vector<double>& v) {
      if (s.precision == Precision::Fp64)
        return cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(double),
                          const_cast<double*>(v.data()));
      std::vector<float> f(v.begin(), v.end());
      return cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, f.size() * sizeof(float), f.data());
    };
    const double table_bytes = double(t.data.size()) * sizeof(float);
    detail::check_device_memory(dev, table_bytes, table_bytes,
                                "a " + std::to_string(s.width) + "x" + std::to_string(s.height) + " DFG table");
    cl::Buffer xs = real_buffer(s.n_dot_v), ys = real_buffer(s.roughness), qb = real_buffer(q);
    cl::Buffer out(dev.context, CL_MEM_WRITE_ONLY, t.data.size() * sizeof(float));
    cl::KernelFunctor<cl::Buffer, cl::Buffer, cl::Buffer, cl_int, cl_int, cl_uint, cl::Buffer, cl_int, cl_int> dfg(
        program, "dfg_lut");
    // Rows go in launches of bounded work (runtime/launch.hpp): a progress line follows them, and a
    // stop request is honoured between them.
    const double seconds = detail::launch_in_tiles(
        static_cast<size_t>(s.width), static_cast<size_t>(s.height), double(evaluations(s)),
        [&](size_t x0, size_t nx, size_t y0, size_t ny) {
          const cl::EnqueueArgs range = group > 0 ? cl::EnqueueArgs(dev.queue, cl::NDRange(x0 * group, y0),
                                                                    cl::NDRange(nx * group, ny), cl::NDRange(group, 1))
                                                  : detail::tile_range(dev.queue, x0, nx, y0, ny);
          return dfg(range, out, xs, ys, s.width, s.height, static_cast<cl_uint>(s.samples), qb, n_xi, n_phi);
        },
        [&](double f) {
          if (progress) progress(f);
        });
    dev.queue.enqueueReadBuffer(out, CL_TRUE, 0, t.data.size() * sizeof(float), t.data.data());
    return seconds;
  });

  t.set_meta("device", dev.info.name + " (" + dev.info.platform_name + ", " + dev.info.driver_version + ")");
  t.set_meta("precision", precision_name(s.precision));
  t.set_meta("estimator", estimator_name(s.estimator));
  t.set_meta("samples", std::to_string(s.samples));
  t.set_meta("evaluations_per_texel", std::to_string(evaluations(s)));
  detail::set_lut_error_bound_meta(t, s);
  if (timing) {
    timing->device_seconds = device_seconds;
    timing->wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return t;
}

}  // namespace brdfbake
