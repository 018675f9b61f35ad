// The Fresnel tables on an OpenCL device (kernels/fresnel.cl): the program of a model, cells padded
// to whole work-items, and the family's OpenCL kernel (kernel.hpp).
#include <algorithm>
#include <chrono>
#include <limits>
#include <string>
#include <vector>

#include "brdfbake/fresnel.hpp"
#include "families/fresnel/kernel.hpp"
#include "families/fresnel/model.hpp"
#include "runtime/program.hpp"

namespace brdfbake {

using detail::Resolved;

namespace {

// Cells per work-item in kernels/fresnel.cl: chunks(device) vectors of lanes(precision) cells; 16
// lanes fill a 512-bit register in fp32 (double16 spills: fp64 keeps 8). See
// kernels/common/fresnel.clh. The CPU shape takes 8 chunks a work-item (128 cells in fp32), the GPU
// shape (docs/DEVICES.md, "Kernel shapes") one chunk of 8 lanes: 16x as many work-items, 8 cells
// each (the kernel stores 8 cells at a time).
int chunks(const DeviceInfo& d) { return d.kernel_shape == "gpu" ? 1 : 8; }
int lanes(Precision p, const DeviceInfo& d) { return p == Precision::Fp64 || d.kernel_shape == "gpu" ? 8 : 16; }

class OpenClFresnel final : public detail::FresnelKernel {
 public:
  explicit OpenClFresnel(Device& device) : device_(device) {}
  Table bake(const FresnelSpec& spec, FresnelTiming* timing) override { return bake_fresnel(device_, spec, timing); }

 private:
  Device& device_;
};

}  // namespace

std::unique_ptr<detail::FresnelKernel> detail::make_opencl_fresnel(Device& device) {
  return std::make_unique<OpenClFresnel>(device);
}

Table bake_fresnel(Device& device, const FresnelSpec& spec, FresnelTiming* timing) {
  const auto t0 = std::chrono::steady_clock::now();
  const Resolved r = detail::resolve_fresnel(spec);
  auto& dev = device.impl();

  detail::ProgramSpec ps;
  ps.file = "fresnel.cl";
  ps.precision = spec.precision;
  ps.defines.push_back({detail::fresnel_model_info(spec.model).define, "1"});
  ps.defines.push_back({"BRDFBAKE_FRESNEL_CHUNKS", std::to_string(chunks(dev.info))});
  ps.defines.push_back({"BRDFBAKE_LANES", std::to_string(lanes(spec.precision, dev.info))});
  if (r.two_d) ps.defines.push_back({"BRDFBAKE_FRESNEL_2D", "1"});
  cl::Program program = detail::build_program(dev, ps);

  // xs padded to whole work-items (the kernel loads whole vectors; the pad is never stored).
  const size_t cells_per_item = static_cast<size_t>(chunks(dev.info) * lanes(spec.precision, dev.info));
  const size_t items = (static_cast<size_t>(r.width) + cells_per_item - 1) / cells_per_item;
  std::vector<double> xs = r.x;
  xs.resize(items * cells_per_item, 1.0);
  std::vector<double> ys = r.two_d ? r.y : std::vector<double>{0.0};

  Table t = detail::make_fresnel_table(r);
  const std::string what = "kernel fresnel_table on '" + dev.info.name + "'";
  const double device_seconds = detail::cl_call(what, [&] {
    auto real_buffer = [&](const std::vector<double>& v, cl_mem_flags flags) {
      if (spec.precision == Precision::Fp64)
        return cl::Buffer(dev.context, flags | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(double),
                          const_cast<double*>(v.data()));
      std::vector<float> f(v.size());
      // Saturated to the float range: a parameter beyond it (--bias 1e308) would be infinite on the
      // device, and inf * 0 is NaN where the double model gives a finite product (issue 24, numbers
      // at the edge); FLT_MAX keeps every product and sum the model clamps to [0, 1] on its side.
      std::transform(v.begin(), v.end(), f.begin(), [](double d) {
        return static_cast<float>(
            std::clamp(d, -double(std::numeric_limits<float>::max()), double(std::numeric_limits<float>::max())));
      });
      return cl::Buffer(dev.context, flags | CL_MEM_COPY_HOST_PTR, f.size() * sizeof(float), f.data());
    };
    cl::Buffer xb = real_buffer(xs, CL_MEM_READ_ONLY), yb = real_buffer(ys, CL_MEM_READ_ONLY),
               pb = real_buffer(r.params, CL_MEM_READ_ONLY);
    cl::Buffer out(dev.context, CL_MEM_WRITE_ONLY, t.data.size() * sizeof(float));
    // Make the output resident before the timed kernel: on a CPU device a fresh buffer's pages
    // fault in on first touch, which would be counted as kernel time (measured here: ~24 ms for
    // a 1<<22-cell table, 7x the Schlick kernel itself) and would hide the models' differences.
    dev.queue.enqueueFillBuffer(out, 0.0f, 0, t.data.size() * sizeof(float));
    cl::KernelFunctor<cl::Buffer, cl::Buffer, cl::Buffer, cl_int, cl_int, cl::Buffer> kernel(program, "fresnel_table");
    cl::Event event = kernel(cl::EnqueueArgs(dev.queue, cl::NDRange(items, static_cast<size_t>(r.height))), out, xb, yb,
                             r.width, r.height, pb);
    event.wait();
    const double seconds = detail::event_seconds(event);
    dev.queue.enqueueReadBuffer(out, CL_TRUE, 0, t.data.size() * sizeof(float), t.data.data());
    return seconds;
  });

  t.set_meta("device", dev.info.name + " (" + dev.info.platform_name + ", " + dev.info.driver_version + ")");
  t.set_meta("precision", precision_name(spec.precision));
  if (timing) {
    timing->device_seconds = device_seconds;
    timing->wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return t;
}

}  // namespace brdfbake
