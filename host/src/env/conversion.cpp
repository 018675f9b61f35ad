// An environment (equirect or cube) as a cube of a given face size on the device (kernels/cubemap.cl):
// level 0 of the prefiltered chain and the source of the irradiance cube.
#include <algorithm>
#include <string>
#include <vector>

#include "brdfbake/error.hpp"
#include "env/cube.hpp"
#include "runtime/launch.hpp"

namespace brdfbake {

CubeLevels detail::convert_to_cube(Device& device, const EnvImage& env, int size, double* device_seconds,
                                   const std::function<void()>& program_built) {
  if (size < 1 || size > kPrefilterMaxSize)
    throw Error("cube size must be in 1.." + std::to_string(kPrefilterMaxSize) + " (got " + std::to_string(size) + ")");
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
    check_device_memory(dev, std::max(source_bytes, cube_bytes), 2.5 * (source_bytes + cube_bytes),
                        "converting '" + env.source + "' to a cube of " + std::to_string(size) + "^2");
  }
  const double seconds = cl_call(what, [&] {
    cl::Program prog = env_program(dev, "cubemap.cl", Precision::Fp32);
    if (program_built) program_built();
    std::vector<cl::Event> events;
    if (env.layout == EnvImage::Layout::Equirect) {
      // the packed RGB pixels as they are (the kernel reads three floats a pixel): on a CPU device
      // no copy at all, elsewhere one upload
      const size_t bytes = env.rgb.size() * sizeof(float);
      check_allocation(dev, bytes,
                       "the " + std::to_string(env.width) + "x" + std::to_string(env.height) + " environment");
      cl::Buffer src(dev.context, CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR, bytes, const_cast<float*>(env.rgb.data()));
      // k x k samples per texel: about two per equirect pixel along the equator
      const int k = std::clamp((env.width + 2 * size - 1) / (2 * size), 1, 16);
      cl::KernelFunctor<cl::Buffer, cl_int, cl_int, cl::Buffer, cl_int, cl_int, cl_int> convert(prog,
                                                                                                "equirect_to_cube");
      // one work-item per 8 texels of a row (kernels/cubemap.cl), one face at a time into a face buffer
      const size_t face_bytes = 4 * static_cast<size_t>(size) * static_cast<size_t>(size) * sizeof(float);
      check_allocation(dev, face_bytes, "a face of the " + std::to_string(size) + "^2 cube");
      cl::Buffer face_buf(dev.context, CL_MEM_WRITE_ONLY, face_bytes);
      const cl::NDRange rows(static_cast<size_t>((size + kEnvVectorWidth - 1) / kEnvVectorWidth),
                             static_cast<size_t>(size));
      for (int f = 0; f < 6; ++f) {
        const cl::EnqueueArgs range(dev.queue, cl::NDRange(0, size_t(f) * size_t(size)), rows, cl::NullRange);
        events.push_back(convert(range, src, env.width, env.height, face_buf, size, k, f));
        dev.queue.enqueueReadBuffer(face_buf, CL_TRUE, 0, face_bytes,
                                    cube.levels[0].data() + (face_bytes / sizeof(float)) * size_t(f));
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
        PaddedChain chain = build_padded_chain(dev, prog, src, s, events);
        // resample from the chain level closest above the target size
        int m = 0;
        while (m + 1 < chain.levels && chain.info[size_t(2 * m + 3)] >= size) ++m;
        const int ms = chain.info[size_t(2 * m + 1)];
        const int k = std::clamp((ms + size - 1) / size, 1, 16);
        cl::KernelFunctor<cl::Buffer, cl_int, cl_int, cl::Buffer, cl_int, cl_int> resample(prog, "cube_resample");
        events.push_back(resample(cl::EnqueueArgs(dev.queue, cube_range(size)), chain.buffer, chain.info[size_t(2 * m)],
                                  ms, dst, size, k));
      }
      dev.queue.enqueueReadBuffer(dst, CL_TRUE, 0, cube.levels[0].size() * sizeof(float), cube.levels[0].data());
    }
    return sum_seconds(events);
  });
  if (device_seconds) *device_seconds = seconds;
  cube_conventions_metadata(cube);
  cube.set_meta("source", env.source);
  return cube;
}

CubeLevels environment_to_cube(Device& device, const EnvImage& env, int size, double* device_seconds) {
  return detail::convert_to_cube(device, env, size, device_seconds, {});
}

}  // namespace brdfbake
