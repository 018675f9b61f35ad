// Internal: what the device paths (prefilter.cpp, irradiance.cpp) and the reference backend
// (reference_backend/prefilter.cpp, irradiance.cpp) of the environment families share: validation,
// the metadata every output records, the SH coefficients' derived values.
#pragma once

#include <string>
#include <vector>

#include "brdfbake/environment.hpp"

namespace brdfbake::detail {

// "a,b,c".
std::string comma_join(const std::vector<std::string>& items);

// The cube conventions every cubemap output records (faces, orientation, up, equirect mapping).
void cube_conventions_metadata(CubeLevels& cube);
// Where the environment came from (source, description, what --sanitize replaced).
void environment_source_metadata(CubeLevels& cube, const EnvImage& env);

// Biased, opt-in (PrefilterSpec::clamp_luminance): luminance above `limit` compressed to
// limit (1 + log(lum / limit)), RGBA texels.
void clamp_luminance(std::vector<float>& rgba, double limit);
// The metadata of a prefiltered chain common to every estimator: conventions, what a level holds,
// sizes, the roughness schedule and the roughness of each level (roughness.size() levels).
void prefilter_metadata(CubeLevels& out, const PrefilterSpec& spec, const std::vector<double>& roughness);

// Throws Error for an SH order other than 3 or 5, or sizes out of range.
void check_irradiance_spec(const IrradianceSpec& spec);
// The coefficients from the radiance coefficients L_lm (order^2 x RGB): window weights and
// irradiance_over_pi = (A_l / pi) w_l L_lm.
ShCoefficients sh_coefficients(const IrradianceSpec& spec, std::vector<double> radiance);
// The metadata of an irradiance cube.
void irradiance_cube_metadata(CubeLevels& cube, const EnvImage& env, const IrradianceSpec& spec,
                              const ShCoefficients& sh, const std::string& definition, const std::string& precision,
                              const std::string& device);

// The reference's prefiltered radiance (RGB per direction) of a source cube (level 0 of `source`,
// RGBA) at unit directions, one lobe of `roughness` (reference_backend/prefilter.cpp): for
// measurements at probe directions (brdfbake report).
std::vector<double> prefilter_reference_directions(const CubeLevels& source, EnvDistribution distribution,
                                                   double roughness, const std::vector<Vec3>& directions);

}  // namespace brdfbake::detail
