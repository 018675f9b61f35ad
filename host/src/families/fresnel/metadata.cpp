// The Fresnel table of a resolved spec: its axes, channels and the metadata every Fresnel table
// carries (model, definition, parameters, material, layout, conventions); a kernel fills the values.
#include <string>
#include <vector>

#include "brdfbake/version.hpp"
#include "families/fresnel/model.hpp"

namespace brdfbake {

using detail::Resolved;

namespace {

std::string fmt(double v) { return detail::fresnel_number(v); }
std::string fmt(const Rgb& c) { return detail::fresnel_number(c); }

}  // namespace

Table detail::make_fresnel_table(const Resolved& r) {
  const FresnelSpec& s = r.spec;
  Table t;
  t.width = r.width;
  t.height = r.height;
  t.channels = r.two_d ? std::vector<std::string>{"f"} : std::vector<std::string>{"r", "g", "b"};
  t.x_name = "cos_theta";
  t.y_name = r.y_name;
  t.x = r.x;
  t.y = r.y;
  t.data.assign(static_cast<size_t>(t.width) * static_cast<size_t>(t.height) * t.channels.size(), 0.f);
  t.set_meta("generator", std::string("brdfbake ") + kVersion);
  t.set_meta("model", fresnel_model_name(s.model));
  t.set_meta("definition", fresnel_model_info(s.model).definition);
  t.set_meta("parameters", r.parameters);
  if (r.preset) {
    t.set_meta("material", r.preset->name);
    t.set_meta("material_n", fmt(r.preset->n));
    t.set_meta("material_k", fmt(r.preset->k));
    t.set_meta("material_source", r.preset->nk_source);
    t.set_meta("material_wavelengths_nm", fmt(kPresetWavelengthsNm));
  } else {
    t.set_meta("material", "none");
  }
  t.set_meta("table", fresnel_table_kind_name(s.table));
  t.set_meta("width", std::to_string(t.width));
  t.set_meta("height", std::to_string(t.height));
  std::string channels;
  for (const auto& c : t.channels) channels += (channels.empty() ? "" : ",") + c;
  t.set_meta("channels", channels);
  if (!s.cos_theta.empty()) {
    t.set_meta("x_axis", "cos_theta at explicit points (the x column)");
  } else {
    t.set_meta("x_axis", s.endpoints ? "cos_theta = i / (width - 1): 0 and 1 are cells"
                                     : "cos_theta = (i + 0.5) / width, the cell centre of column i");
  }
  if (r.two_d) {
    const std::string lo = fmt(r.range.first), hi = fmt(r.range.second);
    t.set_meta("y_axis",
               r.y_name +
                   (s.endpoints ? " = lo + (hi - lo) j / (height - 1)" : " = lo + (hi - lo) (j + 0.5) / height") +
                   ", [lo, hi] = [" + lo + ", " + hi + "]" + (r.y_name == "ior" ? ", linear in the index" : ""));
    t.set_meta("y_range", lo + "," + hi);
    t.set_meta("layout", "row j = 0 (smallest " + r.y_name + ") stored first; sample at uv = (cos_theta, (" + r.y_name +
                             " - lo) / (hi - lo)) with the same cell rule");
  } else {
    t.set_meta("layout", "one row; sample at u = cos_theta with the same cell rule");
  }
  // The conventions of what the model computes: eta only where an index of refraction enters.
  const char* what = "";
  switch (s.model) {
    case FresnelModel::Dielectric:
    case FresnelModel::Conductor:
    case FresnelModel::SchlickIor:
      what = "unpolarised reflectance (mean of s and p); eta = n_t / n_i; ";
      break;
    case FresnelModel::Schlick:
    case FresnelModel::SchlickMetallic:
    case FresnelModel::F82Tint:
      what = "an approximation of unpolarised reflectance from its value at normal incidence; ";
      break;
    case FresnelModel::Empirical:
      what = "an empirical rim term, not a solution of the Fresnel equations; ";
      break;
  }
  t.set_meta("conventions",
             std::string(what) + "cos_theta outside [0, 1] is clamped (docs/CONVENTIONS.md, Fresnel tables)");
  return t;
}

}  // namespace brdfbake
