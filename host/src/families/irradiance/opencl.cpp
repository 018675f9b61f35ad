// The irradiance cube on an OpenCL device (kernels/irradiance.cl): direct cosine convolution of the
// environment converted to a cube, over its rest reduced to points and its bright texels at full
// resolution; the SH are projected on the host (sh_projection.cpp). And the family's OpenCL kernel
// (kernel.hpp).
#include <chrono>
#include <string>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "env/cube.hpp"
#include "families/irradiance/kernel.hpp"
#include "families/irradiance/model.hpp"
#include "runtime/launch.hpp"
#include "runtime/program.hpp"

namespace brdfbake {
namespace {

constexpr int kMaxPointSource = 64;  // the rest is summed at this face size or below
constexpr int kBrightSplit = 2;      // sub-cells per texel side of a bright texel's footprint

using detail::face_texels;

// The rest of the cube (bright texels removed) reduced by solid-angle-weighted 2x2 means to a face
// size of at most kMaxPointSource (or until the size is odd), as points (direction, L Omega).
void rest_points(const CubeLevels& cube, const std::vector<BrightTexel>& bright, std::vector<double> (&arrays)[6]) {
  int s = cube.size;
  std::vector<double> rgb(3 * face_texels(s));
  for (size_t t = 0; t < face_texels(s); ++t)
    for (size_t c = 0; c < 3; ++c) rgb[3 * t + c] = cube.levels[0][4 * t + c];
  for (const BrightTexel& b : bright)
    for (size_t c = 0; c < 3; ++c)
      rgb[3 * ((size_t(b.face) * size_t(s) + size_t(b.j)) * size_t(s) + size_t(b.i)) + c] = 0.0;
  std::vector<double> omega;
  auto solid_angles = [&](int n) {
    omega.assign(size_t(n) * size_t(n), 0.0);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) omega[size_t(j) * size_t(n) + size_t(i)] = math::cube_texel_solid_angle(n, i, j);
  };
  solid_angles(s);
  while (s > kMaxPointSource && s % 2 == 0) {
    const int h = s / 2;
    std::vector<double> next(3 * face_texels(h), 0.0);
    std::vector<double> parent = omega;
    solid_angles(h);
    for (int f = 0; f < 6; ++f)
      for (int j = 0; j < h; ++j)
        for (int i = 0; i < h; ++i) {
          double sum[3] = {0, 0, 0};
          for (int dj = 0; dj < 2; ++dj)
            for (int di = 0; di < 2; ++di) {
              const size_t src = (size_t(f) * size_t(s) + size_t(2 * j + dj)) * size_t(s) + size_t(2 * i + di);
              const double w = parent[size_t(2 * j + dj) * size_t(s) + size_t(2 * i + di)];
              for (size_t c = 0; c < 3; ++c) sum[c] += w * rgb[3 * src + c];
            }
          const size_t dst = (size_t(f) * size_t(h) + size_t(j)) * size_t(h) + size_t(i);
          const double w = omega[size_t(j) * size_t(h) + size_t(i)];
          for (size_t c = 0; c < 3; ++c) next[3 * dst + c] = sum[c] / w;
        }
    rgb = std::move(next);
    s = h;
  }
  for (int f = 0; f < 6; ++f)
    for (int j = 0; j < s; ++j)
      for (int i = 0; i < s; ++i) {
        const auto d = math::cube_texel_direction(f, s, i, j);
        const double w = omega[size_t(j) * size_t(s) + size_t(i)];
        const size_t t = (size_t(f) * size_t(s) + size_t(j)) * size_t(s) + size_t(i);
        arrays[0].push_back(d.x);
        arrays[1].push_back(d.y);
        arrays[2].push_back(d.z);
        for (size_t c = 0; c < 3; ++c) arrays[3 + c].push_back(rgb[3 * t + c] * w);
      }
}

// The points the cube sums: the rest of the source (rest_points), and the bright texels at full
// resolution as their bilinear footprints split into sub-cells (the cosine's kink at the horizon
// cuts through them). Structure of arrays x, y, z, r, g, b, padded to a multiple of 8; *n_points
// the padded count.
std::vector<double> irradiance_points(const CubeLevels& cube, int* n_points) {
  const int s = cube.size;
  const std::vector<BrightTexel> bright = find_bright_texels(cube, kDefaultBrightTexels, kBrightRatio);
  std::vector<double> arrays[6];
  rest_points(cube, bright, arrays);
  // bright texels at full resolution, as their bilinear footprints split into sub-cells: the
  // cosine's kink at the horizon cuts through them
  int n_bright = 0;
  const std::vector<double> bp = bright_texel_points(bright, s, kBrightSplit, 1.0, &n_bright);
  const size_t padded = bp.size() / 6;
  for (size_t a = 0; a < 6; ++a)
    arrays[a].insert(arrays[a].end(), bp.begin() + static_cast<std::ptrdiff_t>(a * padded),
                     bp.begin() + static_cast<std::ptrdiff_t>(a * padded + size_t(n_bright)));
  while (arrays[0].size() % 8 != 0) {
    arrays[0].push_back(0.0);
    arrays[1].push_back(0.0);
    arrays[2].push_back(1.0);
    for (size_t c = 0; c < 3; ++c) arrays[3 + c].push_back(0.0);
  }
  std::vector<double> pts;
  for (const auto& a : arrays) pts.insert(pts.end(), a.begin(), a.end());
  *n_points = static_cast<int>(arrays[0].size());
  return pts;
}

// The OpenCL kernel opens the backend's device only for a cube: SH alone are projected on the host
// (docs/CONVENTIONS.md), and a backend that did nothing else opens no OpenCL platform.
class OpenClIrradiance final : public detail::IrradianceKernel {
 public:
  explicit OpenClIrradiance(Backend& backend) : backend_(backend) {}
  IrradianceResult bake(const EnvImage& env, const IrradianceSpec& spec, const EnvProgress& progress) override {
    if (spec.cube_size == 0) {
      IrradianceResult r;
      r.sh = project_sh(env, spec.sh_order, spec.window);
      if (progress) progress(1.0, "done");
      return r;
    }
    return compute_irradiance(*backend_.device(), env, spec, progress);
  }

