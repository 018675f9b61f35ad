// An environment (equirect or cube) as a cube of a given face size on the device (kernels/cubemap.cl):
// level 0 of the prefiltered chain and the source of the irradiance cube.
#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "brdfbake/error.hpp"
#include "env/cube.hpp"
#include "runtime/launch.hpp"

namespace brdfbake {

CubeLevels detail::convert_to_cube(Device& device, const EnvImage& env, int size, double* device_seconds,
                                   const std::function<void()>& program_built,
                                   const std::function<void()>& source_done) {
  if (size < 1 || size > kPrefilterMaxSize)
    throw Error("cube size must be in 1.." + std::to_string(kPrefilterMaxSize) + " (got " + std::to_string(size) + ")");
  if (env.width < 1 || env.height < 1 || env.rgb.empty()) throw Error("empty environment");
  auto& dev = device.impl();
  CubeLevels cube;
  cube.size = size;
  cube.levels.resize(1);
  const size_t texels = face_texels(size);
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
      // Level 0 is taken in as packed RGB (3/4 of RGBA: 72 MiB at 1024^2) while the equirect is
      // alive, and spread to RGBA in place once it is released (below): the capacity is reserved
      // now and its last quarter untouched until then. One work-item per 8 texels of a row
      // (kernels/cubemap.cl), one face at a time.
      cube.levels[0].reserve(4 * texels);
      cube.levels[0].resize(3 * texels);
      const size_t face_bytes = 3 * static_cast<size_t>(size) * static_cast<size_t>(size) * sizeof(float);
      check_allocation(dev, face_bytes, "a face of the " + std::to_string(size) + "^2 cube");
      const cl::NDRange rows(static_cast<size_t>((size + kEnvVectorWidth - 1) / kEnvVectorWidth),
                             static_cast<size_t>(size));
      float* const level0 = cube.levels[0].data();
      const size_t face_floats = face_bytes / sizeof(float);
      if (dev.info.type == "cpu") {
        // a CPU device's memory is the host's: each face is written where level 0 holds it (no face
        // buffer: 16 MiB less at 1024^2, while the map and level 0 are both alive), mapped to be read
        for (int f = 0; f < 6; ++f) {
          cl::Buffer face_buf(dev.context, CL_MEM_WRITE_ONLY | CL_MEM_USE_HOST_PTR, face_bytes,
                              level0 + face_floats * size_t(f));
          const cl::EnqueueArgs range(dev.queue, cl::NDRange(0, size_t(f) * size_t(size)), rows, cl::NullRange);
          events.push_back(convert(range, src, env.width, env.height, face_buf, size, k, f));
          void* mapped = dev.queue.enqueueMapBuffer(face_buf, CL_TRUE, CL_MAP_READ, 0, face_bytes);
          if (mapped != level0 + face_floats * size_t(f))  // a copy after all: take its values
            std::memcpy(level0 + face_floats * size_t(f), mapped, face_bytes);
          dev.queue.enqueueUnmapMemObject(face_buf, mapped);
        }
        dev.queue.finish();  // the unmaps done before the buffers over level 0 go
        return sum_seconds(events);
      }
      cl::Buffer face_buf(dev.context, CL_MEM_WRITE_ONLY, face_bytes);
      for (int f = 0; f < 6; ++f) {
        const cl::EnqueueArgs range(dev.queue, cl::NDRange(0, size_t(f) * size_t(size)), rows, cl::NullRange);
        events.push_back(convert(range, src, env.width, env.height, face_buf, size, k, f));
        dev.queue.enqueueReadBuffer(face_buf, CL_TRUE, 0, face_bytes, level0 + face_floats * size_t(f));
      }
      return sum_seconds(events);
    } else {
      cube.levels[0].resize(4 * texels);
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
  if (source_done) source_done();  // env's pixels are not read again
  if (cube.levels[0].size() == 3 * texels) {
    // RGB to RGBA in place, from the last texel down (texel t's RGBA, from 4t on, lies past the RGB
    // of every lower texel, below 3t): within the reserved capacity, no second copy
    std::vector<float>& level0 = cube.levels[0];
    level0.resize(4 * texels);
    for (size_t t = texels; t-- > 0;) {
      const float r = level0[3 * t], g = level0[3 * t + 1], b = level0[3 * t + 2];
      level0[4 * t] = r;
      level0[4 * t + 1] = g;
      level0[4 * t + 2] = b;
      level0[4 * t + 3] = 1.0f;
    }
  }
  if (device_seconds) *device_seconds = seconds;
  cube_conventions_metadata(cube);
  cube.set_meta("source", env.source);
  return cube;
}

CubeLevels environment_to_cube(Device& device, const EnvImage& env, int size, double* device_seconds) {
  return detail::convert_to_cube(device, env, size, device_seconds, {}, {});
}

}  // namespace brdfbake
