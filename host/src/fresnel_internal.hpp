// Internal: what the device path (fresnel.cpp) and the reference backend
// (reference_backend/fresnel.cpp) of the Fresnel tables share.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "brdfbake/fresnel.hpp"

namespace brdfbake::detail {

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
  std::string parameters;      // for the metadata
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
