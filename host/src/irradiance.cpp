// Diffuse irradiance: spherical harmonics projected on the host (sh_projection.cpp), and an
// irradiance cube by direct cosine convolution on the device (kernels/irradiance.cl).
//
// Conventions (docs/CONVENTIONS.md): real SH without the Condon-Shortley phase, index l (l + 1) + m;
// "radiance" holds L_lm = int L Y_lm dl; "irradiance_over_pi" holds c_lm = (A_l / pi) w_l L_lm with
// Ramamoorthi & Hanrahan's A_l and the window w_l, so that E(n) / pi = sum c_lm Y_lm(n): a shader
// multiplies by the albedo only. The cube's texels hold E / pi too.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/math/sh.hpp"
#include "brdfbake/version.hpp"
#include "io/atomic_file.hpp"
#include "env_internal.hpp"
#include "io/json_input.hpp"
#include "runtime/launch.hpp"
#include "runtime/program.hpp"

namespace brdfbake {
namespace {

using math::kPi;
constexpr int kMaxPointSource = 64;  // the rest is summed at this face size or below
constexpr int kBrightSplit = 2;      // sub-cells per texel side of a bright texel's footprint

size_t face_texels(int size) { return 6u * static_cast<size_t>(size) * static_cast<size_t>(size); }

cl::Buffer real_buffer(Device::Impl& dev, Precision p, const std::vector<double>& v) {
  if (p == Precision::Fp64)
    return cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(double),
                      const_cast<double*>(v.data()));
  std::vector<float> f(v.size());
  for (size_t k = 0; k < v.size(); ++k) f[k] = static_cast<float>(v[k]);
  return cl::Buffer(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, f.size() * sizeof(float), f.data());
}

// The rest of the cube (bright texels removed) reduced by solid-angle-weighted 2x2 means to a face
// size of at most kMaxPointSource (or until the size is odd), as points (direction, L Omega).
void rest_points(const CubeLevels& cube, const std::vector<BrightTexel>& bright, std::vector<double> (&arrays)[6]) {
  int s = cube.size;
  std::vector<double> rgb(3 * face_texels(s));
  for (size_t t = 0; t < face_texels(s); ++t)
    for (size_t c = 0; c < 3; ++c) rgb[3 * t + c] = cube.levels[0][4 * t + c];
  for (const BrightTexel& b : bright)
    for (size_t c = 0; c < 3; ++c) rgb[3 * ((size_t(b.face) * size_t(s) + size_t(b.j)) * size_t(s) + size_t(b.i)) + c] = 0.0;
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

std::string fmt(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

}  // namespace

void detail::check_irradiance_spec(const IrradianceSpec& spec) {
  if (spec.sh_order != 3 && spec.sh_order != 5)
    throw Error("SH order must be 3 (9 coefficients) or 5 (25), not " + std::to_string(spec.sh_order));
  if (spec.cube_size < 0 || spec.cube_size > kIrradianceMaxCube)
    throw Error("irradiance cube size must be in 1.." + std::to_string(kIrradianceMaxCube) + " (or 0 for none), not " +
                std::to_string(spec.cube_size));
  if (spec.source_size < 1 || spec.source_size > kIrradianceMaxSource)
    throw Error("irradiance source size must be in 1.." + std::to_string(kIrradianceMaxSource) + ", not " +
                std::to_string(spec.source_size));
}

ShCoefficients detail::sh_coefficients(const IrradianceSpec& spec, std::vector<double> radiance) {
  ShCoefficients sh;
  sh.order = spec.sh_order;
  sh.radiance = std::move(radiance);
  apply_sh_window(sh, spec.window);
  return sh;
}

void detail::irradiance_cube_metadata(CubeLevels& c, const EnvImage& env, const IrradianceSpec& spec,
                                      const ShCoefficients& sh, const std::string& definition,
                                      const std::string& precision, const std::string& device) {
  c.set_meta("generator", std::string("brdfbake ") + kVersion);
  c.set_meta("kind", "irradiance");
  c.set_meta("definition", definition);
  c.set_meta("faces", "+X,-X,+Y,-Y,+Z,-Z (KTX / OpenGL cube map order), OpenGL face orientation, +Y up");
  c.set_meta("source", env.source);
  c.set_meta("source_size", std::to_string(spec.source_size));
  std::string coeffs;
  for (double v : sh.irradiance_over_pi) coeffs += (coeffs.empty() ? "" : ",") + fmt(v);
  c.set_meta("sh_order", std::to_string(sh.order));
  c.set_meta("sh_irradiance_over_pi", coeffs);
  if (!sh.projection.empty()) c.set_meta("sh_projection", sh.projection);
  c.set_meta("sh_convention",
             "real SH without Condon-Shortley phase, index l(l+1)+m, RGB per coefficient; E(n)/pi = sum c Y(n)");
  c.set_meta("precision", precision);
  c.set_meta("device", device);
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
  const int s = cube.size;

  detail::cl_call("computing the irradiance cube on '" + dev.info.name + "'", [&] {
    detail::ProgramSpec ps;
    ps.file = "irradiance.cl";
    ps.precision = spec.precision;
    ps.defines = {{"BRDFBAKE_SH_ORDER", std::to_string(spec.sh_order)}, {"BRDFBAKE_ENV_COSINE", "1"}};
    cl::Program prog = detail::build_program(dev, ps);
    if (progress) progress(0.4, "irradiance cube");
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
    const int n_points = static_cast<int>(arrays[0].size());
    cl::Buffer pts_buf = real_buffer(dev, spec.precision, pts);
    const int cs = spec.cube_size;
    cl::Buffer cube_out(dev.context, CL_MEM_WRITE_ONLY, 4 * face_texels(cs) * sizeof(float));
    cl::KernelFunctor<cl::Buffer, cl_int, cl::Buffer, cl_int> irr(prog, "irradiance_cube");
    // Every texel sums every point: bounded launches of whole rows (runtime/launch.hpp).
    seconds += detail::launch_in_tiles(size_t(cs), 6u * size_t(cs), double(n_points),
                                       [&](size_t x0, size_t nx, size_t y0, size_t ny) {
                                         return irr(detail::tile_range(dev.queue, x0, nx, y0, ny), cube_out, cs,
                                                    pts_buf, n_points);
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
      precision_name(spec.precision), dev.info.name + " (" + dev.info.platform_name + ", " + dev.info.driver_version + ")");
  if (progress) progress(1.0, "done");
  return result;
}

std::string sh_to_json(const ShCoefficients& sh, const Metadata& metadata) {
  // JSON has no NaN or infinity (nlohmann would write null): refuse rather than write garbage.
  for (const auto* v : {&sh.radiance, &sh.irradiance_over_pi})
    for (double x : *v)
      if (!std::isfinite(x))
        throw RuntimeFailure("the SH coefficients are not finite (the environment's radiance overflowed); nothing was written");
  nlohmann::ordered_json j;
  j["generator"] = std::string("brdfbake ") + kVersion;
  j["order"] = sh.order;
  j["coefficients"] = sh.order * sh.order;
  j["basis"] =
      "real spherical harmonics without the Condon-Shortley phase (Ramamoorthi & Hanrahan 2001), index "
      "k = l (l + 1) + m, of the unit direction (x, y, z) with +Y up (docs/CONVENTIONS.md): Y00 = 0.282095, "
      "Y1-1 = 0.488603 y, Y10 = 0.488603 z, Y11 = 0.488603 x, Y2-2 = 1.092548 xy, Y2-1 = 1.092548 yz, "
      "Y20 = 0.315392 (3z^2 - 1), Y21 = 1.092548 xz, Y22 = 0.546274 (x^2 - y^2), ...";
  j["radiance_definition"] = "L_lm = int L(l) Y_lm(l) dl";
  if (!sh.projection.empty()) j["projection"] = sh.projection;
  j["irradiance_definition"] =
      "c_lm = (A_l / pi) w_l L_lm, A = (pi, 2pi/3, pi/4, 0, -pi/24) (Ramamoorthi & Hanrahan 2001), so that "
      "E(n) / pi = sum_lm c_lm Y_lm(n): irradiance DIVIDED BY PI, multiply by the albedo only";
  j["window"] = sh_window_name(sh.window);
  j["window_weights"] = sh.window_weights;
  if (sh.window == ShWindow::Auto) j["window_cutoff"] = sh.window_cutoff;
  auto triples = [](const std::vector<double>& v) {
    nlohmann::ordered_json a = nlohmann::ordered_json::array();
    for (size_t k = 0; k + 2 < v.size(); k += 3) a.push_back({v[k], v[k + 1], v[k + 2]});
    return a;
  };
  j["irradiance_over_pi"] = triples(sh.irradiance_over_pi);
  j["radiance"] = triples(sh.radiance);
  nlohmann::ordered_json meta = nlohmann::ordered_json::object();
  for (const auto& [k, v] : metadata) meta[k] = v;
  j["metadata"] = meta;
  return io::json_text(j) + "\n";
}

void write_sh_json(const ShCoefficients& sh, const Metadata& metadata, const std::string& path) {
  io::write_file_atomically(path, sh_to_json(sh, metadata));
}

}  // namespace brdfbake
