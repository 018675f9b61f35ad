// Internal: what the irradiance family's device path (irradiance.cpp) and reference backend
// (reference_backend/irradiance.cpp) share: validation, the SH coefficients' derived values, the
// cube's metadata. (The environment families' shared engine is env/cube.hpp.)
#pragma once

#include <string>
#include <vector>

#include "brdfbake/environment.hpp"

namespace brdfbake::detail {

// Throws Error for an SH order other than 3 or 5, or sizes out of range.
void check_irradiance_spec(const IrradianceSpec& spec);
// The coefficients from the radiance coefficients L_lm (order^2 x RGB): window weights and
// irradiance_over_pi = (A_l / pi) w_l L_lm.
ShCoefficients sh_coefficients(const IrradianceSpec& spec, std::vector<double> radiance);
// The metadata of an irradiance cube.
void irradiance_cube_metadata(CubeLevels& cube, const EnvImage& env, const IrradianceSpec& spec,
                              const ShCoefficients& sh, const std::string& definition, const std::string& precision,
                              const std::string& device);

}  // namespace brdfbake::detail
