// Bulk BRDF evaluation on the device (kernels/brdf_eval.cl): the program of a model and the lobes its
// materials use, buffers in the program's precision, and BrdfEvaluator, which evaluates batches of
// direction pairs against a set of materials.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "brdfbake/brdf.hpp"
#include "brdfbake/error.hpp"
#include "families/brdf_eval/model.hpp"
#include "runtime/launch.hpp"
#include "runtime/program.hpp"

namespace brdfbake {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Lane widths measured by bench/brdf_bench on PoCL (docs/BENCHMARKS.md): float16 and double8 fill
// an AVX-512 register; a GPU shape's work-item takes 4.
int default_lanes(Precision p, const DeviceInfo& device) {
  if (device.kernel_shape == "gpu") return 4;
  return p == Precision::Fp64 ? 8 : 16;
}

}  // namespace

detail::ProgramSpec detail::brdf_program_spec(BrdfModel model, const Lobes& lobes, const EvalOptions& options,
                                              int lanes) {
  detail::ProgramSpec ps;
  ps.file = "brdf_eval.cl";
  ps.precision = options.precision;
  ps.defines.push_back({brdf_model_define(model), "1"});
  ps.defines.push_back({"BRDFBAKE_LANES", std::to_string(lanes)});
  const std::pair<bool, const char*> flags[] = {{lobes.diffuse, "BRDFBAKE_LOBE_DIFFUSE"},
                                                {lobes.subsurface, "BRDFBAKE_LOBE_SUBSURFACE"},
                                                {lobes.sheen, "BRDFBAKE_LOBE_SHEEN"},
                                                {lobes.clearcoat, "BRDFBAKE_LOBE_CLEARCOAT"},
                                                {lobes.anisotropic, "BRDFBAKE_LOBE_ANISOTROPIC"},
                                                {lobes.metal, "BRDFBAKE_LOBE_METAL"},
                                                {lobes.specular_color, "BRDFBAKE_LOBE_SPECULAR_COLOR"},
                                                {lobes.beckmann, "BRDFBAKE_CT_BECKMANN"},
                                                {lobes.ggx, "BRDFBAKE_CT_GGX"}};
  for (const auto& [on, name] : flags)
    if (on) ps.defines.push_back({name, "1"});
  if (options.fast_math) ps.options = "-cl-fast-relaxed-math";
  return ps;
}

int detail::resolve_lanes(const EvalOptions& o, const DeviceInfo& device) {
  const int lanes = o.lanes == 0 ? default_lanes(o.precision, device) : o.lanes;
  if (lanes != 4 && lanes != 8 && lanes != 16)
    throw Error("lanes must be 4, 8 or 16 (got " + std::to_string(lanes) + ")");
  return lanes;
}

size_t detail::eval_chunk_pairs(const DeviceInfo& device) {
  constexpr size_t kCpuChunk = size_t(1) << 16, kMaxChunk = size_t(1) << 21;
  if (device.kernel_shape != "gpu") return kCpuChunk;
  const size_t want = size_t(std::max(1u, device.compute_units)) * kGpuPairsPerComputeUnit;
  return std::min(kMaxChunk, std::max(kCpuChunk, want));
}

cl::Buffer detail::brdf_real_buffer(Device::Impl& dev, Precision p, const std::vector<double>& v, cl_mem_flags flags) {
  const std::vector<double> data = v.empty() ? std::vector<double>{0.0} : v;
  if (p == Precision::Fp64)
    return cl::Buffer(dev.context, flags | CL_MEM_COPY_HOST_PTR, data.size() * sizeof(double),
                      const_cast<double*>(data.data()));
  std::vector<float> f(data.begin(), data.end());
  return cl::Buffer(dev.context, flags | CL_MEM_COPY_HOST_PTR, f.size() * sizeof(float), f.data());
}

size_t detail::real_size(Precision p) { return p == Precision::Fp64 ? sizeof(double) : sizeof(float); }

void detail::read_reals(Device::Impl& dev, Precision p, const cl::Buffer& buffer, size_t n, double* out) {
  if (p == Precision::Fp64) {
    dev.queue.enqueueReadBuffer(buffer, CL_TRUE, 0, n * sizeof(double), out);
    return;
  }
  std::vector<float> f(n);
  dev.queue.enqueueReadBuffer(buffer, CL_TRUE, 0, n * sizeof(float), f.data());
  std::copy(f.begin(), f.end(), out);
}

std::string detail::pair_error(size_t i, const char* which) {
  return "direction pair " + std::to_string(i) + ": " + which + " is zero or not finite";
}

bool detail::unit_direction(const double* v, double* out) {
  const double m = std::max(std::fabs(v[0]), std::max(std::fabs(v[1]), std::fabs(v[2])));
  if (!(m > 0.0) || !std::isfinite(m) || !std::isfinite(v[0] + v[1] + v[2])) return false;
  const double x = v[0] / m, y = v[1] / m, z = v[2] / m;
  const double len = std::sqrt(x * x + y * y + z * z);
  out[0] = x / len;
  out[1] = y / len;
  out[2] = z / len;
  return true;
}

namespace {
constexpr size_t kPairPlanes = 9;  // wi, wo, h (kernels/brdf_eval.cl, brdf_pairs)

}  // namespace

struct BrdfEvaluator::Impl {
  std::optional<Device> device;
  BrdfModel model;
  std::vector<Material> materials;
  EvalOptions options;
  int lanes;
  Lobes lobes;
  cl::Program program;
  cl::Buffer params, sheen;
  cl::Buffer dirs, out;
  size_t capacity = 0;  // pairs the dirs/out buffers hold
  std::vector<double> staging;
};

