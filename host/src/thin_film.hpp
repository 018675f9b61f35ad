// Internal: the thin-film interference Fresnel table (KHR_materials_iridescence; Belcour & Barla
// 2017), as the job runner reaches it. Builds without the module report it as not available.
#pragma once

#include <optional>
#include <string>

#include "brdfbake/device.hpp"
#include "brdfbake/reference/fresnel.hpp"
#include "brdfbake/table.hpp"

namespace brdfbake::detail {

struct ThinFilmRequest {
  double film_ior = 1.3;     // the film's index (iridescenceIor)
  double outside_ior = 1.0;  // the medium above the film
  std::optional<double> base_ior;          // a dielectric base ...
  std::optional<reference::Rgb> base_f0;   // ... or a base given by its F0 (a metal's colour)
  double thickness_min = 100.0, thickness_max = 400.0;  // nm
  int width = 128;           // cells along cos_theta
  int height = 128;          // cells along the thickness
  Precision precision = Precision::Fp32;
};

struct ThinFilmResult {
  Table table;
  std::optional<double> error_bound;
  std::string error_bound_definition;
};

bool thin_film_available();
// device == nullptr: the scalar double reference.
ThinFilmResult bake_thin_film_adapter(Device* device, const ThinFilmRequest& request);

}  // namespace brdfbake::detail
