// Internal: the environment families' shared engine (prefilter and irradiance, host/src/families/):
// cube texels and their solid angles, the metadata every cube records, the device helpers of
// kernels/cubemap.cl (programs, buffers, the padded mip chain), the conversion of an environment to
// a cube (conversion.cpp) and the bright texels that environment sampling takes out
// (bright_texels.cpp).
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "brdfbake/environment.hpp"
#include "runtime/program.hpp"

namespace brdfbake::detail {

// BRDFBAKE_LANES of the environment kernels: sample and point arrays are padded to a multiple.
inline constexpr int kEnvVectorWidth = 8;

inline size_t face_texels(int size) { return 6u * static_cast<size_t>(size) * static_cast<size_t>(size); }

inline double luminance(const float* rgb) {
  return 0.2126 * double(rgb[0]) + 0.7152 * double(rgb[1]) + 0.0722 * double(rgb[2]);
}

// The exact solid angle of every texel (i, j) of a face of `size`, row-major.
std::vector<double> texel_solid_angles(int size);

// "a,b,c".
std::string comma_join(const std::vector<std::string>& items);
// The cube conventions every cubemap output records (faces, orientation, up, equirect mapping).
void cube_conventions_metadata(CubeLevels& cube);
// Where the environment came from (source, description, what --sanitize replaced).
void environment_source_metadata(CubeLevels& cube, const EnvImage& env);
// Biased, opt-in (PrefilterSpec::clamp_luminance): luminance above `limit` compressed to
// limit (1 + log(lum / limit)), RGBA texels.
void clamp_luminance(std::vector<float>& rgba, double limit);

// ---- On the device (kernels/cubemap.cl) -----------------------------------------------------------

// A read-only buffer of `v` in the precision's real type.
cl::Buffer env_real_buffer(Device::Impl& dev, Precision p, const std::vector<double>& v);
// The program of kernels/`file` in precision `p` with `defines`.
cl::Program env_program(Device::Impl& dev, const char* file, Precision p,
                        std::vector<std::pair<std::string, std::string>> defines = {});
// Device buffers stay within CL_DEVICE_MAX_MEM_ALLOC_SIZE (GPUs allow a quarter of their memory or
// less in one allocation): a larger one is refused here with its size, not by the driver.
void check_allocation(const Device::Impl& dev, size_t bytes, const std::string& what);
// One work-item a texel of a cube of face `size`.
inline cl::NDRange cube_range(int size) {
  return cl::NDRange(static_cast<size_t>(size), 6u * static_cast<size_t>(size));
}
// The total device time of finished kernels.
double sum_seconds(const std::vector<cl::Event>& events);

// The padded mip chain on the device: every level of a cube down to 1x1, each face with a border of
// one texel (kernels/cubemap.cl).
struct PaddedChain {
  cl::Buffer buffer;
  std::vector<cl_int> info;  // offset, size per level
  int levels = 0;
  cl::Buffer info_buffer;
};
// Builds the chain from an unpadded RGBA cube already on the device; appends the kernel events.
PaddedChain build_padded_chain(Device::Impl& dev, cl::Program& cube_prog, const cl::Buffer& level0, int size,
                               std::vector<cl::Event>& events);

// The environment as a cube of face `size` on the device (environment_to_cube); program_built runs
// once the conversion's program is built, before its kernels (prefilter_environment builds the
// filter's program meanwhile); source_done once env's pixels are no longer read (the caller may
// release them), before level 0 takes its full size (an equirect's level 0 is taken in as RGB).
CubeLevels convert_to_cube(Device& device, const EnvImage& env, int size, double* device_seconds,
                           const std::function<void()>& program_built, const std::function<void()>& source_done);

}  // namespace brdfbake::detail
