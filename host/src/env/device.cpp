// The environment families' device helpers (kernels/cubemap.cl): real-typed buffers, programs, the
// allocation limit, and the padded mip chain of a cube.
#include <limits>
#include <string>
#include <vector>

#include "brdfbake/error.hpp"
#include "env/cube.hpp"
#include "runtime/launch.hpp"

namespace brdfbake {

cl::Buffer detail::env_real_buffer(Device::Impl& dev, Precision p, const std::vector<double>& v) {
  if (p == Precision::Fp64)
    return cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(double),
                      const_cast<double*>(v.data()));
  std::vector<float> f(v.size());
  for (size_t k = 0; k < v.size(); ++k) f[k] = static_cast<float>(v[k]);
  return cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, f.size() * sizeof(float), f.data());
}

cl::Program detail::env_program(Device::Impl& dev, const char* file, Precision p,
                                std::vector<std::pair<std::string, std::string>> defines) {
  detail::ProgramSpec ps;
  ps.file = file;
  ps.precision = p;
  ps.defines = std::move(defines);
  return detail::build_program(dev, ps);
}

void detail::check_allocation(const Device::Impl& dev, size_t bytes, const std::string& what) {
  if (dev.info.max_alloc == 0 || bytes <= dev.info.max_alloc) return;
  throw Error(what + " needs a device buffer of " + std::to_string(bytes >> 20) + " MiB, more than '" + dev.info.name +
              "' allocates at once (CL_DEVICE_MAX_MEM_ALLOC_SIZE, " + std::to_string(dev.info.max_alloc >> 20) +
              " MiB): give a smaller size or input, or another device");
}

detail::PaddedChain detail::build_padded_chain(Device::Impl& dev, cl::Program& cube_prog, const cl::Buffer& level0,
                                               int size, std::vector<cl::Event>& events) {
  PaddedChain c;
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
  c.info_buffer =
      cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, c.info.size() * sizeof(cl_int), c.info.data());
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

double detail::sum_seconds(const std::vector<cl::Event>& events) {
  double s = 0.0;
  for (const auto& e : events) s += detail::event_seconds(e);
  return s;
}

}  // namespace brdfbake
