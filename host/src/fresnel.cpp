// Fresnel reflectance tables on the device (kernels/fresnel.cl): names, validation, the resolution of a
// spec into the kernels' parameters (material presets and the engine's own fits), errors and the
// comparison of models. The reference backend (bake_fresnel_reference, fit_conductor) is
// host/src/reference_backend/fresnel.cpp.
#include "brdfbake/fresnel.hpp"

#include <algorithm>
#include <limits>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "brdfbake/error.hpp"
#include "brdfbake/version.hpp"
#include "fresnel_internal.hpp"
#include "runtime/program.hpp"

namespace brdfbake {

using detail::Resolved;

namespace {

// ---- Names ---------------------------------------------------------------------------------------

struct ModelInfo {
  FresnelModel model;
  const char* name;
  const char* define;      // the kernel's compile-time switch
  const char* definition;  // the formula, for the metadata
};
const ModelInfo kModels[] = {
    {FresnelModel::Schlick, "schlick", "BRDFBAKE_FRESNEL_SCHLICK",
     "F = F0 + (F90 - F0)(1 - cos_theta)^5 (Schlick 1994)"},
    {FresnelModel::SchlickMetallic, "schlick-metallic", "BRDFBAKE_FRESNEL_SCHLICK_METALLIC",
     "Schlick with F90 = 1 and F0 = mix(dielectric_f0, base_color, metallic) (Burley 2012; glTF 2.0 "
     "metallic-roughness)"},
    {FresnelModel::SchlickIor, "schlick-ior", "BRDFBAKE_FRESNEL_SCHLICK_IOR",
     "Schlick with F90 = 1 and F0 = ((n1 - n2) / (n1 + n2))^2, n1 = ior_outside, n2 = ior"},
    {FresnelModel::Dielectric, "dielectric", "BRDFBAKE_FRESNEL_DIELECTRIC",
     "exact unpolarised Fresnel equations for a real relative index eta = ior / ior_outside (Born & "
     "Wolf 1.5.2); eta < 1 reflects totally past the critical angle"},
    {FresnelModel::Conductor, "conductor", "BRDFBAKE_FRESNEL_CONDUCTOR",
     "exact unpolarised Fresnel equations for a complex index n + ik seen from air (Born & Wolf 14.2)"},
    {FresnelModel::F82Tint, "f82-tint", "BRDFBAKE_FRESNEL_F82_TINT",
     "Schlick (F90 = 1) minus a cos_theta (1 - cos_theta)^6, a set so that F(1/7) = f82_tint * "
     "Schlick(1/7) (Hoffman 2023; OpenPBR metal)"},
    {FresnelModel::Empirical, "empirical", "BRDFBAKE_FRESNEL_EMPIRICAL",
     "R = clamp(bias + scale (1 - cos_theta)^power, 0, 1) (Fernando & Kilgard 2003, The Cg "
     "Tutorial, eq. 7-3, with I.N = -cos_theta)"},
};

const ModelInfo& info(FresnelModel m) {
  for (const ModelInfo& i : kModels)
    if (i.model == m) return i;
  throw Error("invalid FresnelModel value");
}

// Cells per work-item in kernels/fresnel.cl: kChunks vectors of lanes(precision) cells; 16 lanes
// fill a 512-bit register in fp32 (double16 spills: fp64 keeps 8). See kernels/common/fresnel.clh.
constexpr int kChunks = 8;
int lanes(Precision p) { return p == Precision::Fp64 ? 8 : 16; }

std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

bool grey(const Rgb& c) { return c.r == c.g && c.g == c.b; }

std::string fmt(const Rgb& c) {
  if (grey(c)) return fmt(c.r);
  return "(" + fmt(c.r) + ", " + fmt(c.g) + ", " + fmt(c.b) + ")";
}

double channel(const Rgb& c, int i) { return i == 0 ? c.r : i == 1 ? c.g : c.b; }
Rgb splat(double v) { return {v, v, v}; }

// ---- Validation ---------------------------------------------------------------------------------

// The parameters a spec gives, by their command-line names.
std::vector<std::string> given_parameters(const FresnelSpec& s) {
  std::vector<std::string> g;
  if (s.f0) g.push_back("f0");
  if (s.f90) g.push_back("f90");
  if (s.f82_tint) g.push_back("f82");
  if (s.base_color) g.push_back("base-color");
  if (s.metallic) g.push_back("metallic");
  if (s.dielectric_f0) g.push_back("dielectric-f0");
  if (s.ior) g.push_back("ior");
  if (s.ior_outside) g.push_back("ior-outside");
  if (s.n) g.push_back("n");
  if (s.k) g.push_back("k");
  if (s.bias) g.push_back("bias");
  if (s.scale) g.push_back("scale");
  if (s.power) g.push_back("power");
  return g;
}

std::vector<std::string> model_parameters(FresnelModel m) {
  switch (m) {
    case FresnelModel::Schlick: return {"f0", "f90"};
    case FresnelModel::SchlickMetallic: return {"base-color", "metallic", "dielectric-f0"};
    case FresnelModel::SchlickIor:
    case FresnelModel::Dielectric: return {"ior", "ior-outside"};
    case FresnelModel::Conductor: return {"n", "k"};
    case FresnelModel::F82Tint: return {"f0", "f82"};
    case FresnelModel::Empirical: return {"bias", "scale", "power"};
  }
  return {};
}

std::string join(const std::vector<std::string>& v, const char* last_sep) {
  std::string s;
  for (size_t i = 0; i < v.size(); ++i) {
    if (i > 0) s += i + 1 == v.size() ? last_sep : ", ";
    s += v[i];
  }
  return s;
}

void check_finite(double v, const std::string& what) {
  if (!std::isfinite(v)) throw Error(what + " must be a finite number (got " + fmt(v) + ")");
}
void check_unit(double v, const std::string& what) {
  check_finite(v, what);
  if (v < 0.0 || v > 1.0) throw Error(what + " must be in [0, 1] (got " + fmt(v) + ")");
}
void check_index(double v, const std::string& what, bool zero_allowed) {
  check_finite(v, what);
  if (zero_allowed ? v < 0.0 : v <= 0.0)
    throw Error(what + (zero_allowed ? " must not be negative" : " must be positive") + " (got " +
                fmt(v) + ")");
  if (v > kFresnelMaxIndex)
    throw Error(what + " must be at most " + fmt(kFresnelMaxIndex) + " (got " + fmt(v) + ")");
}
template <class Check>
void check_rgb(const std::optional<Rgb>& c, const std::string& what, Check check) {
  if (!c) return;
  check(c->r, what + (grey(*c) ? "" : " (r)"));
  check(c->g, what + " (g)");
  check(c->b, what + " (b)");
}

std::string material_list() {
  std::vector<std::string> names;
  for (const MaterialPreset& p : material_presets()) names.push_back(p.name);
  return join(names, ", ");
}

const MaterialPreset* find_preset(const std::string& name) {
  const MaterialPreset* p = find_material_preset(name);
  if (!p) throw Error("unknown material '" + name + "' (expected one of " + material_list() + ")");
  return p;
}

// ---- Resolution -----------------------------------------------------------------------------------

std::vector<double> grid(int n, double lo, double hi, bool endpoints) {
  std::vector<double> g(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const double t = endpoints ? static_cast<double>(i) / static_cast<double>(n - 1)
                               : (static_cast<double>(i) + 0.5) / static_cast<double>(n);
    g[static_cast<size_t>(i)] = lo + (hi - lo) * t;
  }
  if (endpoints && n > 1) g.back() = hi;  // exactly
  return g;
}

void check_sizes(const FresnelSpec& s, bool two_d) {
  const bool custom = !s.cos_theta.empty();
  if (!custom) {
    if (s.size < 1) throw Error("size must be at least 1 (got " + std::to_string(s.size) + ")");
    if (s.endpoints && s.size < 2)
      throw Error("endpoints need a size of at least 2 (got " + std::to_string(s.size) + ")");
  }
  for (double c : s.cos_theta) check_finite(c, "cos_theta");
  const long long width = custom ? static_cast<long long>(s.cos_theta.size()) : s.size;
  long long height = 1;
  if (two_d) {
    height = s.height == 0 ? width : s.height;
    if (height < 1) throw Error("height must be at least 1 (got " + std::to_string(height) + ")");
    if (s.endpoints && height < 2)
      throw Error("endpoints need a height of at least 2 (got " + std::to_string(height) + ")");
  } else if (s.height != 0 && s.height != 1) {
    throw Error("height is for 2-D tables (a 1-D table has one row)");
  }
  if (width > kFresnelMaxCells || width * height > kFresnelMaxCells)
    throw Error("the table has too many cells (" + std::to_string(width * height) + ", at most " +
                std::to_string(kFresnelMaxCells) + ")");
}

void check_values(const FresnelSpec& s) {
  check_rgb(s.f0, "f0", check_unit);
  check_rgb(s.f90, "f90", check_unit);
  check_rgb(s.f82_tint, "f82", [](double v, const std::string& w) {
    check_finite(v, w);
    if (v < 0.0) throw Error(w + " must not be negative (got " + fmt(v) + ")");
  });
  check_rgb(s.base_color, "base-color", check_unit);
  if (s.metallic) check_unit(*s.metallic, "metallic");
  if (s.dielectric_f0) check_unit(*s.dielectric_f0, "dielectric-f0");
  check_rgb(s.ior, "ior", [](double v, const std::string& w) { check_index(v, w, false); });
  if (s.ior_outside) check_index(*s.ior_outside, "ior-outside", false);
  check_rgb(s.n, "n", [](double v, const std::string& w) { check_index(v, w, false); });
  check_rgb(s.k, "k", [](double v, const std::string& w) { check_index(v, w, true); });
  if (s.bias) check_finite(*s.bias, "bias");
  if (s.scale) check_finite(*s.scale, "scale");
  if (s.power) {
    check_finite(*s.power, "power");
    if (*s.power < 0.0) throw Error("power must not be negative (got " + fmt(*s.power) + ")");
  }
}

}  // namespace

// ---- The engine's conversions of a conductor's (n, k) --------------------------------------------
// Written here, not taken from the reference: the kernels receive these parameters, and a mistake
// in them must show against the reference's own fit (tests/device/test_fresnel.cpp).

// The exact unpolarised reflectance of a conductor n + ik seen from air at incidence cos c, in real
// arithmetic (Born & Wolf 14.2; the form of Cook & Torrance 1982, appendix): with s^2 = 1 - c^2,
// t0 = n^2 - k^2 - s^2 and a^2 + b^2 = sqrt(t0^2 + 4 n^2 k^2), a = sqrt((a^2 + b^2 + t0) / 2),
//   R_s = (a^2 + b^2 + c^2 - 2 a c) / (a^2 + b^2 + c^2 + 2 a c),
//   R_p = R_s ((a^2 + b^2) c^2 + s^4 - 2 a c s^2) / ((a^2 + b^2) c^2 + s^4 + 2 a c s^2).
namespace {
double conductor_reflectance(double c, double n, double k) {
  const double c2 = c * c, s2 = 1.0 - c2;
  const double t0 = n * n - k * k - s2;
  const double ab2 = std::sqrt(t0 * t0 + 4.0 * n * n * k * k);
  const double a = std::sqrt(std::max(0.0, 0.5 * (ab2 + t0)));
  const double two_ac = 2.0 * a * c;
  const double rs = (ab2 + c2 - two_ac) / (ab2 + c2 + two_ac);
  const double q = ab2 * c2 + s2 * s2, r = two_ac * s2;
  const double rp = rs * (q - r) / (q + r);
  return 0.5 * (rs + rp);
}
}  // namespace

Rgb detail::conductor_f0(const Rgb& n, const Rgb& k) {
  const auto f0 = [](double nn, double kk) {
    const double k2 = kk * kk;
    return ((nn - 1.0) * (nn - 1.0) + k2) / ((nn + 1.0) * (nn + 1.0) + k2);
  };
  return {f0(n.r, k.r), f0(n.g, k.g), f0(n.b, k.b)};
}

// F82(1/7) = tint * Schlick(1/7) = exact(1/7) (Hoffman 2023): tint = exact(1/7) / Schlick(1/7, F0),
// Schlick(1/7) = F0 + (1 - F0)(6/7)^5 >= (6/7)^5 > 0.46, never 0.
Rgb detail::fit_f82_tint(const Rgb& n, const Rgb& k) {
  const Rgb f0 = conductor_f0(n, k);
  const double pin = 1.0 / 7.0, w = std::pow(6.0 / 7.0, 5.0);
  const auto tint = [&](double nn, double kk, double f) {
    return conductor_reflectance(pin, nn, kk) / (f + (1.0 - f) * w);
  };
  return {tint(n.r, k.r, f0.r), tint(n.g, k.g, f0.g), tint(n.b, k.b, f0.b)};
}

int detail::fresnel_parameter_count(FresnelModel m) {
  switch (m) {
    case FresnelModel::SchlickMetallic:
    case FresnelModel::Empirical: return 3;
    default: return 2;
  }
}

int detail::fresnel_y_parameter(FresnelModel m) {
  return m == FresnelModel::SchlickIor || m == FresnelModel::Dielectric ? 1 : 0;
}

Resolved detail::resolve_fresnel(const FresnelSpec& in) {
  Resolved r;
  r.spec = in;
  const FresnelSpec& s = r.spec;
  const FresnelModel m = s.model;
  const std::string model = fresnel_model_name(m);
  r.two_d = s.table == FresnelTableKind::TwoD;

  // Parameters that belong to another model.
  const std::vector<std::string> given = given_parameters(s);
  const std::vector<std::string> own = model_parameters(m);
  for (const std::string& g : given)
    if (std::find(own.begin(), own.end(), g) == own.end())
      throw Error(g + " does not apply to model '" + model + "' (it takes " + join(own, " and ") +
                  (m == FresnelModel::Empirical ? "" : ", or a material") + ")");
  check_values(s);
  check_sizes(s, r.two_d);

  if (!s.material.empty()) {
    r.preset = find_preset(s.material);
    if (!given.empty())
      throw Error("give either a material or the model's parameters, not both (material '" +
                  s.material + "' with " + join(given, " and ") + ")");
    if (m == FresnelModel::Empirical)
      throw Error("model 'empirical' takes bias, scale and power, not a material");
    if ((m == FresnelModel::SchlickIor || m == FresnelModel::Dielectric) &&
        r.preset->kind == MaterialKind::Conductor)
      throw Error("model '" + model + "' takes a real index; '" + s.material +
                  "' is a conductor (use the conductor model)");
    if (r.two_d)
      throw Error("a 2-D table takes its " +
                  std::string(fresnel_y_parameter(m) == 1 ? "ior" : "f0") +
                  " from the y axis; give no material");
  }

  // 2-D: which models have a y axis, and what else they need.
  if (r.two_d) {
    switch (m) {
      case FresnelModel::Schlick:
      case FresnelModel::F82Tint:
        r.y_name = "f0";
        if (s.f0) throw Error("f0 is the y axis of a 2-D " + model + " table; do not give it");
        break;
      case FresnelModel::SchlickIor:
      case FresnelModel::Dielectric:
        r.y_name = "ior";
        if (s.ior) throw Error("ior is the y axis of a 2-D " + model + " table; do not give it");
        break;
      default:
        throw Error("a 2-D table is cos_theta x f0 (schlick, f82-tint) or cos_theta x ior "
                    "(schlick-ior, dielectric); model '" + model + "' has neither");
    }
    if (s.f90 && !grey(*s.f90)) throw Error("a 2-D table has one channel: f90 must be one value");
    if (s.f82_tint && !grey(*s.f82_tint))
      throw Error("a 2-D table has one channel: f82 must be one value");
    r.range = s.range.value_or(r.y_name == "f0" ? std::pair{0.0, 1.0} : std::pair{1.0, 3.0});
    const auto [lo, hi] = r.range;
    check_finite(lo, "range");
    check_finite(hi, "range");
    if (!(lo < hi)) throw Error("range must be increasing (got " + fmt(lo) + ", " + fmt(hi) + ")");
    if (r.y_name == "f0" && (lo < 0.0 || hi > 1.0))
      throw Error("an f0 range must lie in [0, 1] (got " + fmt(lo) + ", " + fmt(hi) + ")");
    if (r.y_name == "ior") {
      check_index(lo, "the ior range's start", false);
      check_index(hi, "the ior range's end", false);
    }
  } else if (s.range) {
    throw Error("range is for 2-D tables (the y axis)");
  }

  // Required parameters (without a material).
  const auto require = [&](bool present, const std::string& what) {
    if (!present && !r.preset)
      throw Error("model '" + model + "' needs " + what +
                  (m == FresnelModel::Empirical ? "" : " (or a material)"));
  };
  switch (m) {
    case FresnelModel::Schlick: require(r.two_d || s.f0.has_value(), "f0"); break;
    case FresnelModel::SchlickMetallic:
      require(s.base_color && s.metallic, "base-color and metallic");
      break;
    case FresnelModel::SchlickIor:
    case FresnelModel::Dielectric: require(r.two_d || s.ior.has_value(), "ior"); break;
    case FresnelModel::Conductor: require(s.n && s.k, "n and k"); break;
    case FresnelModel::F82Tint:
      require((r.two_d || s.f0) && s.f82_tint, r.two_d ? "f82" : "f0 and f82");
      break;
    case FresnelModel::Empirical: require(s.bias && s.scale && s.power, "bias, scale and power"); break;
  }

  // Per-channel parameters in the kernel's order; and the record of them.
  std::vector<Rgb> p;  // one Rgb per kernel parameter
  const MaterialPreset* mat = r.preset;
  const Rgb preset_f0 = mat ? exact_f0(*mat) : Rgb{0, 0, 0};
  switch (m) {
    case FresnelModel::Schlick: {
      const Rgb f0 = mat ? preset_f0 : s.f0.value_or(splat(0.0));
      const Rgb f90 = s.f90.value_or(splat(1.0));
      p = {f0, f90};
      r.parameters = (r.two_d ? "f0 = y axis" : "f0 = " + fmt(f0)) + ", f90 = " + fmt(f90);
      if (mat) r.parameters += " (f0: the exact F0 of " + mat->name + ")";
      break;
    }
    case FresnelModel::SchlickMetallic: {
      Rgb base = mat ? preset_f0 : *s.base_color;
      double metallic = mat ? (mat->kind == MaterialKind::Conductor ? 1.0 : 0.0) : *s.metallic;
      const double d = s.dielectric_f0.value_or(0.04);
      p = {base, splat(metallic), splat(d)};
      r.parameters = "base_color = " + fmt(base) + ", metallic = " + fmt(metallic) +
                     ", dielectric_f0 = " + fmt(d);
      if (mat)
        r.parameters += mat->kind == MaterialKind::Conductor
                            ? " (" + mat->name + ": a metal, base colour = the exact F0)"
                            : " (" + mat->name + ": a dielectric, F0 = the workflow's constant)";
      break;
    }
    case FresnelModel::SchlickIor:
    case FresnelModel::Dielectric: {
      const double outside = s.ior_outside.value_or(1.0);
      const Rgb ior = mat ? mat->n : s.ior.value_or(splat(1.0));
      p = {splat(outside), ior};
      r.parameters = "ior_outside = " + fmt(outside) + ", ior = " + (r.two_d ? "y axis" : fmt(ior));
      if (mat) r.parameters += " (ior: " + mat->name + ")";
      break;
    }
    case FresnelModel::Conductor: {
      const Rgb n = mat ? mat->n : *s.n, k = mat ? mat->k : *s.k;
      p = {n, k};
      r.parameters = "n = " + fmt(n) + ", k = " + fmt(k) + " (seen from air)";
      if (mat) r.parameters += " (" + mat->name + ")";
      break;
    }
    case FresnelModel::F82Tint: {
      const Rgb f0 = mat ? preset_f0 : s.f0.value_or(splat(0.0));
      const Rgb tint = mat ? fit_f82_tint(mat->n, mat->k) : *s.f82_tint;
      p = {f0, tint};
      r.parameters = (r.two_d ? "f0 = y axis" : "f0 = " + fmt(f0)) + ", f82_tint = " + fmt(tint);
      if (mat) r.parameters += " (" + mat->name + ": exact F0, tint fitted at cos = 1/7)";
      break;
    }
    case FresnelModel::Empirical: {
      p = {splat(*s.bias), splat(*s.scale), splat(*s.power)};
      r.parameters = "bias = " + fmt(*s.bias) + ", scale = " + fmt(*s.scale) + ", power = " +
                     fmt(*s.power);
      break;
    }
  }
  r.channels = r.two_d ? 1 : 3;
  for (int c = 0; c < r.channels; ++c)
    for (const Rgb& v : p) r.params.push_back(channel(v, c));

  if (!s.cos_theta.empty()) {
    r.x = s.cos_theta;
  } else {
    r.x = grid(s.size, 0.0, 1.0, s.endpoints);
  }
  r.width = static_cast<int>(r.x.size());
  if (r.two_d) {
    r.height = s.height == 0 ? r.width : s.height;
    r.y = grid(r.height, r.range.first, r.range.second, s.endpoints);
  }
  return r;
}

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
  t.set_meta("definition", info(s.model).definition);
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
               r.y_name + (s.endpoints ? " = lo + (hi - lo) j / (height - 1)"
                                       : " = lo + (hi - lo) (j + 0.5) / height") +
                   ", [lo, hi] = [" + lo + ", " + hi + "]" +
                   (r.y_name == "ior" ? ", linear in the index" : ""));
    t.set_meta("y_range", lo + "," + hi);
    t.set_meta("layout", "row j = 0 (smallest " + r.y_name +
                             ") stored first; sample at uv = (cos_theta, (" + r.y_name +
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
  t.set_meta("conventions", std::string(what) + "cos_theta outside [0, 1] is clamped (docs/CONVENTIONS.md, Fresnel tables)");
  return t;
}

