// The DFG tables' model: the names of kinds, estimators, axes and visibilities, the resolution of
// a spec (defaults, limits, the sample count a max_error needs) and the table a resolved spec makes,
// with the metadata every DFG table carries whatever its backend.
#include "families/dfg_lut/model.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "brdfbake/error.hpp"
#include "brdfbake/version.hpp"
#include "text.hpp"

namespace brdfbake {

namespace {

constexpr long long kMaxTexels = kLutMaxTexels;

bool has_custom_points(const LutSpec& in) { return !in.n_dot_v.empty() || !in.roughness.empty(); }

}  // namespace

Table detail::make_lut_table(const LutSpec& s) {
  Table t;
  t.width = static_cast<int>(s.n_dot_v.size());
  t.height = static_cast<int>(s.roughness.size());
  t.channels = lut_channels(s.kind);
  t.x_name = "n_dot_v";
  t.y_name = s.kind == LutKind::Charlie ? "sheen_roughness" : "roughness";
  t.x = s.n_dot_v;
  t.y = s.roughness;
  t.data.assign(static_cast<size_t>(t.width) * static_cast<size_t>(t.height) * t.channels.size(), 0.f);
  t.set_meta("generator", std::string("brdfbake ") + kVersion);
  t.set_meta("kind", lut_kind_name(s.kind));
  t.set_meta("width", std::to_string(t.width));
  t.set_meta("height", std::to_string(t.height));
  std::string channels;
  for (const auto& c : t.channels) channels += (channels.empty() ? "" : ",") + c;
  t.set_meta("channels", channels);
  const std::string rough = s.kind == LutKind::Charlie ? "sheen_roughness" : "roughness";
  const bool sx = s.n_dot_v_axis == LutAxis::Sqrt, sy = s.roughness_axis == LutAxis::Sqrt;
  t.set_meta("x_axis", std::string("n_dot_v = ") + (sx ? "((i + 0.5) / width)^2" : "(i + 0.5) / width") +
                           ", at the cell centre of column i");
  t.set_meta("y_axis", rough + " = " + (sy ? "((j + 0.5) / height)^2" : "(j + 0.5) / height") +
                           ", perceptual, at the cell centre of row j; alpha = " + rough + "^2");
  t.set_meta("n_dot_v_axis", lut_axis_name(s.n_dot_v_axis));
  t.set_meta("roughness_axis", lut_axis_name(s.roughness_axis));
  t.set_meta("layout", "row j = 0 (smallest roughness) stored first; sample at uv = (" +
                           std::string(sx ? "sqrt(n_dot_v)" : "n_dot_v") + ", " + (sy ? "sqrt(" + rough + ")" : rough) +
                           ")");
  t.set_meta("lookup", std::string("uv = (") + (sx ? "sqrt(n_dot_v)" : "n_dot_v") + ", " +
                           (sy ? "sqrt(" + rough + ")" : rough) + "), bilinear, clamp to edge");
  switch (s.kind) {
    case LutKind::Ggx:
      t.set_meta("definition",
                 "scale = int (1 - Fc) D V n.l dl, bias = int Fc D V n.l dl, Fc = (1 - v.h)^5, GGX D, "
                 "height-correlated Smith V (Heitz 2014); specular = F0 * scale + F90 * bias; "
                 "diffuse = int f_Burley n.l dl (Burley 2012, F_D90 = 0.5 + 2 roughness (l.h)^2)");
      break;
    case LutKind::GgxMultiscatter:
      t.set_meta("definition",
                 "bias = int Fc D V n.l dl, albedo = int D V n.l dl (= scale + bias), GGX with "
                 "height-correlated Smith V; diffuse = Burley 2012 directional albedo");
      t.set_meta("runtime",
                 "specular = mix(bias, albedo, F0) * (1 + F0 * (1 / albedo - 1)) (Kulla & Conty 2017 "
                 "energy compensation, Filament's formulation)");
      break;
    case LutKind::Charlie:
      t.set_meta("definition", "albedo = int D_Charlie V n.l dl (Estevez & Kulla 2017), sheen colour 1");
      t.set_meta("sheen_visibility", sheen_visibility_name(s.sheen_visibility));
      break;
  }
  return t;
}

LutKind lut_kind_from_name(const std::string& n) {
  return detail::enum_from_name(detail::kLutKindNames, n, "table kind");
}
const char* lut_kind_name(LutKind k) { return detail::enum_name(detail::kLutKindNames, k); }
Estimator estimator_from_name(const std::string& n) {
  return detail::enum_from_name(detail::kEstimatorNames, n, "estimator");
}
const char* estimator_name(Estimator e) { return detail::enum_name(detail::kEstimatorNames, e); }
SheenVisibility sheen_visibility_from_name(const std::string& n) {
  return detail::enum_from_name(detail::kSheenVisibilityNames, n, "sheen visibility");
}
const char* sheen_visibility_name(SheenVisibility v) { return detail::enum_name(detail::kSheenVisibilityNames, v); }
LutAxis lut_axis_from_name(const std::string& n) { return detail::enum_from_name(detail::kLutAxisNames, n, "axis"); }
const char* lut_axis_name(LutAxis a) { return detail::enum_name(detail::kLutAxisNames, a); }
double lut_axis_uv(LutAxis a, double x) { return a == LutAxis::Sqrt ? std::sqrt(std::max(0.0, x)) : x; }
double lut_axis_value(LutAxis a, double uv) { return a == LutAxis::Sqrt ? uv * uv : uv; }

std::vector<std::string> lut_channels(LutKind kind) {
  switch (kind) {
    case LutKind::Ggx:
      return {"scale", "bias", "diffuse"};
    case LutKind::GgxMultiscatter:
      return {"bias", "albedo", "diffuse"};
    case LutKind::Charlie:
      break;
  }
  return {"albedo"};
}

LutSpec resolve_lut_spec(const LutSpec& in) {
  LutSpec s = in;
  if (has_custom_points(s)) {
    if (s.n_dot_v.empty() || s.roughness.empty())
      throw Error("explicit table points need both n_dot_v and roughness values");
    for (double v : s.n_dot_v)
      if (!std::isfinite(v)) throw Error("n_dot_v must be finite");
    for (double v : s.roughness)
      if (!std::isfinite(v)) throw Error("roughness must be finite");
    s.width = static_cast<int>(s.n_dot_v.size());
    s.height = static_cast<int>(s.roughness.size());
  } else {
    if (s.height == 0) s.height = s.width;
    if (s.width < 1 || s.height < 1)
      throw Error("table size must be at least 1x1 (got " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                  ")");
    if (s.width > kLutMaxSize || s.height > kLutMaxSize)
      throw Error("table size must be at most " + std::to_string(kLutMaxSize) + " per side");
  }
  if (static_cast<long long>(s.width) * s.height > kMaxTexels)
    throw Error("table has too many texels (at most " + std::to_string(kMaxTexels) + ")");
  if (s.samples < 0) throw Error("samples must be positive (got " + std::to_string(s.samples) + ")");
  if (s.estimator == Estimator::Quadrature && s.samples > kLutMaxQuadratureSamples)
    throw Error("the quadrature takes at most " + std::to_string(kLutMaxQuadratureSamples) +
                " evaluations per texel (got " + std::to_string(s.samples) + "; its error is below 1e-7 long before)");
  if (s.samples > kLutMaxSamples)
    throw Error("samples must be at most " + std::to_string(kLutMaxSamples) + " (got " + std::to_string(s.samples) +
                ")");
  if (std::isnan(s.max_error) || s.max_error < 0.0) throw Error("max-error must be a positive number");
  const bool ggx = s.kind != LutKind::Charlie;
  if (ggx && s.estimator == Estimator::Uniform) throw Error("estimator 'uniform' is for the charlie table only");
  if (!ggx && s.estimator == Estimator::Vndf)
    throw Error("estimator 'vndf' samples GGX visible normals; the charlie table takes quadrature, ndf or uniform");
  if (s.max_error > 0.0) {
    if (s.samples > 0) throw Error("give either samples or max-error, not both");
    double best_error = -1.0;
    const int best = detail::lut_samples_for(s, &best_error);
    if (best == 0)
      throw Error("no calibrated sample count of estimator '" + std::string(estimator_name(s.estimator)) +
                  "' reaches max-error " + detail::fmt_number(s.max_error, "%.3g") + " for " + lut_kind_name(s.kind) +
                  (best_error > 0 ? " (the best measured is " + detail::fmt_number(best_error, "%.3g") + ")" : ""));
    s.samples = best;
  }
  if (s.samples == 0) s.samples = detail::default_lut_samples(s.kind, s.estimator, s.precision);
  if (!has_custom_points(s)) {
    s.n_dot_v.resize(static_cast<size_t>(s.width));
    s.roughness.resize(static_cast<size_t>(s.height));
    for (int i = 0; i < s.width; ++i)
      s.n_dot_v[static_cast<size_t>(i)] = lut_axis_value(s.n_dot_v_axis, (i + 0.5) / s.width);
    for (int j = 0; j < s.height; ++j)
      s.roughness[static_cast<size_t>(j)] = lut_axis_value(s.roughness_axis, (j + 0.5) / s.height);
  }
  return s;
}

}  // namespace brdfbake
