// Internal: the Fresnel family's model, what its descriptor and its two kernels (opencl.cpp,
// reference.cpp) share: the model table and names (names.cpp), the resolution of a spec into the
// kernels' parameters (resolve.cpp), the table and its metadata (metadata.cpp), and the engine's
// conversions of a conductor's index (conductor.cpp).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "brdfbake/fresnel.hpp"
#include "enum_names.hpp"

namespace brdfbake::detail {

// The table kinds' names (names.cpp's fresnel_table_kind_from_name and _name; the schema offers them).
inline constexpr EnumName<FresnelTableKind> kFresnelTableKindNames[] = {{FresnelTableKind::OneD, "1d"},
                                                                        {FresnelTableKind::TwoD, "2d"}};

// One model: its name, the kernel's compile-time switch and its formula for the metadata.
struct FresnelModelInfo {
  FresnelModel model;
  const char* name;
  const char* define;
  const char* definition;
};
const FresnelModelInfo& fresnel_model_info(FresnelModel model);

// Numbers in messages and metadata: 6 significant digits; a grey colour as one number.
std::string fresnel_number(double v);
std::string fresnel_number(const Rgb& c);
// "a, b and c" (last_sep " and ").
std::string fresnel_join(const std::vector<std::string>& v, const char* last_sep);
// The preset called `name`; throws Error listing the presets otherwise.
const MaterialPreset* find_fresnel_preset(const std::string& name);
inline bool is_grey(const Rgb& c) { return c.r == c.g && c.g == c.b; }
inline double channel_of(const Rgb& c, int i) { return i == 0 ? c.r : i == 1 ? c.g : c.b; }
inline Rgb splat(double v) { return {v, v, v}; }

// The parameters a spec gives, by their command-line names.
std::vector<std::string> fresnel_given_parameters(const FresnelSpec& spec);

// What the kernel and the reference evaluate: the cells, and per channel the model's parameters.
struct Resolved {
  FresnelSpec spec;
  const MaterialPreset* preset = nullptr;
  bool two_d = false;
  int width = 0, height = 1, channels = 3;
  std::vector<double> x, y;
  std::vector<double> params;  // channels x fresnel_parameter_count(model), kernels/fresnel.cl's order
  std::string y_name;          // "f0" | "ior" for 2-D tables
  std::pair<double, double> range{0.0, 0.0};
  std::string parameters;  // for the metadata
};

// Validates a spec (Error with a one-line message) and resolves it: a material preset into the
// model's parameters, the cell coordinates.
Resolved resolve_fresnel(const FresnelSpec& spec);
// The table of a resolved spec with its axes and metadata; the backend fills the data and adds its
// device and precision.
Table make_fresnel_table(const Resolved& resolved);

// Kernel parameters per channel, in kernels/fresnel.cl's order, and which one a 2-D table's y axis
// replaces (kernels/fresnel.cl's FRESNEL_Y_PARAM).
int fresnel_parameter_count(FresnelModel model);
int fresnel_y_parameter(FresnelModel model);

// The engine's conversions of a conductor's (n, k), per channel: the exact normal-incidence
// reflectance (Schlick's F0), and the F82 tint that reproduces the exact conductor at cos = 1/7.
Rgb conductor_f0(const Rgb& n, const Rgb& k);
Rgb fit_f82_tint(const Rgb& n, const Rgb& k);

}  // namespace brdfbake::detail
