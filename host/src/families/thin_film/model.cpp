// The thin-film family's model: the film as both kernels evaluate it (indices and the base's F0),
// the limits of a spec, and the table with its axes and metadata.
#include "families/thin_film/model.hpp"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "brdfbake/error.hpp"
#include "brdfbake/version.hpp"
#include "text.hpp"

namespace brdfbake {

namespace {

std::vector<double> cos_grid(int n) {
  std::vector<double> x(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) x[static_cast<size_t>(i)] = (i + 0.5) / n;
  return x;
}

std::vector<double> thickness_grid(const ThinFilmSpec& r) {
  std::vector<double> y(static_cast<size_t>(r.height));
  for (int j = 0; j < r.height; ++j)
    y[static_cast<size_t>(j)] =
        r.height == 1 ? r.thickness_min : r.thickness_min + (r.thickness_max - r.thickness_min) * (j + 0.5) / r.height;
  return y;
}

}  // namespace

detail::ThinFilmParams detail::thin_film_params(const ThinFilmSpec& r) {
  ThinFilmParams f;
  f.outside_ior = r.outside_ior;
  f.film_ior = r.film_ior;
  if (r.base_ior) {
    // the base's normal-incidence reflectance from air, ((n - 1) / (n + 1))^2
    const double q = (*r.base_ior - 1.0) / (*r.base_ior + 1.0), f0 = q * q;
    f.base_f0 = {f0, f0, f0};
  } else if (r.base_f0) {
    f.base_f0 = *r.base_f0;
  }
  return f;
}

Table detail::make_thin_film_table(const ThinFilmSpec& r) {
  const ThinFilmParams f = thin_film_params(r);
  Table t;
  t.width = r.width;
  t.height = r.height;
  t.channels = {"r", "g", "b"};
  t.x_name = "cos_theta";
  t.y_name = "thickness_nm";
  t.x = cos_grid(r.width);
  t.y = thickness_grid(r);
  t.data.assign(static_cast<size_t>(t.width) * static_cast<size_t>(t.height) * 3, 0.f);
  t.set_meta("generator", std::string("brdfbake ") + kVersion);
  t.set_meta("kind", "thin-film");
  t.set_meta("definition",
             "thin-film interference Fresnel, Belcour & Barla 2017, as the KHR_materials_iridescence specification "
             "evaluates it: Schlick amplitudes at both interfaces, unpolarised, Airy series to m = 2, spectral "
             "integral in Fourier space against Gaussian fits of the CIE 1931 matching functions, linear Rec. 709, "
             "clamped at 0");
  t.set_meta("film_ior", detail::fmt_number(r.film_ior));
  t.set_meta("outside_ior", detail::fmt_number(r.outside_ior));
  if (r.base_ior) t.set_meta("base_ior", detail::fmt_number(*r.base_ior));
  t.set_meta("base_f0", detail::fmt_number(f.base_f0.r) + "," + detail::fmt_number(f.base_f0.g) + "," +
                            detail::fmt_number(f.base_f0.b));
  t.set_meta("width", std::to_string(t.width));
  t.set_meta("height", std::to_string(t.height));
  t.set_meta("channels", "r,g,b");
  t.set_meta("x_axis", "cos_theta = (i + 0.5) / width, the cell centre of column i (incidence from outside)");
  t.set_meta("y_axis", r.height == 1
                           ? "thickness_nm = " + detail::fmt_number(r.thickness_min) + " (one row)"
                           : "thickness_nm = min + (max - min) (j + 0.5) / height, min " +
                                 detail::fmt_number(r.thickness_min) + ", max " + detail::fmt_number(r.thickness_max));
  t.set_meta("layout",
             "row j = 0 (thinnest film) stored first; sample at uv = (cos_theta, (thickness - min) / (max - min))");
  return t;
}

ThinFilmSpec resolve_thin_film_spec(const ThinFilmSpec& in) {
  ThinFilmSpec r = in;
  auto finite = [](double v) { return std::isfinite(v); };
  if (r.height == 0) r.height = r.thickness_max == r.thickness_min ? 1 : r.width;
  if (r.width < 1 || r.height < 1) throw Error("thin-film: size and height must be at least 1");
  if (static_cast<long long>(r.width) * r.height > (1ll << 24))
    throw Error("thin-film: at most 16777216 cells (got " + std::to_string(r.width) + "x" + std::to_string(r.height) +
                ")");
  if (!finite(r.film_ior) || r.film_ior < 1.0) throw Error("thin-film: film_ior must be at least 1");
  if (!finite(r.outside_ior) || r.outside_ior < 1.0) throw Error("thin-film: outside_ior must be at least 1");
  if (r.base_ior.has_value() == r.base_f0.has_value())
    throw Error("thin-film: give exactly one of base_ior and base_f0");
  if (!finite(r.thickness_min) || !finite(r.thickness_max) || r.thickness_min < 0 || r.thickness_max < r.thickness_min)
    throw Error("thin-film: thickness_min <= thickness_max, both >= 0");
  if (r.thickness_max == r.thickness_min && r.height != 1)
    throw Error("thin-film: height must be 1 when thickness_min = thickness_max (one thickness)");
  return r;
}

}  // namespace brdfbake
