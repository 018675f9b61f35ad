// The thin-film interference Fresnel table (KHR_materials_iridescence) on an OpenCL device
// (kernels/thin_film.cl), and the family's OpenCL kernel (kernel.hpp).
#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "families/thin_film/kernel.hpp"
#include "families/thin_film/model.hpp"
#include "runtime/program.hpp"

namespace brdfbake {

using detail::build_program;
using detail::cl_call;
using detail::ProgramSpec;

namespace {

class OpenClThinFilm final : public detail::ThinFilmKernel {
 public:
  explicit OpenClThinFilm(Device& device) : device_(device) {}
  Table bake(const ThinFilmSpec& spec, ThinFilmTiming* timing) override {
    return bake_thin_film(device_, spec, timing);
  }

 private:
  Device& device_;
};

}  // namespace

std::unique_ptr<detail::ThinFilmKernel> detail::make_opencl_thin_film(Device& device) {
  return std::make_unique<OpenClThinFilm>(device);
}

Table bake_thin_film(Device& device, const ThinFilmSpec& in, ThinFilmTiming* timing) {
  const auto t0 = std::chrono::steady_clock::now();
  const ThinFilmSpec r = resolve_thin_film_spec(in);
  const detail::ThinFilmParams film = detail::thin_film_params(r);
  auto& dev = device.impl();
  ProgramSpec ps;
  ps.file = "thin_film.cl";
  ps.precision = r.precision;
  cl::Program program = build_program(dev, ps);
  Table t = detail::make_thin_film_table(r);
  const std::vector<double> params = {film.outside_ior, film.film_ior, film.base_f0.r, film.base_f0.g, film.base_f0.b};
  double device_seconds = 0.0;
  cl_call("kernel thin_film_table on '" + dev.info.name + "'", [&] {
    auto real_buffer = [&](const std::vector<double>& v) {
      if (r.precision == Precision::Fp64)
        return cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(double),
                          const_cast<double*>(v.data()));
      std::vector<float> f(v.size());
      std::transform(v.begin(), v.end(), f.begin(), [](double d) { return static_cast<float>(d); });
      return cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, f.size() * sizeof(float), f.data());
    };
    cl::Buffer xb = real_buffer(t.x), yb = real_buffer(t.y), pb = real_buffer(params);
    cl::Buffer out(dev.context, CL_MEM_WRITE_ONLY, t.data.size() * sizeof(float));
    cl::KernelFunctor<cl::Buffer, cl::Buffer, cl::Buffer, cl_int, cl_int, cl::Buffer> kernel(program,
                                                                                             "thin_film_table");
    cl::Event event =
        kernel(cl::EnqueueArgs(dev.queue, cl::NDRange(static_cast<size_t>(r.width), static_cast<size_t>(r.height))),
               out, xb, yb, r.width, r.height, pb);
    event.wait();
    device_seconds = 1e-9 * double(event.getProfilingInfo<CL_PROFILING_COMMAND_END>() -
                                   event.getProfilingInfo<CL_PROFILING_COMMAND_START>());
    dev.queue.enqueueReadBuffer(out, CL_TRUE, 0, t.data.size() * sizeof(float), t.data.data());
    return 0;
  });
  t.set_meta("device", dev.info.name + " (" + dev.info.platform_name + ", " + dev.info.driver_version + ")");
  t.set_meta("precision", precision_name(r.precision));
  if (timing) {
    timing->device_seconds = device_seconds;
    timing->wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return t;
}

}  // namespace brdfbake
