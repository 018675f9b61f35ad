// The BRDF both renders use, per target (shading.hpp).
#include "families/preview/shading.hpp"

#include <algorithm>
#include <cmath>

#include "brdfbake/dfg_lut.hpp"

namespace brdfbake::detail::preview {

TargetBrdf target_brdf(EngineTarget target, bool multiscatter_table) {
  TargetBrdf b;
  const std::string single =
      "GGX D (Walter et al. 2007) x height-correlated Smith V (Heitz 2014) x Schlick F(v.h) "
      "(F0 = mix(0.04, baseColor, metallic), F90 1), alpha = roughness^2";
  switch (target) {
    case EngineTarget::Generic:
      b.compensation = multiscatter_table;
      b.diffuse = DiffuseWeight::Plain;
      b.text = single + (multiscatter_table ? ", times 1 + F0 (1 / A - 1)" : "") +
               "; plus Lambert: diffuse colour / pi (docs/CONVENTIONS.md's runtime)";
      break;
    case EngineTarget::Filament:
      b.compensation = true;
      b.diffuse = DiffuseWeight::OneMinusE;
      b.text =
          single + ", times 1 + F0 (1 / A - 1); plus Lambert: diffuse colour (1 - E_ss) / pi (Filament's evaluateIBL)";
      break;
    case EngineTarget::Gltf:
    case EngineTarget::Babylon:
      b.compensation = true;
      b.diffuse = DiffuseWeight::Plain;
      b.text = single +
               ", times 1 + F0 (1 / A - 1) (Babylon.js's getEnergyConservationFactor); plus Lambert: "
               "diffuse colour / pi";
      break;
    case EngineTarget::KhronosViewer:
      b.compensation = false;
      b.diffuse = DiffuseWeight::FdezAguera;
      b.text = single +
               "; plus a Lambertian lobe of albedo E_ms F_avg E_ss / (1 - F_avg E_ms) + diffuse colour (1 - E_ss + "
               "that), E_ms = 1 - A, F_avg = F0 + (1 - F0) / 21 (Fdez-Aguera 2019, as the glTF-Sample-Viewer)";
      break;
  }
  b.text += "; A = int D V n.l, E_ss = F0 A + (1 - F0) B, B = int D V (1 - v.h)^5 n.l, exact at each pixel's n.v";
  return b;
}

Rgb reference_radiance(const TargetBrdf& brdf, const PreviewMaterial& m, double albedo, double bias, const double s[9],
                       double n_dot_v, const double* coat, const double* sheen, double sheen_albedo,
                       const double* film_dielectric, const double* film_metal) {
  // F = F0 + (F90 - F0) Fc: the specular radiance F0 S1 + (F90 - F0) S2, its albedo likewise
  const Rgb f0 = preview_f0(m), cd = preview_diffuse_color(m);
  const double F0[3] = {f0.r, f0.g, f0.b}, CD[3] = {cd.r, cd.g, cd.b}, f90 = preview_f90(m);
  double out[3];
  for (int c = 0; c < 3; ++c) {
    double spec = F0[c] * s[c] + (f90 - F0[c]) * s[3 + c];
    if (preview_has_iridescence(m) && (film_dielectric || film_metal)) {
      // KHR_materials_iridescence: the Fresnel mix(F, F_irid(v.h), iridescence) of the dielectric (its
      // specular factor's weight) and of the metal
      const double film = (film_dielectric ? (1.0 - m.metallic) * m.specular * film_dielectric[c] : 0.0) +
                          (film_metal ? m.metallic * film_metal[c] : 0.0);
      spec = (1.0 - m.iridescence) * spec + m.iridescence * film;
    }
    const double ess = F0[c] * albedo + (f90 - F0[c]) * bias;
    const double k = brdf.compensation && albedo > 0.0 ? 1.0 + F0[c] * (1.0 / albedo - 1.0) : 1.0;
    double w = CD[c];
    if (brdf.diffuse == DiffuseWeight::OneMinusE) {
      w = CD[c] * (1.0 - ess);
    } else if (brdf.diffuse == DiffuseWeight::FdezAguera) {
      const double ems = 1.0 - albedo, favg = F0[c] + (f90 - F0[c]) / 21.0;
      const double fms = ems * ess * favg / (1.0 - favg * ems);
      w = fms + CD[c] * (1.0 - ess + fms);
    }
    out[c] = k * spec + w * s[6 + c] / M_PI;
  }
  if (preview_has_sheen(m) && sheen) {
    // KHR_materials_sheen's albedo scaling at n.v: (1 - max(sheenColor) E(n.v)) base + sheen lobe
    const double scale = 1.0 - std::max({m.sheen_color.r, m.sheen_color.g, m.sheen_color.b}) * sheen_albedo;
    const double sc[3] = {m.sheen_color.r, m.sheen_color.g, m.sheen_color.b};
    for (int c = 0; c < 3; ++c) out[c] = scale * out[c] + sc[c] * sheen[c];
  }
  if (m.clearcoat > 0.0 && coat) {
    // KHR_materials_clearcoat's fresnel_coat: mix(base, layer, clearcoat Fcoat(n.v))
    const double t = m.clearcoat * preview_coat_fresnel(n_dot_v);
    for (int c = 0; c < 3; ++c) out[c] = (1.0 - t) * out[c] + t * coat[c];
  }
  return {out[0], out[1], out[2]};
}

namespace {

// A DFG-family table at explicit (n.v, roughness) coordinates (n.v along the width), fp32.
Table table_at(Backend& backend, LutKind kind, const std::vector<double>& n_dot_v, const std::vector<double>& roughness,
               double* device_seconds) {
  LutSpec spec;
  spec.kind = kind;
  spec.width = int(n_dot_v.size());
  spec.height = int(roughness.size());
  spec.n_dot_v = n_dot_v;
  spec.roughness = roughness;
  spec.precision = Precision::Fp32;
  LutTiming timing;
  Table t = bake_lut(backend, spec, &timing);
  if (device_seconds) *device_seconds = timing.device_seconds;
  return t;
}

}  // namespace

std::vector<double> exact_albedos(Backend& backend, const std::vector<double>& n_dot_v,
                                  const std::vector<double>& roughness, double* device_seconds) {
  const Table t = table_at(backend, LutKind::GgxMultiscatter, n_dot_v, roughness, device_seconds);
  std::vector<double> out(2 * n_dot_v.size() * roughness.size());
  for (size_t j = 0; j < roughness.size(); ++j)
    for (size_t i = 0; i < n_dot_v.size(); ++i) {
      const size_t k = j * n_dot_v.size() + i;
      out[2 * k] = t.at(int(i), int(j), 1);      // albedo
      out[2 * k + 1] = t.at(int(i), int(j), 0);  // bias
    }
  return out;
}

double preview_sheen_alpha(double sheen_roughness) { return std::max(sheen_roughness * sheen_roughness, 1e-7); }

std::vector<double> sheen_albedos(Backend& backend, const std::vector<double>& n_dot_v,
                                  const std::vector<double>& sheen_roughness, double* device_seconds) {
  const Table t = table_at(backend, LutKind::Charlie, n_dot_v, sheen_roughness, device_seconds);
  std::vector<double> out(n_dot_v.size() * sheen_roughness.size());
  for (size_t j = 0; j < sheen_roughness.size(); ++j)
    for (size_t i = 0; i < n_dot_v.size(); ++i) out[j * n_dot_v.size() + i] = t.at(int(i), int(j), 0);
  return out;
}

}  // namespace brdfbake::detail::preview
