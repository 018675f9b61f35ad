// Diffuse irradiance on the reference backend: compute_irradiance_reference, the SH coefficients and
// the irradiance cube by the brute-force double reference (host/reference/src/irradiance.cpp,
// sh_project and irradiance_directions), and the family's reference kernel (kernel.hpp).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/reference/envmap.hpp"
#include "env/reference_cube.hpp"
#include "families/irradiance/kernel.hpp"
#include "families/irradiance/model.hpp"
#include "text.hpp"

namespace brdfbake {
namespace {

// The sub-cells per source texel side of the reference's SH and cosine sums (envmap.hpp: q =
// ceil(128 / size)).
int cosine_subdivision(int source_size) { return std::max(1, (128 + source_size - 1) / source_size); }

class ReferenceIrradiance final : public detail::IrradianceKernel {
 public:
  IrradianceResult bake(const EnvImage& env, const IrradianceSpec& spec, const EnvProgress& progress) override {
    return compute_irradiance_reference(env, spec, progress);
  }
};

}  // namespace

std::unique_ptr<detail::IrradianceKernel> detail::make_reference_irradiance() {
  return std::make_unique<ReferenceIrradiance>();
}

IrradianceResult compute_irradiance_reference(const EnvImage& env, const IrradianceSpec& spec,
                                              const EnvProgress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  detail::check_irradiance_spec(spec);
  const int s = spec.source_size, q = cosine_subdivision(s);
  if (s > kIrradianceReferenceMaxSourceSize)
    throw Error("the scalar reference computes irradiance from sources up to " +
                std::to_string(kIrradianceReferenceMaxSourceSize) + " texels a side (asked for " + std::to_string(s) +
                "): use an OpenCL device (--device), or a smaller source size");
  const double cells = 6.0 * s * s * q * q;
  const double work = 6.0 * spec.cube_size * spec.cube_size * cells;
  if (work > kIrradianceReferenceMaxWork)
    throw Error("the scalar reference would evaluate " + detail::fmt_number(work, "%.3g") +
                " cosine terms for an irradiance cube of " + std::to_string(spec.cube_size) + " from a source of " +
                std::to_string(s) + ", above its limit of " + detail::fmt_number(kIrradianceReferenceMaxWork, "%.3g") +
                " (a few seconds): use an OpenCL device (--device), or a smaller cube or source size");

  if (progress) progress(0.0, "converting to a cube");
  const reference::EnvCube source =
      detail::to_reference_cube(detail::to_rgba(detail::reference_source_cube(env, s)), s);
  IrradianceResult result;
  if (progress) progress(0.1, "spherical harmonics");
  result.sh = detail::sh_coefficients(spec, reference::sh_project(source, spec.sh_order, q));
  result.sh.projection = "the scalar double reference: the source converted to a " + std::to_string(s) +
                         "^2 cube by brute force, every texel split into sub-cells with exact solid angles";
  if (spec.cube_size > 0) {
    if (progress) progress(0.4, "irradiance cube");
    const int cs = spec.cube_size;
    std::vector<Vec3> normals;
    for (int f = 0; f < 6; ++f)
      for (int j = 0; j < cs; ++j)
        for (int i = 0; i < cs; ++i) normals.push_back(math::cube_texel_direction(f, cs, i, j));
    const std::vector<double> e = reference::irradiance_directions(source, normals, q);
    reference::EnvCube cube;
    cube.size = cs;
    cube.rgb = e;
    result.cube.size = cs;
    result.cube.levels.assign(1, detail::to_rgba(cube));
    detail::irradiance_cube_metadata(
        result.cube, env, spec, result.sh,
        "E(n) / pi = (1 / pi) int L(l) (n.l)+ dl, by brute force in double (the scalar reference): every source "
        "texel split into " +
            std::to_string(q) + " x " + std::to_string(q) +
            " sub-cells of exact solid angle, the source's seamless bilinear interpolation at each; multiply by "
            "the diffuse albedo only",
        "fp64", "reference (scalar double)");
  }
  if (progress) progress(1.0, "done");
  result.device_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace brdfbake
