// Internal: the irradiance family's model, what its descriptor and its two kernels (opencl.cpp,
// reference.cpp) share: the limits of a spec, the SH coefficients' derived values (sh.cpp) and the
// metadata of an irradiance cube (model.cpp).
#pragma once

#include <string>
#include <vector>

#include "brdfbake/environment.hpp"
#include "enum_names.hpp"

namespace brdfbake::detail {

// The SH windows' names (sh_window.cpp's sh_window_from_name and sh_window_name; the schema offers them).
inline constexpr EnumName<ShWindow> kShWindowNames[] = {
    {ShWindow::None, "none"}, {ShWindow::Hanning, "hanning"}, {ShWindow::Lanczos, "lanczos"}, {ShWindow::Auto, "auto"}};

// Throws Error for an SH order other than 3 or 5, or sizes out of range.
void check_irradiance_spec(const IrradianceSpec& spec);
// The coefficients from the radiance coefficients L_lm (order^2 x RGB): window weights and
// irradiance_over_pi = (A_l / pi) w_l L_lm.
ShCoefficients sh_coefficients(const IrradianceSpec& spec, std::vector<double> radiance);
// The metadata of an irradiance cube.
void irradiance_cube_metadata(CubeLevels& cube, const EnvImage& env, const IrradianceSpec& spec,
                              const ShCoefficients& sh, const std::string& definition, const std::string& precision,
                              const std::string& device);

// The SH's E / pi against the exact irradiance of `env` (sh_error.cpp): the relative RMS of the
// luminance over `directions` directions of a Fibonacci sphere.
struct ShErrorMeasure {
  double relative_rms = 0.0;
  int directions = 0;
};
ShErrorMeasure sh_irradiance_error(const EnvImage& env, const ShCoefficients& sh);
// The SH's radiance coefficients against the converged projection of the same pixels (sh_error.cpp):
// the relative RMS of their luminance; 0 for an equirect (its cells are integrated exactly,
// subdivision 0), a cube's texels split kSub x kSub (subdivision).
struct ShProjectionMeasure {
  double relative_rms = 0.0;
  int subdivision = 0;
};
ShProjectionMeasure sh_projection_error(const EnvImage& env, const ShCoefficients& sh);

}  // namespace brdfbake::detail