// ---- Errors ------------------------------------------------------------------------------------

namespace {

void check_same_shape(const Table& a, const Table& b) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels ||
      a.data.size() != b.data.size())
    throw Error("Fresnel tables of different shapes cannot be compared (" +
                std::to_string(a.width) + "x" + std::to_string(a.height) + "x" +
                std::to_string(a.channels.size()) + " against " + std::to_string(b.width) + "x" +
                std::to_string(b.height) + "x" + std::to_string(b.channels.size()) + ")");
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

// ---- Public: names ---------------------------------------------------------------------------------

FresnelModel fresnel_model_from_name(const std::string& name) {
  std::vector<std::string> names;
  for (const ModelInfo& i : kModels) {
    if (name == i.name) return i.model;
    names.push_back(i.name);
  }
  throw Error("unknown Fresnel model '" + name + "' (expected " + join(names, " or ") + ")");
}

const char* fresnel_model_name(FresnelModel model) { return info(model).name; }

const std::vector<FresnelModel>& fresnel_models() {
  static const std::vector<FresnelModel> models = [] {
    std::vector<FresnelModel> v;
    for (const ModelInfo& i : kModels) v.push_back(i.model);
    return v;
  }();
  return models;
}

bool fresnel_model_is_exact(FresnelModel model) {
  return model == FresnelModel::Dielectric || model == FresnelModel::Conductor;
}

