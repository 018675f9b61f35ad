// Thin-film interference Fresnel tables (KHR_materials_iridescence; Belcour & Barla 2017): the
// reflectance of a film over a base, over (cos_theta, film thickness), on an OpenCL device
// (kernels/thin_film.cl) or by the scalar double reference.
#pragma once

#include <optional>

#include "brdfbake/brdf.hpp"
#include "brdfbake/device.hpp"
#include "brdfbake/table.hpp"

namespace brdfbake {

struct ThinFilmSpec {
  double film_ior = 1.3;                                // the film's index (iridescenceIor)
  double outside_ior = 1.0;                             // the medium above the film
  std::optional<double> base_ior;                       // a dielectric base ...
  std::optional<Rgb> base_f0;                           // ... or a base given by its F0 (a metal's colour)
  double thickness_min = 100.0, thickness_max = 400.0;  // nm (iridescenceThicknessMinimum/Maximum)
  int width = 128;                                      // cells along cos_theta
  int height = 0;                                       // cells along the thickness; 0: width, or 1 when min = max
  Precision precision = Precision::Fp32;
};

// Throws Error for what a bake would reject (one of base_ior/base_f0, ranges, sizes); fills height.
ThinFilmSpec resolve_thin_film_spec(const ThinFilmSpec& spec);

struct ThinFilmTiming {
  double device_seconds = 0.0;
  double wall_seconds = 0.0;
};

class Backend;

// Bakes on a backend (brdfbake/backend.hpp): its OpenCL device or the scalar reference.
Table bake_thin_film(Backend& backend, const ThinFilmSpec& spec, ThinFilmTiming* timing = nullptr);
// Bakes on an OpenCL device; the metadata's error_bound is max |table - reference| over every cell,
// measured at bake time.
Table bake_thin_film(Device& device, const ThinFilmSpec& spec, ThinFilmTiming* timing = nullptr);
// The scalar double reference at the same cells.
Table bake_thin_film_reference(const ThinFilmSpec& spec, ThinFilmTiming* timing = nullptr);

}  // namespace brdfbake
