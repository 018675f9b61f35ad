// Internal: the thin-film interference Fresnel table (KHR_materials_iridescence; Belcour & Barla
// 2017), as the job runner reaches it. Builds without the module report it as not available.
#pragma once

#include <optional>
#include <string>

#include "brdfbake/device.hpp"
#include "brdfbake/math/types.hpp"
#include "brdfbake/table.hpp"

namespace brdfbake::detail {

struct ThinFilmRequest {
  double film_ior = 1.3;     // the film's index (iridescenceIor)
  double outside_ior = 1.0;  // the medium above the film
  std::optional<double> base_ior;          // a dielectric base ...
  std::optional<Rgb> base_f0;              // ... or a base given by its F0 (a metal's colour)
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
// device == nullptr: the scalar double reference (bake_thin_film_reference); else the device, with
// its error bound measured against the reference.
ThinFilmResult bake_thin_film_adapter(Device* device, const ThinFilmRequest& request);

// ---- Shared by the device path (thin_film.cpp) and the reference backend
// (reference_backend/thin_film.cpp) ---------------------------------------------------------------

// The film as both evaluate it: indices and the base's F0 seen from air (a dielectric base_ior n
// becomes ((n - 1) / (n + 1))^2).
struct ThinFilmParams {
  double outside_ior = 1.0;
  double film_ior = 1.3;
  Rgb base_f0{0.04, 0.04, 0.04};
};
// Throws Error with a one-line message for a request the bake would reject.
void check_thin_film_request(const ThinFilmRequest& request);
ThinFilmParams thin_film_params(const ThinFilmRequest& request);
// The table of a checked request: axes and metadata, data zero.
Table make_thin_film_table(const ThinFilmRequest& request);

// The scalar double reference of a checked request (host/reference/src/thin_film.cpp), stored as
// float, with its metadata.
ThinFilmResult bake_thin_film_reference(const ThinFilmRequest& request);

}  // namespace brdfbake::detail