FresnelTableKind fresnel_table_kind_from_name(const std::string& name) {
  if (name == "1d") return FresnelTableKind::OneD;
  if (name == "2d") return FresnelTableKind::TwoD;
  throw Error("unknown table kind '" + name + "' (expected 1d or 2d)");
}

const char* fresnel_table_kind_name(FresnelTableKind kind) {
  return kind == FresnelTableKind::TwoD ? "2d" : "1d";
}

// ---- Public: specs -----------------------------------------------------------------------------

void validate_fresnel_spec(const FresnelSpec& spec) { (void)detail::resolve_fresnel(spec); }

FresnelSpec exact_fresnel_spec(const FresnelSpec& spec) {
  const Resolved r = detail::resolve_fresnel(spec);
  if (r.two_d) throw Error("the exact model is compared with 1-D tables only");
  FresnelSpec e;
  e.size = spec.size;
  e.endpoints = spec.endpoints;
  e.cos_theta = spec.cos_theta;
  e.precision = spec.precision;
  if (r.preset) {
    e.model = r.preset->kind == MaterialKind::Conductor ? FresnelModel::Conductor
                                                        : FresnelModel::Dielectric;
    e.material = r.preset->name;
    return e;
  }
  switch (spec.model) {
    case FresnelModel::SchlickIor:
    case FresnelModel::Dielectric:
      e.model = FresnelModel::Dielectric;
      e.ior = spec.ior;
      e.ior_outside = spec.ior_outside;
      return e;
    case FresnelModel::Conductor:
      e.model = FresnelModel::Conductor;
      e.n = spec.n;
      e.k = spec.k;
      return e;
    default: break;
  }
  throw Error("model '" + std::string(fresnel_model_name(spec.model)) + "' with " +
              join(given_parameters(spec), " and ") +
              " names no exact model; give a material (or an ior, or n and k)");
}

