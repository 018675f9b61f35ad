// The `khronos-viewer` target's split-sum shading: the glTF-Sample-Viewer's ibl.glsl (getIBLRadianceGGX,
// getIBLRadianceLambertian, getIBLRadianceCharlie) and pbr.frag's layering, as the registry's shading row
// (splitsum_sampling.hpp).
#include <algorithm>

#include "engines/khronos_viewer/khronos_viewer.hpp"
#include "families/preview/iridescence.hpp"
#include "families/preview/splitsum_sampling.hpp"

namespace brdfbake::detail::engines::khronos_viewer {

using preview::BaseInputs;
using preview::mixf;
using preview::pow5;
using preview::SplitSumSampler;

namespace {

// The glTF-Sample-Viewer's f0 (material_info.glsl, getIorInfo then getMetallicRoughnessInfo and
// getSpecularInfo): mix(min(f0_ior specularColorFactor, 1), baseColor, metallic), without the
// specular factor (its specularWeight); preview_f0 of the material with specular 1.
Rgb get_specular_info_f0(const PreviewMaterial& m) {
  PreviewMaterial unweighted = m;
  unweighted.specular = 1.0;
  return preview_f0(unweighted);
}

}  // namespace

void get_ibl_radiance_ggx(const SplitSumSampler& s, const PreviewMaterial& m, const BaseInputs& in, float out[3]) {
  const float nx = in.nx, ny = in.ny, nz = in.nz, vx = in.vx, vy = in.vy, vz = in.vz, dot_nv = in.dot_nv;
  const float* cd = in.cd;
  const float* irr = in.irr;
  const float levels_minus_one = in.levels_minus_one;
  const float specular = in.specular;
  // ibl.glsl getIBLRadianceGGX and getIBLRadianceLambertian; material_info.glsl getIorInfo and
  // getSpecularInfo: f0 = mix(min(f0_ior specularColorFactor, 1), baseColor, metallic) without the
  // specular factor, which both functions apply as specularWeight (to metals too)
  const float nv = std::clamp(dot_nv, 0.0f, 1.0f), r = float(m.roughness);
  const float lod = r * levels_minus_one;
  const Vec3 refl{double(2.0f * dot_nv * nx - vx), double(2.0f * dot_nv * ny - vy), double(2.0f * dot_nv * nz - vz)};
  float light[3], bias = 0, albedo = 0;
  s.trilinear(refl, lod, light);
  s.dfg(std::clamp(nv, 0.0f, 1.0f), std::clamp(r, 0.0f, 1.0f), &bias, &albedo);
  const float fa = albedo - bias, fb = bias;  // f_ab: scale, bias
  const Rgb f0_sv = get_specular_info_f0(m);
  const float f0v[3] = {float(f0_sv.r), float(f0_sv.g), float(f0_sv.b)}, sw = specular;
  // KHR_materials_iridescence (pbr.frag): iridescenceFresnel = evalIridescence(1, iridescenceIor, NdotV,
  // thickness, f0); getIBLRadianceGGXIridescence mixes it into k_S, getIBLRadianceLambertianIridescence
  // mixes F0 with max3(Schlick_to_F0(iridescenceFresnel, NdotV))
  float film = 0.0f, film_fresnel[3] = {0, 0, 0}, f0l[3] = {f0v[0], f0v[1], f0v[2]};
  const bool iridescent = preview::split_sum_film(m, nv, f0v, &film, film_fresnel);
  if (iridescent) {
    const float f0_max =
        std::max({preview::schlick_to_f0(film_fresnel[0], nv), preview::schlick_to_f0(film_fresnel[1], nv),
                  preview::schlick_to_f0(film_fresnel[2], nv)});
    for (int c = 0; c < 3; ++c) f0l[c] = mixf(f0v[c], f0_max, film);
  }
  for (int c = 0; c < 3; ++c) {
    const float fr = std::max(1.0f - r, f0v[c]) - f0v[c];
    const float ks0 = f0v[c] + fr * pow5(1.0f - nv);
    const float ks = iridescent ? mixf(ks0, film_fresnel[c], film) : ks0;
    const float frd = std::max(1.0f - r, f0l[c]) - f0l[c];
    const float ksd = f0l[c] + frd * pow5(1.0f - nv);
    const float fss_ess = sw * ksd * fa + fb;  // getIBLRadianceLambertian's (its bias not weighted)
    const float ems = 1.0f - (fa + fb);
    const float favg = sw * (f0l[c] + (1.0f - f0l[c]) / 21.0f);
    const float fms_ems = ems * fss_ess * favg / (1.0f - favg * ems);
    const float kd = cd[c] * (1.0f - fss_ess + fms_ems);
    out[c] = sw * light[c] * (ks * fa + fb) + (fms_ems + kd) * irr[c];  // getIBLRadianceGGX's
  }
}

void get_ibl_radiance_charlie(const SplitSumSampler& s, const Vec3& nd, const Vec3& vd, const PreviewMaterial& m,
                              float /*aa_alpha_g*/, float out[3]) {
  const float nx = float(nd.x), ny = float(nd.y), nz = float(nd.z), vx = float(vd.x), vy = float(vd.y),
              vz = float(vd.z);
  const float dot_nv = nx * vx + ny * vy + nz * vz;
  const Vec3 refl{double(2.0f * dot_nv * nx - vx), double(2.0f * dot_nv * ny - vy), double(2.0f * dot_nv * nz - vz)};
  const float c[3] = {float(m.sheen_color.r), float(m.sheen_color.g), float(m.sheen_color.b)};
  const float cmax = std::max(c[0], std::max(c[1], c[2]));
  float light[3];
  // ibl.glsl getIBLRadianceCharlie: lod = sheenRoughness (u_MipCount - 1) on the Charlie chain at
  // normalize(reflect(-v, n)), times the charlie LUT at clamp((NdotV, sheenRoughness)), times
  // sheenColor; pbr.frag: color = f_sheen + color albedoSheenScaling, albedoSheenScaling = 1 -
  // max3(sheenColor) albedoSheenScalingLUT(NdotV, sheenRoughness) (not clamped); both LUTs are the
  // bake's charlie table
  const float nv = std::clamp(dot_nv, 0.0f, 1.0f), r = std::clamp(float(m.sheen_roughness), 0.0f, 1.0f);
  // (u_MipCount is the GGX chain's: the IBL Sampler writes both chains with the same levels)
  preview::trilinear_in(s.sheen_levels, refl, r * float(s.levels.size() - 1), light);
  const float e = s.charlie(nv, r), scale = 1.0f - cmax * e;
  for (int k = 0; k < 3; ++k) out[k] = c[k] * light[k] * e + out[k] * scale;
}

void clearcoat_ibl(const SplitSumSampler& s, const Vec3& nd, const Vec3& vd, const PreviewMaterial& m,
                   float /*aa_alpha_g*/, float out[3]) {
  // KHR_materials_clearcoat with the geometric normal (the sphere's)
  const float nx = float(nd.x), ny = float(nd.y), nz = float(nd.z), vx = float(vd.x), vy = float(vd.y),
              vz = float(vd.z);
  const float dot_nv = nx * vx + ny * vy + nz * vz;
  const Vec3 refl{double(2.0f * dot_nv * nx - vx), double(2.0f * dot_nv * ny - vy), double(2.0f * dot_nv * nz - vz)};
  const float levels_minus_one = float(s.levels.size() - 1), cc = float(m.clearcoat);
  float light[3];
  // pbr.frag: f_clearcoat = getIBLRadianceGGX(clearcoatNormal, v, clearcoatRoughness, clearcoatF0, 1)
  // (ibl.glsl), clearcoatFresnel = F_Schlick(clearcoatF0, 1, NdotV), color = color (1 - clearcoatFactor
  // clearcoatFresnel) + clearcoatFactor f_clearcoat; material_info.glsl getClearCoatInfo: clearcoatF0 =
  // the material's f0 at that point, mix(f0 of the ior, baseColor, metallic)
  PreviewMaterial plain = m;
  plain.specular = 1.0;
  plain.specular_color = {1.0, 1.0, 1.0};
  const Rgb f0d = preview_f0(plain);
  const float f0[3] = {float(f0d.r), float(f0d.g), float(f0d.b)};
  const float nv = std::clamp(dot_nv, 0.0f, 1.0f), r = float(m.clearcoat_roughness);
  float bias = 0, albedo = 0;
  s.trilinear(refl, r * levels_minus_one, light);
  s.dfg(nv, std::clamp(r, 0.0f, 1.0f), &bias, &albedo);
  const float fa = albedo - bias, fb = bias;
  for (int c = 0; c < 3; ++c) {
    const float fr = std::max(1.0f - r, f0[c]) - f0[c];
    const float ks = f0[c] + fr * pow5(1.0f - nv);
    const float fresnel = f0[c] + (1.0f - f0[c]) * pow5(1.0f - nv);
    out[c] = out[c] * (1.0f - cc * fresnel) + cc * light[c] * (ks * fa + fb);
  }
}

namespace {

bool renders_sheen(const SplitSumSampler& s) { return s.files.charlie.width > 0 && !s.sheen_levels.empty(); }

std::string sheen_note(const SplitSumSampler& s) {
  return "KHR_materials_sheen: in the split-sum render, the glTF-Sample-Viewer's getIBLRadianceCharlie (" +
         preview::file_name(s.files.sheen_file) + " at lod sheenRoughness (mips - 1)" +
         " x E(n.v, sheenRoughness) of " + preview::file_name(s.files.charlie_file) +
         " x sheenColor) and albedoSheenScaling 1 - max3(sheenColor) E";
}

Metadata steps(const SplitSumSampler& s) {
  return {{"lod", "roughness (u_MipCount - 1) (ibl.glsl, getIBLRadianceGGX)"},
          {"specular_sample", s.cube_text() + ", at normalize(reflect(-v, n)) (getSpecularSample)"},
          {"dfg", s.lut_text() + ", as f_ab = (scale, bias) at clamp(NdotV, roughness)"},
          {"specular",
           "specularLight x (k_S f_ab.x + f_ab.y), k_S = F0 + (max(1 - roughness, F0) - F0) (1 - NdotV)^5 "
           "(getIBLRadianceGGX)"},
          {"diffuse",
           "(FmsEms + k_D) x texture(u_LambertianEnvSampler, n) (getIBLRadianceLambertian, Fdez-Aguera's multiple "
           "scattering)"}};
}

}  // namespace

const preview::SplitSumShading& shading() {
  static const preview::SplitSumShading row = [] {
    preview::SplitSumShading r;
    r.base = get_ibl_radiance_ggx;
    r.sheen = get_ibl_radiance_charlie;
    r.coat = clearcoat_ibl;
    r.renders_sheen = renders_sheen;
    r.sheen_note = sheen_note;
    r.steps = steps;
    return r;
  }();
  return row;
}

}  // namespace brdfbake::detail::engines::khronos_viewer
