// The irradiance family's model: the limits of a spec and the metadata of an irradiance cube.
#include "families/irradiance/model.hpp"

#include <cstdio>
#include <string>

#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/version.hpp"
#include "text.hpp"

namespace brdfbake {

namespace {}  // namespace

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
  for (double v : sh.irradiance_over_pi) coeffs += (coeffs.empty() ? "" : ",") + detail::fmt_number(v);
  c.set_meta("sh_order", std::to_string(sh.order));
  c.set_meta("sh_irradiance_over_pi", coeffs);
  if (!sh.projection.empty()) c.set_meta("sh_projection", sh.projection);
  c.set_meta("sh_convention",
             "real SH without Condon-Shortley phase, index l(l+1)+m, RGB per coefficient; E(n)/pi = sum c Y(n)");
  c.set_meta("precision", precision);
  c.set_meta("device", device);
}

}  // namespace brdfbake
