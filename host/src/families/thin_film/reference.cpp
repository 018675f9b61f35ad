// The thin-film table on the reference backend: every cell by the scalar double reference
// (host/reference/src/thin_film.cpp, Belcour & Barla 2017 as KHR_materials_iridescence evaluates
// it), and the family's reference kernel (kernel.hpp).
#include <chrono>

#include "brdfbake/reference/thin_film.hpp"
#include "families/thin_film/kernel.hpp"
#include "families/thin_film/model.hpp"

namespace brdfbake {

namespace {

class ReferenceThinFilm final : public detail::ThinFilmKernel {
 public:
  Table bake(const ThinFilmSpec& spec, ThinFilmTiming* timing) override {
    return bake_thin_film_reference(spec, timing);
  }
};

}  // namespace

std::unique_ptr<detail::ThinFilmKernel> detail::make_reference_thin_film() {
  return std::make_unique<ReferenceThinFilm>();
}

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