 private:
  Backend& backend_;
};

}  // namespace

std::unique_ptr<detail::IrradianceKernel> detail::make_opencl_irradiance(Backend& backend) {
  return std::make_unique<OpenClIrradiance>(backend);
}

IrradianceResult compute_irradiance(Device& device, const EnvImage& env, const IrradianceSpec& spec,
                                    const EnvProgress& progress) {
  detail::check_irradiance_spec(spec);
  IrradianceResult result;
  // The SH on the host (sh_projection.cpp): exact for the input, and no device for SH alone.
  if (progress) progress(0.0, "spherical harmonics");
  result.sh = project_sh(env, spec.sh_order, spec.window);
  const ShCoefficients& sh = result.sh;
  if (spec.cube_size == 0) {
    if (progress) progress(1.0, "done");
    return result;
  }
  auto& dev = device.impl();
  if (progress) progress(0.1, "converting to a cube");
  double seconds = 0.0;
  const CubeLevels cube = environment_to_cube(device, env, spec.source_size, &seconds);

  detail::cl_call("computing the irradiance cube on '" + dev.info.name + "'", [&] {
    detail::ProgramSpec ps;
    ps.file = "irradiance.cl";
    ps.precision = spec.precision;
    ps.defines = {{"BRDFBAKE_SH_ORDER", std::to_string(spec.sh_order)}, {"BRDFBAKE_ENV_COSINE", "1"}};
    cl::Program prog = detail::build_program(dev, ps);
    if (progress) progress(0.4, "irradiance cube");
    int n_points = 0;
    const std::vector<double> pts = irradiance_points(cube, &n_points);
    cl::Buffer pts_buf = detail::env_real_buffer(dev, spec.precision, pts);
    const int cs = spec.cube_size;
    cl::Buffer cube_out(dev.context, CL_MEM_WRITE_ONLY, 4 * face_texels(cs) * sizeof(float));
    cl::KernelFunctor<cl::Buffer, cl_int, cl::Buffer, cl_int> irr(prog, "irradiance_cube");
    // Every texel sums every point: bounded launches of whole rows (runtime/launch.hpp).
    seconds += detail::launch_in_tiles(
        size_t(cs), 6u * size_t(cs), double(n_points), [&](size_t x0, size_t nx, size_t y0, size_t ny) {
          return irr(detail::tile_range(dev.queue, x0, nx, y0, ny), cube_out, cs, pts_buf, n_points);
        });
    result.cube.size = cs;
    result.cube.levels.assign(1, std::vector<float>(4 * face_texels(cs)));
    dev.queue.enqueueReadBuffer(cube_out, CL_TRUE, 0, result.cube.levels[0].size() * sizeof(float),
                                result.cube.levels[0].data());
    return 0;
  });
  result.device_seconds = seconds;

  detail::irradiance_cube_metadata(
      result.cube, env, spec, sh,
      "E(n) / pi = (1 / pi) int L(l) (n.l)+ dl, by direct cosine convolution over every source texel "
      "(the source at face size <= 64, bright texels at full resolution); multiply by the diffuse albedo only",
      precision_name(spec.precision),
      dev.info.name + " (" + dev.info.platform_name + ", " + dev.info.driver_version + ")");
  if (progress) progress(1.0, "done");
  return result;
}

}  // namespace brdfbake
