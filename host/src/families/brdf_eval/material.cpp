// The materials' parameter blocks (kernels/common/brdf_params.clh): everything per material (tints,
// Fresnel indices, widths, normalisations) derived here in double, once, from the parameters as the
// papers define them (cited in kernels/brdf_eval.cl), by the engine's own code; and the narrowest
// lobe of a material, where the albedo quadrature starts.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>

#include "brdfbake/brdf.hpp"
#include "brdfbake/math/conventions.hpp"
#include "families/brdf_eval/model.hpp"
#include "families/brdf_eval/sheen_albedo.hpp"

// The parameter block layout, shared with the kernels.
#include "../../../../kernels/common/brdf_params.clh"

namespace brdfbake {
namespace {

using detail::max3;
using detail::mix;
using math::kDisneyMinAlpha;
using math::kMinAlpha;
using math::kPi;

using Block = std::array<double, BRDF_PARAM_STRIDE>;

void put(Block& b, int slot, const Rgb& c) {
  b[static_cast<size_t>(slot)] = c.r;
  b[static_cast<size_t>(slot) + 1] = c.g;
  b[static_cast<size_t>(slot) + 2] = c.b;
}
void put(Block& b, int slot, double v) { b[static_cast<size_t>(slot)] = v; }
Rgb scale(const Rgb& c, double s) { return {c.r * s, c.g * s, c.b * s}; }

// The classic models' parameter conventions (docs/CONVENTIONS.md): kd = diffuse_color, else
// base_color (1 - metallic); ks = specular_color, else mix(0.04, base_color, metallic) (the
// metallic-roughness F0); n = shininess, else 2048^(1 - roughness) (blinn-phong-from-pbr's mapping).
Rgb classic_kd(const Material& m) { return m.diffuse_color ? *m.diffuse_color : scale(m.base_color, 1.0 - m.metallic); }
Rgb classic_ks(const Material& m) {
  if (m.specular_color) return *m.specular_color;
  const Rgb& c = m.base_color;
  return {mix(0.04, c.r, m.metallic), mix(0.04, c.g, m.metallic), mix(0.04, c.b, m.metallic)};
}
double classic_exponent(const Material& m) { return m.shininess ? *m.shininess : std::pow(2048.0, 1.0 - m.roughness); }

// disney.brdf's parameters (Burley 2012).
Block pack_disney(const Material& m) {
  Block b{};
  const double r2 = m.roughness * m.roughness;
  // disney.brdf: Ctint = C / lum(C) (1 when lum = 0), Cspec0 = mix(0.08 specular mix(1, Ctint,
  // specularTint), C, metallic), Csheen = mix(1, Ctint, sheenTint).
  const Rgb c = m.base_color;
  const double lum = 0.3 * c.r + 0.6 * c.g + 0.1 * c.b;
  const Rgb tint = lum > 0.0 ? scale(c, 1.0 / lum) : Rgb{1.0, 1.0, 1.0};
  auto tinted = [&](double t) { return Rgb{mix(1.0, tint.r, t), mix(1.0, tint.g, t), mix(1.0, tint.b, t)}; };
  const Rgb s = scale(tinted(m.specular_tint), 0.08 * m.specular);
  put(b, BRDF_DISNEY_KD, scale(c, (1.0 - m.metallic) / kPi));
  put(b, BRDF_DISNEY_SPEC0, Rgb{mix(s.r, c.r, m.metallic), mix(s.g, c.g, m.metallic), mix(s.b, c.b, m.metallic)});
  put(b, BRDF_DISNEY_SHEEN, scale(tinted(m.sheen_tint), m.sheen * (1.0 - m.metallic)));
  put(b, BRDF_DISNEY_ROUGHNESS, m.roughness);
  put(b, BRDF_DISNEY_SUBSURFACE, m.subsurface);
  const double aspect = std::sqrt(1.0 - 0.9 * m.anisotropic);
  const double ax = std::max(kDisneyMinAlpha, r2 / aspect);
  const double ay = std::max(kDisneyMinAlpha, r2 * aspect);
  put(b, BRDF_DISNEY_AX, ax);
  put(b, BRDF_DISNEY_AY, ay);
  put(b, BRDF_DISNEY_D_NORM, 1.0 / (kPi * ax * ay));
  // GTR1 at a = mix(0.1, 0.001, clearcoatGloss): (a^2 - 1) / (pi ln a^2)
  const double a = mix(0.1, 0.001, m.clearcoat_gloss), a2 = a * a;
  put(b, BRDF_DISNEY_COAT, 0.25 * m.clearcoat);
  put(b, BRDF_DISNEY_COAT_A2, a2);
  put(b, BRDF_DISNEY_COAT_NORM, (a2 - 1.0) / (kPi * std::log(a2)));
  return b;
}

// glTF 2.0 with KHR_materials_ior, _specular, _sheen and _clearcoat.
Block pack_gltf(const Material& m, double sheen_table_offset) {
  Block b{};
  const double r2 = m.roughness * m.roughness;
  const Rgb c = m.base_color;
  // fresnel_mix with KHR_materials_ior and _specular: f0 = min(((1 - ior)/(1 + ior))^2 f0_color, 1)
  const double q = (1.0 - m.ior) / (1.0 + m.ior), f0_ior = q * q;
  const Rgb f0{std::min(f0_ior * m.specular_color_factor.r, 1.0), std::min(f0_ior * m.specular_color_factor.g, 1.0),
               std::min(f0_ior * m.specular_color_factor.b, 1.0)};
  put(b, BRDF_GLTF_KD, scale(c, (1.0 - m.metallic) / kPi));
  put(b, BRDF_GLTF_F0, f0);
  put(b, BRDF_GLTF_METAL_F0, c);
  put(b, BRDF_GLTF_WEIGHT, m.specular_factor);
  put(b, BRDF_GLTF_DIELECTRIC, (1.0 - m.metallic) * m.specular_factor);
  put(b, BRDF_GLTF_METALLIC, m.metallic);
  const double alpha = std::max(r2, kMinAlpha);
  put(b, BRDF_GLTF_A2, alpha * alpha);
  const double alpha_s = m.sheen_roughness * m.sheen_roughness;
  const double inv_a = 1.0 / std::max(alpha_s, kMinAlpha);
  put(b, BRDF_GLTF_SHEEN, m.sheen_color);
  put(b, BRDF_GLTF_SHEEN_MAX, max3(m.sheen_color));
  put(b, BRDF_GLTF_SHEEN_INV_A, inv_a);
  put(b, BRDF_GLTF_SHEEN_NORM, (2.0 + inv_a) / (2.0 * kPi));
  const detail::EstevezKullaFit fit = detail::estevez_kulla_fit(alpha_s);
  put(b, BRDF_GLTF_SHEEN_FIT + 0, fit.a);
  put(b, BRDF_GLTF_SHEEN_FIT + 1, fit.b);
  put(b, BRDF_GLTF_SHEEN_FIT + 2, fit.c);
  put(b, BRDF_GLTF_SHEEN_FIT + 3, fit.d);
  put(b, BRDF_GLTF_SHEEN_FIT + 4, fit.e);
  put(b, BRDF_GLTF_SHEEN_L_HALF, fit.a / (1.0 + fit.b * std::pow(0.5, fit.c)) + 0.5 * fit.d + fit.e);
  put(b, BRDF_GLTF_SHEEN_TABLE, sheen_table_offset);
  put(b, BRDF_GLTF_SHEEN_S_SEAM, std::pow(0.5, fit.c));
  put(b, BRDF_GLTF_F0_MAX, max3(f0));
  const double alpha_c = std::max(m.clearcoat_roughness * m.clearcoat_roughness, kMinAlpha);
  put(b, BRDF_GLTF_COAT, m.clearcoat);
  put(b, BRDF_GLTF_COAT_A2, alpha_c * alpha_c);
  return b;
}

// The classic models (Lambert, Phong, Blinn-Phong, Cook-Torrance, Blinn-Phong from PBR).
Block pack_classic(BrdfModel model, const Material& m) {
  Block b{};
  const double r2 = m.roughness * m.roughness;
  switch (model) {
    case BrdfModel::Lambert:
      put(b, BRDF_CLASSIC_KD, scale(classic_kd(m), 1.0 / kPi));
      break;
    case BrdfModel::Phong:
    case BrdfModel::BlinnPhong: {
      const double n = classic_exponent(m);
      // Lewis 1994: (n + 2) / (2 pi); RTR3 eq. 7.49: (n + 8) / (8 pi)
      const double norm = !m.normalized               ? 1.0
                          : model == BrdfModel::Phong ? (n + 2.0) / (2.0 * kPi)
                                                      : (n + 8.0) / (8.0 * kPi);
      put(b, BRDF_CLASSIC_KD, scale(classic_kd(m), 1.0 / kPi));
      put(b, BRDF_CLASSIC_KS, scale(classic_ks(m), norm));
      put(b, BRDF_CLASSIC_N, n);
      break;
    }
    case BrdfModel::CookTorrance: {
      put(b, BRDF_CLASSIC_KD, scale(classic_kd(m), 1.0 / kPi));
      // eta = (1 + sqrt F0) / (1 - sqrt F0); F0 = 1 (eta infinite) -> -1.
      const Rgb f0 = classic_ks(m);
      for (int c = 0; c < 3; ++c) {
        const double v = c == 0 ? f0.r : c == 1 ? f0.g : f0.b;
        const double s = std::sqrt(v);
        put(b, BRDF_CLASSIC_KS + c, v >= 1.0 ? -1.0 : (1.0 + s) / (1.0 - s));
      }
      const double alpha = std::max(r2, kMinAlpha);
      put(b, BRDF_CLASSIC_A2, alpha * alpha);
      put(b, BRDF_CLASSIC_BECKMANN, m.distribution == MicrofacetDistribution::Beckmann ? 1.0 : 0.0);
      break;
    }
    case BrdfModel::BlinnPhongFromPbr: {
      const double n = std::pow(2048.0, 1.0 - m.roughness);
      const Rgb c = m.base_color;
      put(b, BRDF_CLASSIC_KD, scale(c, (1.0 - m.metallic) / kPi));
      put(b, BRDF_CLASSIC_KS, Rgb{mix(0.04, c.r, m.metallic), mix(0.04, c.g, m.metallic), mix(0.04, c.b, m.metallic)});
      put(b, BRDF_CLASSIC_N, n);
      put(b, BRDF_CLASSIC_NORM, (n + 8.0) / (8.0 * kPi));
      break;
    }
    default:
      break;
  }
  return b;
}

Block pack_material(BrdfModel model, const Material& m, double sheen_table_offset) {
  switch (model) {
    case BrdfModel::Disney:
      return pack_disney(m);
    case BrdfModel::Gltf:
    case BrdfModel::GltfCorrelated:
      return pack_gltf(m, sheen_table_offset);
    default:
      return pack_classic(model, m);
  }
}

bool has_sheen(BrdfModel model, const Material& m) { return detail::is_gltf(model) && max3(m.sheen_color) > 0.0; }

// The narrowest lobe of a material, in radians of the half vector's polar angle: the albedo
// quadrature starts its log-spaced polar nodes 1e-4 of it below it.
}  // namespace

double detail::narrowest_lobe(BrdfModel model, const Material& m) {
  const double r2 = std::max(m.roughness * m.roughness, kMinAlpha);
  switch (model) {
    case BrdfModel::Disney: {
      const double aspect = std::sqrt(1.0 - 0.9 * m.anisotropic);
      double w = std::max(kDisneyMinAlpha, r2 * aspect);
      if (m.clearcoat > 0.0) w = std::min(w, mix(0.1, 0.001, m.clearcoat_gloss));
      return w;
    }
    case BrdfModel::Gltf:
    case BrdfModel::GltfCorrelated:
      return m.clearcoat > 0.0 ? std::min(r2, std::max(m.clearcoat_roughness * m.clearcoat_roughness, kMinAlpha)) : r2;
    case BrdfModel::CookTorrance:
      return r2;
    case BrdfModel::Phong:
    case BrdfModel::BlinnPhong:
      return 1.0 / std::sqrt(classic_exponent(m) + 1.0);
    case BrdfModel::BlinnPhongFromPbr:
      return 1.0 / std::sqrt(std::pow(2048.0, 1.0 - m.roughness) + 1.0);
    case BrdfModel::Lambert:
      break;
  }
  return 1.0;
}

detail::PackedMaterials detail::pack_materials(BrdfModel model, const std::vector<Material>& materials) {
  PackedMaterials out;
  std::map<double, size_t> sheen_offsets;
  for (const Material& m : materials) {
    double offset = 0.0;
    if (has_sheen(model, m)) {
      auto it = sheen_offsets.find(m.sheen_roughness);
      if (it == sheen_offsets.end()) {
        it = sheen_offsets.emplace(m.sheen_roughness, out.sheen.size()).first;
        const auto& t = detail::sheen_albedo_pieces(m.sheen_roughness);
        out.sheen.insert(out.sheen.end(), t.begin(), t.end());
      }
      offset = static_cast<double>(it->second);
    }
    const Block b = pack_material(model, m, offset);
    out.params.insert(out.params.end(), b.begin(), b.end());
  }
  return out;
}

}  // namespace brdfbake
