// The reference backend of the thin-film table: every cell by the scalar double reference
// (host/reference/src/thin_film.cpp, Belcour & Barla 2017 as KHR_materials_iridescence evaluates it).
#include <chrono>

#include "brdfbake/reference/thin_film.hpp"
#include "thin_film.hpp"

namespace brdfbake {

Table bake_thin_film_reference(const ThinFilmSpec& in, ThinFilmTiming* timing) {
  const auto t0 = std::chrono::steady_clock::now();
  const ThinFilmSpec r = resolve_thin_film_spec(in);
  const detail::ThinFilmParams p = detail::thin_film_params(r);
  reference::ThinFilm film;
  film.outside_ior = p.outside_ior;
  film.film_ior = p.film_ior;
  film.base_f0 = p.base_f0;
  Table t = detail::make_thin_film_table(r);
  for (int j = 0; j < r.height; ++j)
    for (int i = 0; i < r.width; ++i) {
      const Rgb v = reference::thin_film_fresnel(t.x[static_cast<size_t>(i)], t.y[static_cast<size_t>(j)], film);
      t.at(i, j, 0) = static_cast<float>(v.r);
      t.at(i, j, 1) = static_cast<float>(v.g);
      t.at(i, j, 2) = static_cast<float>(v.b);
    }
  t.set_meta("device", "reference (scalar double)");
  t.set_meta("precision", "fp64");
  if (timing) timing->wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return t;
}

}  // namespace brdfbake
