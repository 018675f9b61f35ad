// The Fresnel family's specs: validation (every parameter belongs to its model, values and sizes in
// range, a material or the model's own parameters) and the resolution of a spec into what the
// kernels evaluate: the cells and, per channel, the model's parameters (material presets and the
// engine's own fits included).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "brdfbake/error.hpp"
#include "families/fresnel/model.hpp"

namespace brdfbake {

using detail::channel_of;
using detail::Resolved;
using detail::splat;

namespace {

std::string fmt(double v) { return detail::fresnel_number(v); }
std::string fmt(const Rgb& c) { return detail::fresnel_number(c); }
bool grey(const Rgb& c) { return detail::is_grey(c); }

// The parameters a spec gives, by their command-line names.
}  // namespace

std::vector<std::string> detail::fresnel_given_parameters(const FresnelSpec& s) {
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

namespace {

std::vector<std::string> model_parameters(FresnelModel m) {
  switch (m) {
    case FresnelModel::Schlick:
      return {"f0", "f90"};
    case FresnelModel::SchlickMetallic:
      return {"base-color", "metallic", "dielectric-f0"};
    case FresnelModel::SchlickIor:
    case FresnelModel::Dielectric:
      return {"ior", "ior-outside"};
    case FresnelModel::Conductor:
      return {"n", "k"};
    case FresnelModel::F82Tint:
      return {"f0", "f82"};
    case FresnelModel::Empirical:
      return {"bias", "scale", "power"};
  }
  return {};
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
    throw Error(what + (zero_allowed ? " must not be negative" : " must be positive") + " (got " + fmt(v) + ")");
  if (v > kFresnelMaxIndex) throw Error(what + " must be at most " + fmt(kFresnelMaxIndex) + " (got " + fmt(v) + ")");
}
template <class Check>
void check_rgb(const std::optional<Rgb>& c, const std::string& what, Check check) {
  if (!c) return;
  check(c->r, what + (grey(*c) ? "" : " (r)"));
  check(c->g, what + " (g)");
  check(c->b, what + " (b)");
}

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

// Parameters that belong to another model, values, sizes, and a material with what it excludes.
void check_parameters(Resolved& r) {
  const FresnelSpec& s = r.spec;
  const FresnelModel m = s.model;
  const std::string model = fresnel_model_name(m);
  const std::vector<std::string> given = detail::fresnel_given_parameters(s);
  const std::vector<std::string> own = model_parameters(m);
  for (const std::string& g : given)
    if (std::find(own.begin(), own.end(), g) == own.end())
      throw Error(g + " does not apply to model '" + model + "' (it takes " + detail::fresnel_join(own, " and ") +
                  (m == FresnelModel::Empirical ? "" : ", or a material") + ")");
  check_values(s);
  check_sizes(s, r.two_d);
  if (s.material.empty()) return;
  r.preset = detail::find_fresnel_preset(s.material);
  if (!given.empty())
    throw Error("give either a material or the model's parameters, not both (material '" + s.material + "' with " +
                detail::fresnel_join(given, " and ") + ")");
  if (m == FresnelModel::Empirical) throw Error("model 'empirical' takes bias, scale and power, not a material");
  if ((m == FresnelModel::SchlickIor || m == FresnelModel::Dielectric) && r.preset->kind == MaterialKind::Conductor)
    throw Error("model '" + model + "' takes a real index; '" + s.material +
                "' is a conductor (use the conductor model)");
  if (r.two_d)
    throw Error("a 2-D table takes its " + std::string(detail::fresnel_y_parameter(m) == 1 ? "ior" : "f0") +
                " from the y axis; give no material");
}

// 2-D: which models have a y axis, what else they need, and the y range.
void resolve_y_axis(Resolved& r) {
  const FresnelSpec& s = r.spec;
  const std::string model = fresnel_model_name(s.model);
  if (!r.two_d) {
    if (s.range) throw Error("range is for 2-D tables (the y axis)");
    return;
  }
  switch (s.model) {
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
      throw Error(
          "a 2-D table is cos_theta x f0 (schlick, f82-tint) or cos_theta x ior "
          "(schlick-ior, dielectric); model '" +
          model + "' has neither");
  }
  if (s.f90 && !detail::is_grey(*s.f90)) throw Error("a 2-D table has one channel: f90 must be one value");
  if (s.f82_tint && !detail::is_grey(*s.f82_tint)) throw Error("a 2-D table has one channel: f82 must be one value");
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
}

// The parameters a model needs when no material gives them.
void check_required(const Resolved& r) {
  const FresnelSpec& s = r.spec;
  const FresnelModel m = s.model;
  const auto require = [&](bool present, const std::string& what) {
    if (!present && !r.preset)
      throw Error("model '" + std::string(fresnel_model_name(m)) + "' needs " + what +
                  (m == FresnelModel::Empirical ? "" : " (or a material)"));
  };
  switch (m) {
    case FresnelModel::Schlick:
      require(r.two_d || s.f0.has_value(), "f0");
      break;
    case FresnelModel::SchlickMetallic:
      require(s.base_color && s.metallic, "base-color and metallic");
      break;
    case FresnelModel::SchlickIor:
    case FresnelModel::Dielectric:
      require(r.two_d || s.ior.has_value(), "ior");
      break;
    case FresnelModel::Conductor:
      require(s.n && s.k, "n and k");
      break;
    case FresnelModel::F82Tint:
      require((r.two_d || s.f0) && s.f82_tint, r.two_d ? "f82" : "f0 and f82");
      break;
    case FresnelModel::Empirical:
      require(s.bias && s.scale && s.power, "bias, scale and power");
      break;
  }
}

// One Rgb per kernel parameter, in kernels/fresnel.cl's order, from the spec or its material; and
// the record of them (r.parameters).
std::vector<Rgb> kernel_parameters(Resolved& r) {
  const FresnelSpec& s = r.spec;
  const MaterialPreset* mat = r.preset;
  const Rgb preset_f0 = mat ? exact_f0(*mat) : Rgb{0, 0, 0};
  switch (s.model) {
    case FresnelModel::Schlick: {
      const Rgb f0 = mat ? preset_f0 : s.f0.value_or(splat(0.0));
      const Rgb f90 = s.f90.value_or(splat(1.0));
      r.parameters = (r.two_d ? "f0 = y axis" : "f0 = " + fmt(f0)) + ", f90 = " + fmt(f90);
      if (mat) r.parameters += " (f0: the exact F0 of " + mat->name + ")";
      return {f0, f90};
    }
    case FresnelModel::SchlickMetallic: {
      Rgb base = mat ? preset_f0 : *s.base_color;
      double metallic = mat ? (mat->kind == MaterialKind::Conductor ? 1.0 : 0.0) : *s.metallic;
      const double d = s.dielectric_f0.value_or(0.04);
      r.parameters = "base_color = " + fmt(base) + ", metallic = " + fmt(metallic) + ", dielectric_f0 = " + fmt(d);
      if (mat)
        r.parameters += mat->kind == MaterialKind::Conductor
                            ? " (" + mat->name + ": a metal, base colour = the exact F0)"
                            : " (" + mat->name + ": a dielectric, F0 = the workflow's constant)";
      return {base, splat(metallic), splat(d)};
    }
    case FresnelModel::SchlickIor:
    case FresnelModel::Dielectric: {
      const double outside = s.ior_outside.value_or(1.0);
      const Rgb ior = mat ? mat->n : s.ior.value_or(splat(1.0));
      r.parameters = "ior_outside = " + fmt(outside) + ", ior = " + (r.two_d ? "y axis" : fmt(ior));
      if (mat) r.parameters += " (ior: " + mat->name + ")";
      return {splat(outside), ior};
    }
    case FresnelModel::Conductor: {
      const Rgb n = mat ? mat->n : *s.n, k = mat ? mat->k : *s.k;
      r.parameters = "n = " + fmt(n) + ", k = " + fmt(k) + " (seen from air)";
      if (mat) r.parameters += " (" + mat->name + ")";
      return {n, k};
    }
    case FresnelModel::F82Tint: {
      const Rgb f0 = mat ? preset_f0 : s.f0.value_or(splat(0.0));
      const Rgb tint = mat ? detail::fit_f82_tint(mat->n, mat->k) : *s.f82_tint;
      r.parameters = (r.two_d ? "f0 = y axis" : "f0 = " + fmt(f0)) + ", f82_tint = " + fmt(tint);
      if (mat) r.parameters += " (" + mat->name + ": exact F0, tint fitted at cos = 1/7)";
      return {f0, tint};
    }
    case FresnelModel::Empirical:
      r.parameters = "bias = " + fmt(*s.bias) + ", scale = " + fmt(*s.scale) + ", power = " + fmt(*s.power);
      return {splat(*s.bias), splat(*s.scale), splat(*s.power)};
  }
  return {};
}

}  // namespace

int detail::fresnel_parameter_count(FresnelModel m) {
  switch (m) {
    case FresnelModel::SchlickMetallic:
    case FresnelModel::Empirical:
      return 3;
    default:
      return 2;
  }
}

int detail::fresnel_y_parameter(FresnelModel m) {
  return m == FresnelModel::SchlickIor || m == FresnelModel::Dielectric ? 1 : 0;
}

Resolved detail::resolve_fresnel(const FresnelSpec& in) {
  Resolved r;
  r.spec = in;
  const FresnelSpec& s = r.spec;
  r.two_d = s.table == FresnelTableKind::TwoD;
  check_parameters(r);
  resolve_y_axis(r);
  check_required(r);
  const std::vector<Rgb> p = kernel_parameters(r);
  r.channels = r.two_d ? 1 : 3;
  for (int c = 0; c < r.channels; ++c)
    for (const Rgb& v : p) r.params.push_back(channel_of(v, c));

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
    e.model = r.preset->kind == MaterialKind::Conductor ? FresnelModel::Conductor : FresnelModel::Dielectric;
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
    default:
      break;
  }
  throw Error("model '" + std::string(fresnel_model_name(spec.model)) + "' with " +
              detail::fresnel_join(detail::fresnel_given_parameters(spec), " and ") +
              " names no exact model; give a material (or an ior, or n and k)");
}

}  // namespace brdfbake
