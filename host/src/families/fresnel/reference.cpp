// The Fresnel tables on the reference backend: bake_fresnel_reference (every cell by the scalar
// double reference, host/reference/src/fresnel.cpp), the family's reference kernel, and
// fit_conductor (the engine's fits, measured against the reference's exact conductor).
#include <algorithm>
#include <chrono>
#include <vector>

#include "brdfbake/error.hpp"
#include "brdfbake/fresnel.hpp"
#include "brdfbake/reference/fresnel.hpp"
#include "families/fresnel/kernel.hpp"
#include "families/fresnel/model.hpp"

namespace brdfbake {
namespace {

using detail::splat;
double channel(const Rgb& c, int i) { return detail::channel_of(c, i); }

// One channel of one cell by the scalar double reference, parameters in the kernel's order.
double reference_value(FresnelModel m, const double* p, double c) {
  switch (m) {
    case FresnelModel::Schlick:
      return reference::fresnel_schlick(c, p[0], p[1]);
    case FresnelModel::SchlickMetallic:
      return reference::fresnel_schlick(c, reference::schlick_metallic_f0(splat(p[0]), p[1], p[2]).r);
    case FresnelModel::SchlickIor:
      return reference::fresnel_schlick(c, reference::f0_from_ior(p[0], p[1]));
    case FresnelModel::Dielectric:
      return reference::fresnel_dielectric(c, p[1] / p[0]);
    case FresnelModel::Conductor:
      return reference::fresnel_conductor(c, p[0], p[1]);
    case FresnelModel::F82Tint:
      return reference::fresnel_f82_tint(c, p[0], p[1]);
    case FresnelModel::Empirical:
      return reference::fresnel_empirical(c, p[0], p[1], p[2]);
  }
  return 0.0;
}

class ReferenceFresnel final : public detail::FresnelKernel {
 public:
  Table bake(const FresnelSpec& spec, FresnelTiming* timing) override { return bake_fresnel_reference(spec, timing); }
};

}  // namespace

std::unique_ptr<detail::FresnelKernel> detail::make_reference_fresnel() { return std::make_unique<ReferenceFresnel>(); }

Table bake_fresnel_reference(const FresnelSpec& spec, FresnelTiming* timing) {
  const auto t0 = std::chrono::steady_clock::now();
  const detail::Resolved r = detail::resolve_fresnel(spec);
  Table t = detail::make_fresnel_table(r);
  const int np = detail::fresnel_parameter_count(spec.model);
  std::vector<double> p(static_cast<size_t>(np));
  for (int j = 0; j < r.height; ++j) {
    for (int c = 0; c < r.channels; ++c) {
      std::copy_n(r.params.begin() + static_cast<std::ptrdiff_t>(c * np), np, p.begin());
      if (r.two_d) p[static_cast<size_t>(detail::fresnel_y_parameter(spec.model))] = r.y[static_cast<size_t>(j)];
      for (int i = 0; i < r.width; ++i)
        t.at(i, j, c) = static_cast<float>(reference_value(spec.model, p.data(), r.x[static_cast<size_t>(i)]));
    }
  }
  t.set_meta("device", "reference (scalar double)");
  t.set_meta("precision", "fp64");
  if (timing) {
    timing->wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    timing->device_seconds = timing->wall_seconds;
  }
  return t;
}

ConductorFit fit_conductor(const Rgb& n, const Rgb& k) {
  FresnelSpec check;
  check.model = FresnelModel::Conductor;
  check.n = n;
  check.k = k;
  validate_fresnel_spec(check);
  ConductorFit fit;
  // The parameters a table of this conductor would ship (the engine's fits) ...
  fit.f0 = detail::conductor_f0(n, k);
  fit.f82_tint = detail::fit_f82_tint(n, k);
  // ... and what each approximation leaves against the reference's exact conductor.
  double schlick[3], f82[3];
  for (int c = 0; c < 3; ++c) {
    const double nc = channel(n, c), kc = channel(k, c), f0c = channel(fit.f0, c), tc = channel(fit.f82_tint, c);
    const auto exact = [&](double x) { return reference::fresnel_conductor(x, nc, kc); };
    schlick[c] = reference::fresnel_fit_error([&](double x) { return reference::fresnel_schlick(x, f0c); }, exact,
                                              kFresnelErrorGrid)
                     .max_abs;
    f82[c] = reference::fresnel_fit_error([&](double x) { return reference::fresnel_f82_tint(x, f0c, tc); }, exact,
                                          kFresnelErrorGrid)
                 .max_abs;
  }
  fit.schlick_max_error = {schlick[0], schlick[1], schlick[2]};
  fit.f82_max_error = {f82[0], f82[1], f82[2]};
  return fit;
}

}  // namespace brdfbake
