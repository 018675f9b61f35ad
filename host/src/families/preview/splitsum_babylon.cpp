// Babylon.js's clear coat and sheen blocks, IBL part (splitsum_babylon.hpp): fp32, in the shader's
// order of operations.
#include "families/preview/splitsum_babylon.hpp"

#include <algorithm>
#include <cmath>

namespace brdfbake::detail::preview::babylon {

float abs_eps(float x) { return std::fabs(x) + kAbsEpsilon; }

float alpha_g(float roughness) { return roughness * roughness + kMinimumVariance; }

float reflection_lod(float cube_size, float alpha_g, float lod_generation_scale) {
  return std::log2(cube_size * alpha_g) * lod_generation_scale;
}

float fresnel_schlick_ggx(float v_dot_h, float r0, float r90) {
  const float x = 1.0f - v_dot_h, x2 = x * x;
  return r0 + (r90 - r0) * (x2 * x2 * x);  // pow5
}

ClearCoat clear_coat(float intensity, float n_dot_v, float brdf_x, float brdf_y) {
  ClearCoat out;
  // clear coat energy conservation: fresnelIBLClearCoat = fresnelSchlickGGX(clearCoatNdotV,
  // vClearCoatRefractionParams.x, CLEARCOATREFLECTANCE90) x clearCoatIntensity
  out.conservation = 1.0f - fresnel_schlick_ggx(n_dot_v, kClearCoatF0, kClearCoatF90) * intensity;
  // clearCoatEnvironmentReflectance = getReflectanceFromBRDFLookup(vec3(F0), brdf) x intensity,
  // getReflectanceFromBRDFLookup (height-correlated): mix(brdf.xxx, brdf.yyy, R0)
  out.coat_reflectance = (brdf_x + (brdf_y - brdf_x) * kClearCoatF0) * intensity;
  return out;
}

Sheen sheen(const float color[3], float intensity, float brdf_b) {
  Sheen out;
  // sheenColor *= sheenIntensity ("Remap F0 and sheen"); getSheenReflectanceFromBRDFLookup:
  // sheenColor x environmentSheenBrdf.b
  float c[3];
  for (int k = 0; k < 3; ++k) {
    c[k] = color[k] * intensity;
    out.reflectance[k] = c[k] * brdf_b;
  }
  // sheenAlbedoScaling = 1 - sheenIntensity x max(max(sheenColor.r, sheenColor.g), sheenColor.b) x b
  out.albedo_scaling = 1.0f - intensity * std::max(std::max(c[0], c[1]), c[2]) * brdf_b;
  return out;
}

}  // namespace brdfbake::detail::preview::babylon
