// The reference backend of the thin-film table: every cell by the scalar double reference
// (host/reference/src/thin_film.cpp, Belcour & Barla 2017 as KHR_materials_iridescence evaluates it).
#include "brdfbake/reference/thin_film.hpp"

#include "thin_film.hpp"

namespace brdfbake::detail {

ThinFilmResult bake_thin_film_reference(const ThinFilmRequest& r) {
  check_thin_film_request(r);
  const ThinFilmParams p = thin_film_params(r);
  reference::ThinFilm film;
  film.outside_ior = p.outside_ior;
  film.film_ior = p.film_ior;
  film.base_f0 = p.base_f0;
  Table t = make_thin_film_table(r);
  for (int j = 0; j < r.height; ++j)
    for (int i = 0; i < r.width; ++i) {
      const Rgb v = reference::thin_film_fresnel(t.x[static_cast<size_t>(i)], t.y[static_cast<size_t>(j)], film);
      t.at(i, j, 0) = static_cast<float>(v.r);
      t.at(i, j, 1) = static_cast<float>(v.g);
      t.at(i, j, 2) = static_cast<float>(v.b);
    }
  t.set_meta("device", "reference (scalar double)");
  t.set_meta("precision", "fp64");
  ThinFilmResult result;
  result.table = std::move(t);
  result.error_bound = 0.0;
  result.error_bound_definition = "the scalar double reference itself (stored as float32)";
  return result;
}

}  // namespace brdfbake::detail
