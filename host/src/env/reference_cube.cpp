// An environment as the scalar reference sees it (reference_cube.hpp).
#include "env/reference_cube.hpp"

#include <algorithm>
#include <cmath>

#include "brdfbake/error.hpp"

namespace brdfbake::detail {

int reference_conversion_subdivision(const EnvImage& env, int size) {
  if (env.layout == EnvImage::Layout::Cube && env.width == size) return 1;
  // reference/envmap.hpp: at least 4 sub-cells per source pixel (or texel) side, 2 to 64
  const double pixels =
      env.layout == EnvImage::Layout::Cube ? static_cast<double>(env.width) / size : 0.25 * env.width / size;
  return static_cast<int>(std::clamp(std::ceil(4.0 * pixels), 2.0, 64.0));
}

reference::EnvCube reference_source_cube(const EnvImage& env, int size) {
  if (env.width < 1 || env.height < 1 || env.rgb.empty()) throw Error("empty environment");
  reference::EnvCube out;
  const int q = reference_conversion_subdivision(env, size);
  if (env.layout == EnvImage::Layout::Cube) {
    reference::EnvCube src;
    src.size = env.width;
    src.rgb.assign(env.rgb.begin(), env.rgb.end());
    out = env.width == size ? std::move(src) : reference::cube_resample(src, size, q);
  } else {
    reference::EnvEquirect src;
    src.width = env.width;
    src.height = env.height;
    src.rgb.assign(env.rgb.begin(), env.rgb.end());
    out = reference::equirect_to_cube(src, size, q);
  }
  for (double& v : out.rgb) v = static_cast<double>(static_cast<float>(v));
  return out;
}

std::vector<float> to_rgba(const reference::EnvCube& cube) {
  const size_t n = 6u * static_cast<size_t>(cube.size) * static_cast<size_t>(cube.size);
  std::vector<float> rgba(4 * n, 1.0f);
  for (size_t t = 0; t < n; ++t)
    for (size_t c = 0; c < 3; ++c) rgba[4 * t + c] = static_cast<float>(cube.rgb[3 * t + c]);
  return rgba;
}

reference::EnvCube to_reference_cube(const std::vector<float>& rgba, int size) {
  reference::EnvCube cube;
  cube.size = size;
  const size_t n = 6u * static_cast<size_t>(size) * static_cast<size_t>(size);
  cube.rgb.resize(3 * n);
  for (size_t t = 0; t < n; ++t)
    for (size_t c = 0; c < 3; ++c) cube.rgb[3 * t + c] = rgba[4 * t + c];
  return cube;
}

}  // namespace brdfbake::detail
