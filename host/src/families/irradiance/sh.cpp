// The irradiance family's spherical harmonics: the irradiance coefficients from the radiance ones
// (windowed by sh_window.cpp), and their JSON file.
//
// Conventions (docs/CONVENTIONS.md): real SH without the Condon-Shortley phase, index l (l + 1) + m;
// "radiance" holds L_lm = int L Y_lm dl; "irradiance_over_pi" holds c_lm = (A_l / pi) w_l L_lm with
// Ramamoorthi & Hanrahan's A_l and the window w_l, so that E(n) / pi = sum c_lm Y_lm(n): a shader
// multiplies by the albedo only.
#include "brdfbake/math/sh.hpp"

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/version.hpp"
#include "families/irradiance/model.hpp"
#include "io/atomic_file.hpp"
#include "io/json_input.hpp"

namespace brdfbake {

using math::kPi;

ShCoefficients detail::sh_coefficients(const IrradianceSpec& spec, std::vector<double> radiance) {
  ShCoefficients sh;
  sh.order = spec.sh_order;
  sh.radiance = std::move(radiance);
  apply_sh_window(sh, spec.window);  // the window's names and weights: sh_window.cpp
  return sh;
}

std::string sh_to_json(const ShCoefficients& sh, const Metadata& metadata) {
  // JSON has no NaN or infinity (nlohmann would write null): refuse rather than write garbage.
  for (const auto* v : {&sh.radiance, &sh.irradiance_over_pi})
    for (double x : *v)
      if (!std::isfinite(x))
        throw RuntimeFailure(
            "the SH coefficients are not finite (the environment's radiance overflowed); nothing was written");
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