BrdfEvaluator::BrdfEvaluator(Device& device, BrdfModel model, std::vector<Material> materials,
                             const EvalOptions& options)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.device = device;
  s.model = model;
  s.materials = std::move(materials);
  s.options = options;
  if (s.materials.empty()) throw Error("no materials to evaluate");
  for (size_t i = 0; i < s.materials.size(); ++i) validate_material(s.materials[i], "material " + std::to_string(i));
  s.lanes = detail::resolve_lanes(options, device.info());
  s.lobes = options.specialize ? lobes_used(model, s.materials) : all_lobes(model);
  auto& dev = device.impl();
  s.program = detail::build_program(dev, detail::brdf_program_spec(model, s.lobes, options, s.lanes));
  const detail::PackedMaterials p = detail::pack_materials(model, s.materials);
  detail::cl_call("uploading materials", [&] {
    s.params = detail::brdf_real_buffer(dev, options.precision, p.params);
    s.sheen = detail::brdf_real_buffer(dev, options.precision, p.sheen);
  });
}

BrdfEvaluator::~BrdfEvaluator() = default;

const Lobes& BrdfEvaluator::lobes() const { return impl_->lobes; }
size_t BrdfEvaluator::material_count() const { return impl_->materials.size(); }
int BrdfEvaluator::lanes() const { return impl_->lanes; }
size_t BrdfEvaluator::chunk_pairs() const { return detail::eval_chunk_pairs(impl_->device->info()); }

void BrdfEvaluator::eval(const double* pairs, size_t count, double* out, EvalTiming* timing) {
  const auto t0 = Clock::now();
  Impl& s = *impl_;
  if (count == 0) {
    if (timing) *timing = {};
    return;
  }
  auto& dev = s.device->impl();
  const size_t lanes = static_cast<size_t>(s.lanes);
  const size_t stride = (count + lanes - 1) / lanes * lanes;
  if (stride > static_cast<size_t>(INT32_MAX)) throw Error("too many direction pairs in one batch");
  const size_t n_mat = s.materials.size();
  const Precision p = s.options.precision;

  // Normalise (in double) into nine planes of `stride` values, zero-padded: wi, wo and their half
  // vector (kernels/brdf_eval.cl, brdf_pairs, says why h is formed here).
  s.staging.assign(kPairPlanes * stride, 0.0);
  for (size_t i = 0; i < count; ++i) {
    double wi[3], wo[3], h[3];
    if (!detail::unit_direction(pairs + 6 * i, wi)) throw Error(detail::pair_error(i, "wi"));
    if (!detail::unit_direction(pairs + 6 * i + 3, wo)) throw Error(detail::pair_error(i, "wo"));
    const double sum[3] = {wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]};
    if (!detail::unit_direction(sum, h)) h[0] = h[1] = 0.0, h[2] = 1.0;  // wi = -wo: no half vector (and f = 0)
    for (size_t c = 0; c < 3; ++c) {
      s.staging[c * stride + i] = wi[c];
      s.staging[(3 + c) * stride + i] = wo[c];
      s.staging[(6 + c) * stride + i] = h[c];
    }
  }
  const std::string what = "kernel brdf_pairs on '" + dev.info.name + "'";
  const double device_seconds = detail::cl_call(what, [&] {
    if (stride > s.capacity) {
      s.dirs = cl::Buffer(dev.context, CL_MEM_READ_ONLY, kPairPlanes * stride * detail::real_size(p));
      s.out = cl::Buffer(dev.context, CL_MEM_WRITE_ONLY, 3 * n_mat * stride * detail::real_size(p));
      s.capacity = stride;
    }
    if (p == Precision::Fp64) {
      dev.queue.enqueueWriteBuffer(s.dirs, CL_FALSE, 0, kPairPlanes * stride * sizeof(double), s.staging.data());
    } else {
      // Components below FLT_MIN are flushed to zero here rather than left to the device's denormal
      // mode: in fp32 a cosine under 1.2e-38 is the horizon (docs/CONVENTIONS.md).
      std::vector<float> f(s.staging.size());
      for (size_t k = 0; k < f.size(); ++k) {
        const float v = static_cast<float>(s.staging[k]);
        f[k] = std::fabs(v) < std::numeric_limits<float>::min() ? 0.0f : v;
      }
      dev.queue.enqueueWriteBuffer(s.dirs, CL_TRUE, 0, f.size() * sizeof(float), f.data());
    }
    cl::KernelFunctor<cl::Buffer, cl_int, cl::Buffer, cl::Buffer, cl::Buffer> kernel(s.program, "brdf_pairs");
    cl::Event e = kernel(cl::EnqueueArgs(dev.queue, cl::NDRange(stride / lanes, n_mat)), s.dirs,
                         static_cast<cl_int>(stride), s.params, s.sheen, s.out);
    e.wait();
    std::vector<double> planes(3 * n_mat * stride);
    detail::read_reals(dev, p, s.out, planes.size(), planes.data());
    for (size_t m = 0; m < n_mat; ++m)
      for (size_t c = 0; c < 3; ++c) {
        const double* src = planes.data() + (m * 3 + c) * stride;
        for (size_t i = 0; i < count; ++i) out[(m * count + i) * 3 + c] = src[i];
      }
    return detail::event_seconds(e);
  });
  if (timing) {
    timing->device_seconds = device_seconds;
    timing->wall_seconds = seconds_since(t0);
  }
}

}  // namespace brdfbake
