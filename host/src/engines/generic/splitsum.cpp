// The `generic` target's split-sum shading: the runtime docs/CONVENTIONS.md describes (no engine of its own), as
// the registry's shading row (splitsum_sampling.hpp).
#include <algorithm>

#include "engines/generic/generic.hpp"
#include "families/preview/iridescence.hpp"
#include "families/preview/splitsum_sampling.hpp"

namespace brdfbake::detail::engines::generic {

using preview::BaseInputs;
using preview::SplitSumSampler;

void split_sum_ibl(const SplitSumSampler& s, const PreviewMaterial& m, const BaseInputs& in, float out[3]) {
  const float nx = in.nx, ny = in.ny, nz = in.nz, vx = in.vx, vy = in.vy, vz = in.vz, dot_nv = in.dot_nv;
  const float* cd = in.cd;
  const float* irr = in.irr;
  float f0[3] = {in.f0[0], in.f0[1], in.f0[2]};
  const float levels_minus_one = in.levels_minus_one;
  const float f90 = in.f90;
  // docs/CONVENTIONS.md's runtime: lod = (levels - 1) roughness, specular = prefiltered x
  // (F90 bias + (albedo - bias) F0) x (1 + F0 (1 / albedo - 1)) (ggx-multiscatter) or F0 scale
  // + F90 bias
  const float nv = std::clamp(dot_nv, 0.0f, 1.0f), r = float(m.roughness);
  const Vec3 refl{double(2.0f * nv * nx - vx), double(2.0f * nv * ny - vy), double(2.0f * nv * nz - vz)};
  float light[3], bias = 0, albedo = 0;
  s.trilinear(refl, levels_minus_one * r, light);
  s.dfg(nv, r, &bias, &albedo);
  preview::iridescent_f0(m, nv, f0);  // KHR_materials_iridescence: F0 = mix(F0, F_irid(n.v), iridescenceFactor)
  for (int c = 0; c < 3; ++c) {
    const float e = f90 * bias + (albedo - bias) * f0[c];
    const float k = s.files.dfg_multiscatter ? 1.0f + f0[c] * (1.0f / albedo - 1.0f) : 1.0f;
    out[c] = light[c] * e * k + cd[c] * irr[c];
  }
}

void charlie_sheen(const SplitSumSampler& s, const Vec3& nd, const Vec3& vd, const PreviewMaterial& m,
                   float /*aa_alpha_g*/, float out[3]) {
  const float nx = float(nd.x), ny = float(nd.y), nz = float(nd.z), vx = float(vd.x), vy = float(vd.y),
              vz = float(vd.z);
  const float dot_nv = nx * vx + ny * vy + nz * vz;
  const Vec3 refl{double(2.0f * dot_nv * nx - vx), double(2.0f * dot_nv * ny - vy), double(2.0f * dot_nv * nz - vz)};
  const float c[3] = {float(m.sheen_color.r), float(m.sheen_color.g), float(m.sheen_color.b)};
  const float cmax = std::max(c[0], std::max(c[1], c[2]));
  float light[3];
  // docs/CONVENTIONS.md, "Charlie sheen at run time": sheen = sheenColor x prefiltered Charlie
  // radiance (lod (levels - 1) sheenRoughness, the linear schedule) x E(n.v, sheenRoughness); the
  // base scaled by max(1 - max(sheenColor) E, 0)
  const float nv = std::clamp(dot_nv, 0.0f, 1.0f), r = float(m.sheen_roughness);
  preview::trilinear_in(s.sheen_levels, refl, float(s.sheen_levels.size() - 1) * r, light);
  const float e = s.charlie(nv, r), scale = std::max(1.0f - cmax * e, 0.0f);
  for (int k = 0; k < 3; ++k) out[k] = out[k] * scale + c[k] * light[k] * e;
}

void fresnel_coat(const SplitSumSampler& s, const Vec3& nd, const Vec3& vd, const PreviewMaterial& m,
                  float /*aa_alpha_g*/, float out[3]) {
  // KHR_materials_clearcoat with the geometric normal (the sphere's)
  const float nx = float(nd.x), ny = float(nd.y), nz = float(nd.z), vx = float(vd.x), vy = float(vd.y),
              vz = float(vd.z);
  const float dot_nv = nx * vx + ny * vy + nz * vz;
  const Vec3 refl{double(2.0f * dot_nv * nx - vx), double(2.0f * dot_nv * ny - vy), double(2.0f * dot_nv * nz - vz)};
  const float levels_minus_one = float(s.levels.size() - 1), cc = float(m.clearcoat);
  float light[3];
  // the extension's fresnel_coat over the split sum: the coat's radiance is prefiltered x A_coat
  // (its layer D V carries no Fresnel), weighted by clearcoat Fcoat(n.v), Fcoat = F_Schlick(0.04, 1)
  const float nv = std::clamp(dot_nv, 0.0f, 1.0f), r = float(m.clearcoat_roughness);
  float bias = 0, albedo = 0;
  s.trilinear(refl, levels_minus_one * r, light);
  s.dfg(nv, r, &bias, &albedo);
  const float t = cc * (0.04f + 0.96f * preview::pow5(1.0f - nv));
  for (int c = 0; c < 3; ++c) out[c] = out[c] * (1.0f - t) + t * light[c] * albedo;
}

namespace {

bool renders_sheen(const SplitSumSampler& s) { return s.files.charlie.width > 0 && !s.sheen_levels.empty(); }

std::string sheen_note(const SplitSumSampler& s) {
  return "KHR_materials_sheen: in the split-sum render, docs/CONVENTIONS.md's runtime: sheenColor x " +
         preview::file_name(s.files.sheen_file) + " at lod (levels - 1) sheenRoughness" +
         " x E(n.v, sheenRoughness) of " + preview::file_name(s.files.charlie_file) +
         ", the base x max(1 - max(sheenColor) E, 0)";
}

Metadata steps(const SplitSumSampler& s) {
  return {{"lod", "(levels - 1) roughness (docs/CONVENTIONS.md, linear schedule)"},
          {"specular_sample", s.cube_text() + ", at reflect(-v, n)"},
          {"dfg", s.lut_text() + ", at (clamp(n.v), roughness)"},
          {"specular", s.files.dfg_multiscatter ? "prefiltered x mix(bias, albedo, F0) x (1 + F0 (1 / albedo - 1))"
                                                : "prefiltered x (F0 scale + bias)"},
          {"diffuse", s.files.diffuse == preview::DiffuseSource::None
                          ? std::string("none: the bake holds no irradiance, and no sphere has a diffuse lobe")
                          : "diffuse colour x sum c_lm Y_lm(n) (E / pi, " + s.files.diffuse_file + ")"}};
}

}  // namespace

const preview::SplitSumShading& shading() {
  static const preview::SplitSumShading row = [] {
    preview::SplitSumShading r;
    r.base = split_sum_ibl;
    r.sheen = charlie_sheen;
    r.coat = fresnel_coat;
    r.renders_sheen = renders_sheen;
    r.sheen_note = sheen_note;
    r.steps = steps;
    return r;
  }();
  return row;
}

}  // namespace brdfbake::detail::engines::generic