// ---- Public: baking ---------------------------------------------------------------------------------

Table bake_fresnel(Device& device, const FresnelSpec& spec, FresnelTiming* timing) {
  const auto t0 = std::chrono::steady_clock::now();
  const Resolved r = detail::resolve_fresnel(spec);
  auto& dev = device.impl();

  detail::ProgramSpec ps;
  ps.file = "fresnel.cl";
  ps.precision = spec.precision;
  ps.defines.push_back({info(spec.model).define, "1"});
  ps.defines.push_back({"BRDFBAKE_FRESNEL_CHUNKS", std::to_string(kChunks)});
  ps.defines.push_back({"BRDFBAKE_LANES", std::to_string(lanes(spec.precision))});
  if (r.two_d) ps.defines.push_back({"BRDFBAKE_FRESNEL_2D", "1"});
  cl::Program program = detail::build_program(dev, ps);

  // xs padded to whole work-items (the kernel loads whole vectors; the pad is never stored).
  const size_t cells_per_item = static_cast<size_t>(kChunks * lanes(spec.precision));
  const size_t items = (static_cast<size_t>(r.width) + cells_per_item - 1) / cells_per_item;
  std::vector<double> xs = r.x;
  xs.resize(items * cells_per_item, 1.0);
  std::vector<double> ys = r.two_d ? r.y : std::vector<double>{0.0};

  Table t = detail::make_fresnel_table(r);
  const std::string what = "kernel fresnel_table on '" + dev.info.name + "'";
  const double device_seconds = detail::cl_call(what, [&] {
    auto real_buffer = [&](const std::vector<double>& v, cl_mem_flags flags) {
      if (spec.precision == Precision::Fp64)
        return cl::Buffer(dev.context, flags | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(double),
                          const_cast<double*>(v.data()));
      // Saturated to the float range: a parameter beyond it (--bias 1e308) would be infinite on the
      // device, and inf * 0 is NaN where the double model gives a finite product (issue 24, numbers
      // at the edge); FLT_MAX keeps every product and sum the model clamps to [0, 1] on its side.
      std::vector<float> f(v.size());
      std::transform(v.begin(), v.end(), f.begin(), [](double d) {
        return static_cast<float>(std::clamp(d, -double(std::numeric_limits<float>::max()),
                                             double(std::numeric_limits<float>::max())));
      });
      return cl::Buffer(dev.context, flags | CL_MEM_COPY_HOST_PTR, f.size() * sizeof(float), f.data());
    };
    cl::Buffer xb = real_buffer(xs, CL_MEM_READ_ONLY), yb = real_buffer(ys, CL_MEM_READ_ONLY),
               pb = real_buffer(r.params, CL_MEM_READ_ONLY);
    cl::Buffer out(dev.context, CL_MEM_WRITE_ONLY, t.data.size() * sizeof(float));
    // Make the output resident before the timed kernel: on a CPU device a fresh buffer's pages
    // fault in on first touch, which would be counted as kernel time (measured here: ~24 ms for
    // a 1<<22-cell table, 7x the Schlick kernel itself) and would hide the models' differences.
    dev.queue.enqueueFillBuffer(out, 0.0f, 0, t.data.size() * sizeof(float));
    cl::KernelFunctor<cl::Buffer, cl::Buffer, cl::Buffer, cl_int, cl_int, cl::Buffer> kernel(
        program, "fresnel_table");
    cl::Event event = kernel(cl::EnqueueArgs(dev.queue, cl::NDRange(items, static_cast<size_t>(r.height))),
                             out, xb, yb, r.width, r.height, pb);
    event.wait();
    const double seconds = detail::event_seconds(event);
    dev.queue.enqueueReadBuffer(out, CL_TRUE, 0, t.data.size() * sizeof(float), t.data.data());
    return seconds;
  });

  t.set_meta("device", dev.info.name + " (" + dev.info.platform_name + ", " + dev.info.driver_version + ")");
  t.set_meta("precision", precision_name(spec.precision));
  if (timing) {
    timing->device_seconds = device_seconds;
    timing->wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return t;
}

// ---- Public: errors ----------------------------------------------------------------------------

FresnelError fresnel_error(const Table& approx, const Table& exact) {
  check_same_shape(approx, exact);
  FresnelError e;
  double sum = 0.0;
  const int nc = approx.channel_count();
  for (int j = 0; j < approx.height; ++j)
    for (int i = 0; i < approx.width; ++i)
      for (int c = 0; c < nc; ++c) {
        const double d = std::fabs(static_cast<double>(approx.at(i, j, c)) -
                                   static_cast<double>(exact.at(i, j, c)));
        sum += d;
        if (d > e.max_abs) {
          e.max_abs = d;
          e.x_at_max = static_cast<size_t>(i) < approx.x.size() ? approx.x[static_cast<size_t>(i)] : 0.0;
          e.row_at_max = j;
          e.channel_at_max = c;
        }
      }
  if (!approx.data.empty()) e.mean_abs = sum / static_cast<double>(approx.data.size());
  return e;
}

Table with_error_columns(const Table& table, const Table& exact) {
  check_same_shape(table, exact);
  Table t = table;
  const int nc = table.channel_count();
  for (const std::string& c : table.channels) t.channels.push_back("err_" + c);
  t.data.assign(table.data.size() * 2, 0.f);
  for (int j = 0; j < table.height; ++j)
    for (int i = 0; i < table.width; ++i)
      for (int c = 0; c < nc; ++c) {
        t.at(i, j, c) = table.at(i, j, c);
        // The difference of two floats, formed in double and rounded once.
        t.at(i, j, nc + c) = static_cast<float>(static_cast<double>(table.at(i, j, c)) -
                                                static_cast<double>(exact.at(i, j, c)));
      }
  std::string channels;
  for (const auto& c : t.channels) channels += (channels.empty() ? "" : ",") + c;
  t.set_meta("channels", channels);
  t.set_meta("error_columns",
             "err_<c> = <c> - exact_<c>, signed, where exact is the " + exact.meta("model") +
                 " model (" + exact.meta("parameters") + ") by the scalar double reference at the "
                 "same cos_theta");
  const FresnelError e = fresnel_error(table, exact);
  t.set_meta("error_max_abs", fmt(e.max_abs));
  t.set_meta("error_mean_abs", fmt(e.mean_abs));
  return t;
}

// ---- Public: comparison ------------------------------------------------------------------------

FresnelComparison compare_fresnel_models(const std::string& material, Device* device,
                                         const FresnelCompareOptions& options) {
  const MaterialPreset* preset = find_preset(material);
  if (options.grid < 2) throw Error("the comparison grid needs at least 2 cosines");
  if (options.rate_cells < 0) throw Error("rate cells must not be negative");
  FresnelComparison out;
  out.material = preset->name;
  out.exact_model = preset->kind == MaterialKind::Conductor ? FresnelModel::Conductor
                                                            : FresnelModel::Dielectric;
  out.grid = options.grid;
  out.rate_cells = device ? options.rate_cells : 0;
  if (device && options.rate_cells > 0) out.device = device->info().name;

  FresnelSpec exact_spec;
  exact_spec.model = out.exact_model;
  exact_spec.material = preset->name;
  exact_spec.size = options.grid;
  exact_spec.endpoints = true;
  const Table exact = bake_fresnel_reference(exact_spec);
  const Rgb f0 = exact_f0(*preset);

  for (FresnelModel m : fresnel_models()) {
    if (preset->kind == MaterialKind::Conductor &&
        (m == FresnelModel::SchlickIor || m == FresnelModel::Dielectric))
      continue;  // a real index cannot describe a metal
    FresnelSpec s;
    s.model = m;
    s.size = options.grid;
    s.endpoints = true;
    s.precision = options.precision;
    std::string setting;
    if (m == FresnelModel::Empirical) {
      const double mean_f0 = (f0.r + f0.g + f0.b) / 3.0;
      s.bias = options.bias.value_or(mean_f0);
      s.scale = options.scale.value_or(1.0 - mean_f0);
      s.power = options.power.value_or(5.0);
      setting = !options.bias && !options.scale && !options.power
                    ? "bias = mean exact F0, scale = 1 - bias, power = 5 (grey Schlick)"
                    : "";
    } else {
      s.material = preset->name;
    }
    const Table approx = bake_fresnel_reference(s);
    FresnelModelReport row;
    row.model = m;
    row.setting = approx.meta("parameters");
    if (!setting.empty()) row.setting += " (" + setting + ")";
    double max_c[3] = {0, 0, 0}, sum_c[3] = {0, 0, 0}, x_c[3] = {0, 0, 0};
    for (int i = 0; i < approx.width; ++i)
      for (int c = 0; c < 3; ++c) {
        const double d = std::fabs(static_cast<double>(approx.at(i, 0, c)) -
                                   static_cast<double>(exact.at(i, 0, c)));
        sum_c[c] += d;
        if (d > max_c[c]) {
          max_c[c] = d;
          x_c[c] = approx.x[static_cast<size_t>(i)];
        }
      }
    const double n = static_cast<double>(approx.width);
    row.max_abs = {max_c[0], max_c[1], max_c[2]};
    row.mean_abs = {sum_c[0] / n, sum_c[1] / n, sum_c[2] / n};
    for (int c = 0; c < 3; ++c)
      if (max_c[c] > row.worst) {
        row.worst = max_c[c];
        row.cos_at_worst = x_c[c];
      }

    if (device && options.rate_cells > 0) {
      FresnelSpec rs = s;
      rs.size = options.rate_cells;
      rs.endpoints = false;
      FresnelTiming timing;
      bake_fresnel(*device, rs, &timing);  // warm-up: program build, first touch of the buffers
      std::vector<double> times;
      for (int k = 0; k < std::max(1, options.rate_runs); ++k) {
        bake_fresnel(*device, rs, &timing);
        times.push_back(timing.device_seconds);
      }
      row.device_seconds = median(times);
      row.cells_per_second =
          row.device_seconds > 0 ? static_cast<double>(options.rate_cells) / row.device_seconds : 0.0;
    }
    out.rows.push_back(row);
  }
  return out;
}

// ---- Public: hard-coded F0 values ------------------------------------------------------------

// Hoffman 2010, SIGGRAPH course "Physically-Based Shading Models in Film and Game Production",
// Table 1 (values from Real-Time Rendering, 3rd ed.): the F0 colours many shaders still hard-code.
// Linear values; water and diamond are grey.
namespace {
struct LegacyF0 {
  const char* material;
  Rgb f0;
};
const LegacyF0 kLegacyF0[] = {
    {"gold", {1.00, 0.71, 0.29}},      {"silver", {0.95, 0.93, 0.88}},
    {"copper", {0.95, 0.64, 0.54}},    {"iron", {0.56, 0.57, 0.58}},
    {"aluminium", {0.91, 0.92, 0.92}}, {"water", {0.02, 0.02, 0.02}},
    {"diamond", {0.17, 0.17, 0.17}},
};
constexpr const char* kLegacySource =
    "Hoffman 2010 SIGGRAPH course notes, Table 1 (from Real-Time Rendering 3rd ed.)";
}  // namespace

std::vector<HardCodedF0> hard_coded_f0(const MaterialPreset& preset) {
  std::vector<HardCodedF0> out;
  if (preset.common_f0) out.push_back({*preset.common_f0, preset.common_f0_source});
  for (const LegacyF0& l : kLegacyF0) {
    if (preset.name != l.material) continue;
    const bool same = preset.common_f0 && preset.common_f0->r == l.f0.r &&
                      preset.common_f0->g == l.f0.g && preset.common_f0->b == l.f0.b;
    if (!same) out.push_back({l.f0, kLegacySource});
  }
  return out;
}

}  // namespace brdfbake
