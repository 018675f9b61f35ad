// KHR_materials_iridescence in the preview (iridescence.hpp).
#include "families/preview/iridescence.hpp"

#include <algorithm>
#include <cmath>

namespace brdfbake::detail::preview {

namespace {

constexpr float kPi = 3.14159265358979323846f;

float ior_to_f0(float transmitted, float incident) {
  const float r = (transmitted - incident) / (transmitted + incident);
  return r * r;
}

float schlick(float f0, float cos_theta) {
  const float x = std::clamp(1.0f - cos_theta, 0.0f, 1.0f), x2 = x * x;
  return f0 + (1.0f - f0) * x2 * x2 * x;
}

float smoothstep(float e0, float e1, float x) {
  const float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

// evalSensitivity: the CIE 1931 matching functions' Gaussian fits (Belcour & Barla 2017's
// supplemental) in Fourier space at the optical path difference, XYZ to linear Rec. 709.
void sensitivity(float opd, const float shift[3], float out[3]) {
  const float phase = 2.0f * kPi * opd * 1.0e-9f;
  const float val[3] = {5.4856e-13f, 4.4201e-13f, 5.2481e-13f};
  const float pos[3] = {1.6810e+06f, 1.7953e+06f, 2.2084e+06f};
  const float var[3] = {4.3278e+09f, 9.3046e+09f, 6.6121e+09f};
  float xyz[3];
  for (int k = 0; k < 3; ++k)
    xyz[k] = val[k] * std::sqrt(2.0f * kPi * var[k]) * std::cos(pos[k] * phase + shift[k]) *
             std::exp(-phase * phase * var[k]);
  xyz[0] += 9.7470e-14f * std::sqrt(2.0f * kPi * 4.5282e+09f) * std::cos(2.2399e+06f * phase + shift[0]) *
            std::exp(-4.5282e+09f * phase * phase);
  for (float& v : xyz) v /= 1.0685e-7f;
  out[0] = 3.2404542f * xyz[0] - 1.5371385f * xyz[1] - 0.4985314f * xyz[2];
  out[1] = -0.9692660f * xyz[0] + 1.8760108f * xyz[1] + 0.0415560f * xyz[2];
  out[2] = 0.0556434f * xyz[0] - 0.2040259f * xyz[1] + 1.0572252f * xyz[2];
}

}  // namespace

void eval_iridescence(float outside_ior, float film_ior_in, float cos1, float thickness, const float base_f0[3],
                      float out[3]) {
  // the film's index fades to the outside's over its first 0.03 nm; Snell to the base's angle
  const float film_ior = outside_ior + (film_ior_in - outside_ior) * smoothstep(0.0f, 0.03f, thickness);
  const float ratio = outside_ior / film_ior;
  const float cos2_sq = 1.0f - ratio * ratio * (1.0f - cos1 * cos1);
  if (cos2_sq < 0.0f) {  // total internal reflection
    out[0] = out[1] = out[2] = 1.0f;
    return;
  }
  const float cos2 = std::sqrt(cos2_sq);
  // the first interface (outside to film) and the second (film to base), Schlick's amplitudes
  const float r12 = schlick(ior_to_f0(film_ior, outside_ior), cos1);
  const float t121 = 1.0f - r12;
  const float phi21 = film_ior < outside_ior ? 0.0f : kPi;  // pi - phi12
  const float opd = 2.0f * film_ior * thickness * cos2;
  float cm[3], amplitude[3], phi[3];
  for (int k = 0; k < 3; ++k) {
    const float s = std::sqrt(std::clamp(base_f0[k], 0.0f, 0.9999f));
    const float base_ior = (1.0f + s) / (1.0f - s);
    const float r23 = schlick(ior_to_f0(base_ior, film_ior), cos2);
    phi[k] = phi21 + (base_ior < film_ior ? kPi : 0.0f);
    const float r123 = std::clamp(r12 * r23, 1e-5f, 0.9999f);
    amplitude[k] = std::sqrt(r123);
    const float rs = t121 * t121 * r23 / (1.0f - r123);
    out[k] = r12 + rs;  // C0
    cm[k] = rs - t121;
  }
  for (int m = 1; m <= 2; ++m) {
    const float shift[3] = {float(m) * phi[0], float(m) * phi[1], float(m) * phi[2]};
    float sm[3];
    sensitivity(float(m) * opd, shift, sm);
    for (int k = 0; k < 3; ++k) {
      cm[k] *= amplitude[k];
      out[k] += cm[k] * 2.0f * sm[k];
    }
  }
  for (int k = 0; k < 3; ++k) out[k] = std::max(out[k], 0.0f);
}

float schlick_to_f0(float f, float v_dot_h) {
  const float x = std::clamp(1.0f - v_dot_h, 0.0f, 1.0f), x2 = x * x;
  const float x5 = std::clamp(x * x2 * x2, 0.0f, 0.9999f);
  return (f - x5) / (1.0f - x5);
}

bool split_sum_film(const PreviewMaterial& m, float n_dot_v, const float base_f0[3], float* factor, float fresnel[3]) {
  if (!preview_has_iridescence(m) || m.iridescence_thickness == 0.0) return false;
  *factor = float(m.iridescence);
  eval_iridescence(1.0f, float(m.iridescence_ior), n_dot_v, float(m.iridescence_thickness), base_f0, fresnel);
  return true;
}

ReferenceFilms reference_films(const PreviewMaterial& m) {
  ReferenceFilms f;
  if (!preview_has_iridescence(m)) return f;
  f.dielectric_weight = (1.0 - m.metallic) * m.specular;
  f.metal_weight = m.metallic;
  f.dielectric_f0 = preview_dielectric_f0(m);
  f.metal_f0 = m.base_color;
  return f;
}

bool split_sum_renders_iridescence(EngineTarget target) { return target != EngineTarget::Filament; }

std::string iridescence_note(EngineTarget target) {
  switch (target) {
    case EngineTarget::Generic:
      return "KHR_materials_iridescence: in the split-sum render, docs/CONVENTIONS.md's runtime: F0 replaced by "
             "mix(F0, F_irid(n.v), iridescenceFactor), F_irid the thin film over F0 (evalIridescence(1, "
             "iridescenceIor, n.v, thickness, F0))";
    case EngineTarget::KhronosViewer:
      return "KHR_materials_iridescence: in the split-sum render, the glTF-Sample-Viewer's "
             "getIBLRadianceGGXIridescence (k_S = mix(F0 + Fr (1 - NdotV)^5, iridescenceFresnel, iridescenceFactor)) "
             "and getIBLRadianceLambertianIridescence (F0 mixed with max3(Schlick_to_F0(iridescenceFresnel, "
             "NdotV))), iridescenceFresnel = evalIridescence(1, iridescenceIor, NdotV, thickness, f0)";
    case EngineTarget::Gltf:
    case EngineTarget::Babylon:
      return "KHR_materials_iridescence: in the split-sum render, Babylon.js's iridescenceBlock "
             "(pbrBlockIridescence.fx): specularEnvironmentR0 = mix(R0, evalIridescence(1, iridescenceIOR, NdotV, "
             "thickness, R0), intensity), then the BRDF lookup and energy conservation with it (under a clear coat "
             "Babylon.js sees the film through the coat: not emulated)";
    case EngineTarget::Filament:
      return "KHR_materials_iridescence: not rendered for this target (Filament has no iridescence); in the "
             "reference";
  }
  return {};
}

}  // namespace brdfbake::detail::preview
