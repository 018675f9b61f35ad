// The `filament` target's split-sum shading: Filament 1.76's light_indirect.fs (evaluateIBL, prefilteredRadiance,
// evaluateSheenIBL, evaluateClearCoatIBL) on its own DFG table, as the registry's shading row
// (splitsum_sampling.hpp).
#include <algorithm>

#include "engines/filament/filament.hpp"
#include "families/preview/splitsum_sampling.hpp"

namespace brdfbake::detail::engines::filament {

using preview::BaseInputs;
using preview::mixf;
using preview::SplitSumSampler;

// common_material.fs: MIN_PERCEPTUAL_ROUGHNESS.
constexpr float kMinPerceptualRoughness = 0.045f;

float perceptual_roughness_to_lod(const SplitSumSampler& s, float perceptual_roughness) {
  // light_indirect.fs perceptualRoughnessToLod: (levels - 1) r (2 - r)
  return float(s.levels.size() - 1) * perceptual_roughness * (2.0f - perceptual_roughness);
}

void prefiltered_radiance(const SplitSumSampler& s, const Vec3& r, float perceptual_roughness, float out[3]) {
  s.trilinear(r, perceptual_roughness_to_lod(s, perceptual_roughness), out);
}

float sheen_dfg(const SplitSumSampler& s, float n_dot_v, float sheen_perceptual_roughness) {
  // prefilteredDFG(sheenPerceptualRoughness, NoV).z: the third channel of Filament's own table
  float e = 0.0f;
  preview::lut_lookup(s.files.dfg, false, n_dot_v, sheen_perceptual_roughness, 1, &e, 2);
  return e;
}

void evaluate_ibl(const SplitSumSampler& s, const PreviewMaterial& m, const BaseInputs& in, float out[3]) {
  const float nx = in.nx, ny = in.ny, nz = in.nz, vx = in.vx, vy = in.vy, vz = in.vz, dot_nv = in.dot_nv;
  const float* cd = in.cd;
  const float* irr = in.irr;
  float f0[3] = {in.f0[0], in.f0[1], in.f0[2]};
  // surface_shading_lit.fs getRoughnessPixelParams: under a clear coat (MATERIAL_HAS_CLEAR_COAT_ROUGHNESS,
  // which gltfio's materials set) the base is at least as rough as the coat, mixed by clearCoat:
  // mix(r, max(r, clearCoatPerceptualRoughness), clearCoat), the coat's clamped as evaluateClearCoatIBL's;
  // then perceptualRoughness clamped to [MIN_PERCEPTUAL_ROUGHNESS 0.045, 1] (common_material.fs),
  // roughness = perceptualRoughness^2; shading_NoV = clampNoV(dot(n, v)) = max(NoV, 1e-4)
  float base_pr = float(m.roughness);
  if (m.clearcoat > 0.0)
    base_pr = mixf(base_pr, std::max(base_pr, std::clamp(float(m.clearcoat_roughness), kMinPerceptualRoughness, 1.0f)),
                   float(m.clearcoat));
  const float pr = std::clamp(base_pr, kMinPerceptualRoughness, 1.0f), a = pr * pr;
  const float nv = std::max(dot_nv, 1e-4f);
  float bias = 0, albedo = 0;
  s.dfg(nv, pr, &bias, &albedo);  // PrefilteredDFG_LUT(perceptualRoughness, NoV)
  // getReflectedVector -> getSpecularDominantDirection: mix(r, n, roughness^2), r = reflect(-v, n)
  const float rx = 2.0f * dot_nv * nx - vx, ry = 2.0f * dot_nv * ny - vy, rz = 2.0f * dot_nv * nz - vz;
  const float sq = a * a;
  const Vec3 dir{mixf(rx, nx, sq), mixf(ry, ny, sq), mixf(rz, nz, sq)};
  float light[3];
  prefiltered_radiance(s, dir, pr, light);
  for (int c = 0; c < 3; ++c) {
    const float e = mixf(bias, albedo, f0[c]);                // specularDFG (F90 1)
    const float k = 1.0f + f0[c] * (1.0f / albedo - 1.0f);    // energyCompensation
    out[c] = e * light[c] * k + cd[c] * irr[c] * (1.0f - e);  // evaluateIBL: Fr + Fd
  }
}

void evaluate_sheen_ibl(const SplitSumSampler& s, const Vec3& nd, const Vec3& vd, const PreviewMaterial& m,
                        float /*aa_alpha_g*/, float out[3]) {
  const float nx = float(nd.x), ny = float(nd.y), nz = float(nd.z), vx = float(vd.x), vy = float(vd.y),
              vz = float(vd.z);
  const float dot_nv = nx * vx + ny * vy + nz * vz;
  const Vec3 refl{double(2.0f * dot_nv * nx - vx), double(2.0f * dot_nv * ny - vy), double(2.0f * dot_nv * nz - vz)};
  const float c[3] = {float(m.sheen_color.r), float(m.sheen_color.g), float(m.sheen_color.b)};
  const float cmax = std::max(c[0], std::max(c[1], c[2]));
  float light[3];
  // light_indirect.fs evaluateSheenIBL: Fd and Fr times sheenScaling = 1 - max3(sheenColor)
  // sheenDFG; Fr += sheenDFG sheenColor prefilteredRadiance(shading_reflected,
  // sheenPerceptualRoughness): the GGX chain at perceptualRoughnessToLod; sheenDFG =
  // prefilteredDFG(sheenPerceptualRoughness, NoV).z, Filament's built-in table's third channel;
  // sheenPerceptualRoughness clamped to [MIN_PERCEPTUAL_ROUGHNESS 0.045, 1] (common_material.fs)
  const float nv = std::max(dot_nv, 1e-4f);
  const float pr = std::clamp(float(m.sheen_roughness), kMinPerceptualRoughness, 1.0f);
  const float e = sheen_dfg(s, nv, pr), scale = 1.0f - cmax * e;
  prefiltered_radiance(s, refl, pr, light);
  for (int k = 0; k < 3; ++k) out[k] = out[k] * scale + e * c[k] * light[k];
}

void evaluate_clear_coat_ibl(const SplitSumSampler& s, const Vec3& nd, const Vec3& vd, const PreviewMaterial& m,
                             float /*aa_alpha_g*/, float out[3]) {
  const float nx = float(nd.x), ny = float(nd.y), nz = float(nd.z), vx = float(vd.x), vy = float(vd.y),
              vz = float(vd.z);
  const float dot_nv = nx * vx + ny * vy + nz * vz;
  const Vec3 refl{double(2.0f * dot_nv * nx - vx), double(2.0f * dot_nv * ny - vy), double(2.0f * dot_nv * nz - vz)};
  const float cc = float(m.clearcoat);
  float light[3];
  // light_indirect.fs, evaluateClearCoatIBL (no clear coat normal: clearCoatNoV = shading_NoV,
  // clearCoatR = shading_reflected): Fc = F_Schlick(0.04, 1, NoV) clearCoat; Fd and Fr times
  // 1 - Fc; Fr += prefilteredRadiance(clearCoatR, clearCoatPerceptualRoughness) Fc (no DFG term);
  // clearCoatPerceptualRoughness clamped to [MIN_PERCEPTUAL_ROUGHNESS, 1] (common_material.fs)
  const float nv = std::max(dot_nv, 1e-4f);
  const float pr = std::clamp(float(m.clearcoat_roughness), kMinPerceptualRoughness, 1.0f);
  prefiltered_radiance(s, refl, pr, light);
  const float fc = (0.04f + 0.96f * preview::pow5(1.0f - std::min(nv, 1.0f))) * cc;
  for (int c = 0; c < 3; ++c) out[c] = out[c] * (1.0f - fc) + light[c] * fc;
}

namespace {

// the GGX chain at the sheen's LOD, its own table's sheen channel: always
bool renders_sheen(const SplitSumSampler&) { return true; }

std::string sheen_note(const SplitSumSampler&) {
  return "KHR_materials_sheen: in the split-sum render, Filament's evaluateSheenIBL (the GGX chain at "
         "perceptualRoughnessToLod(sheenPerceptualRoughness) x sheenDFG, the z channel of Filament's built-in "
         "DFG table at (n.v, sheenPerceptualRoughness), x sheenColor; Fd and Fr x 1 - max3(sheenColor) sheenDFG)";
}

Metadata steps(const SplitSumSampler& s) {
  return {{"roughness",
           "clamp(roughness, MIN_PERCEPTUAL_ROUGHNESS 0.045, 1) (common_material.fs); n.v = clampNoV: max(n.v, 1e-4)"},
          {"lod", "perceptualRoughnessToLod: (levels - 1) r (2 - r) (light_indirect.fs)"},
          {"direction",
           "getSpecularDominantDirection: mix(reflect(-v, n), n, roughness^2), roughness = r^2 (light_indirect.fs)"},
          {"specular_sample", s.cube_text() + " (prefilteredRadiance)"},
          {"dfg", s.lut_text() + " (PrefilteredDFG_LUT(perceptualRoughness, NoV)): Filament 1.76 samples the table "
                                 "built into it, never the bake's"},
          {"specular",
           "specularDFG: mix(dfg.x, dfg.y, F0) x prefilteredRadiance x energyCompensation 1 + F0 (1 / dfg.y - 1) "
           "(evaluateIBL)"},
          {"diffuse",
           "diffuseColor x Irradiance_SphericalHarmonics(n) (max(sum sh_k poly_k, 0), the KTX sh key) x (1 - E) "
           "(evaluateIBL)"}};
}

}  // namespace

const preview::SplitSumShading& shading() {
  static const preview::SplitSumShading row = [] {
    preview::SplitSumShading r;
    r.base = evaluate_ibl;
    r.sheen = evaluate_sheen_ibl;
    r.coat = evaluate_clear_coat_ibl;
    r.renders_sheen = renders_sheen;
    r.sheen_note = sheen_note;
    r.steps = steps;
    return r;
  }();
  return row;
}

}  // namespace brdfbake::detail::engines::filament
