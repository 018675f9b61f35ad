// Internal: Babylon.js's PBR shader in the split-sum render of the `babylon` and `gltf` targets (the glTF target
// is Babylon.js's glTF loader: gltf/splitsum.cpp sets what the loader changes and shades with these). First its
// clear coat and sheen blocks (docs/ENGINES.md, "The extensions' lobes in the split-sum render"): the terms
// its PBRMaterial computes from the BRDF lookup and the reflection texture, with the options its glTF
// loader sets (KHR_materials_clearcoat: clearCoat.remapF0OnInterfaceChange false, the coat's index
// of refraction Babylon's default 1.5; KHR_materials_sheen: sheen.intensity 1, albedoScaling true,
// the sheen roughness of the file). Pure fp32 functions of values the caller has looked up, so a
// test can evaluate the same formula by hand; then the shading row's functions (splitsum.cpp), which sample.
//
// Read at BabylonJS/Babylon.js: packages/dev/core/src/Shaders/ShadersInclude/pbrBlockClearcoat.fx
// (011c37f), pbrBlockSheen.fx (626ee12), pbrBRDFFunctions.fx (00e0487), pbrBlockReflectance.fx
// (158c4a7), pbrBlockFinalLitComponents.fx (076e49a), pbrBlockFinalColorComposition.fx (9082b8a),
// pbrDirectLightingFunctions.fx (CLEARCOATREFLECTANCE90 1.0); packages/dev/loaders/src/glTF/2.0/
// Extensions/KHR_materials_clearcoat.ts (06c05dd), KHR_materials_sheen.ts (00da831) and the
// PBRMaterialLoadingAdapter's configureCoat / configureFuzz (the same options).
#pragma once

#include <string>
#include <vector>

#include "families/preview/splitsum_sampling.hpp"

namespace brdfbake::detail::engines::babylon {

// PBRClearCoatConfiguration's default index of refraction 1.5 (the loader sets no other):
// vClearCoatRefractionParams.x = ((1 - 1.5) / (1 + 1.5))^2.
inline constexpr float kClearCoatF0 = 0.04f;
// pbrDirectLightingFunctions.fx: #define CLEARCOATREFLECTANCE90 1.0.
inline constexpr float kClearCoatF90 = 1.0f;
// pbrBlockGeometryInfo / pbrBlockClearcoat: absEps(x) = |x| + Epsilon (helperFunctions.fx, 1e-7).
inline constexpr float kAbsEpsilon = 1e-7f;
// convertRoughnessToAverageSlope: alphaG = roughness^2 + MINIMUMVARIANCE.
inline constexpr float kMinimumVariance = 0.0005f;

// absEps(x): the n.v every block of the PBR shader uses ("The Order 1886 page 3").
float abs_eps(float x);
// convertRoughnessToAverageSlope(roughness).
float alpha_g(float roughness);
// sampleReflectionTexture's LOD (pbrBlockReflection.fx, LODBASEDMICROSFURACE):
// getLodFromAlphaG(size, alphaG) x lodGenerationScale = log2(size alphaG) x scale.
float reflection_lod(float cube_size, float alpha_g, float lod_generation_scale);
// fresnelSchlickGGX(VdotH, R0, R90) (pbrBRDFFunctions.fx).
float fresnel_schlick_ggx(float v_dot_h, float r0, float r90);

// The clear coat block (clearcoatBlock, IBL part) for a coat of intensity c and n.v (absEps'd), from
// the BRDF lookup at (n.v, clearCoatRoughness), x and y its first two channels:
// - conservation = 1 - c fresnelSchlickGGX(n.v, 0.04, 1): what the base's irradiance, its radiance
//   (pbrBlockReflectance.fx: cumulativeSpecularEnvironmentReflectance) and the sheen's radiance are
//   multiplied by (pbrBlockFinalLitComponents.fx);
// - coat_reflectance = c getReflectanceFromBRDFLookup(0.04, brdf) = c mix(x, y, 0.04)
//   (BRDF_V_HEIGHT_CORRELATED): the coat's radiance (the reflection texture at the coat's alphaG)
//   is multiplied by it, finalClearCoatRadianceScaled (no energy conservation factor: Babylon.js
//   applies energyConservationFactorClearCoat to its punctual lights' coat only).
struct ClearCoat {
  float conservation = 1.0f;
  float coat_reflectance = 0.0f;
};
ClearCoat clear_coat(float intensity, float n_dot_v, float brdf_x, float brdf_y);

// The sheen block (sheenBlock with SHEEN_ROUGHNESS and SHEEN_ALBEDOSCALING, ENVIRONMENTBRDF) for a
// sheen colour and intensity, from the BRDF lookup's blue channel at (n.v, sheenRoughness):
// - reflectance[k] = getSheenReflectanceFromBRDFLookup(sheenColor, brdf) = intensity color[k] b,
//   the weight of the reflection texture sampled at the sheen's alphaG (finalSheenRadianceScaled);
// - albedo_scaling = 1 - intensity max3(intensity color) b: what the base's irradiance (through
//   surfaceAlbedo) and radiance are multiplied by; not clamped (Babylon.js clamps only the final
//   colour at 0, pbrBlockFinalColorComposition.fx).
struct Sheen {
  float reflectance[3] = {0.0f, 0.0f, 0.0f};
  float albedo_scaling = 1.0f;
};
Sheen sheen(const float color[3], float intensity, float brdf_b);

// The shading row's functions (splitsum.cpp), shared with the `gltf` target.
using preview::BaseInputs;
using preview::SplitSumSampler;

// Babylon.js's renderer (sphericalPolynomial.ts): the harmonics its shader evaluates from a spherical
// polynomial p (x, y, z, xx, yy, zz, yz, zx, xy; 9 x RGB), SphericalHarmonics.FromPolynomial then
// preScaleForRendering.
std::vector<double> prescaled_harmonics(const std::vector<double>& p);
// SphericalPolynomial.FromHarmonics (updateFromHarmonics) of harmonics h (9 x RGB).
std::vector<double> polynomial_from(const std::vector<double>& h);
// pbrBlockReflection.fx sampleReflectionTexture at reflectionCoords d and alphaG: the chain at getLodFromAlphaG x
// lodGenerationScale, decoded to linear (toLinearSpace where the texture is in gamma space).
void sample_reflection_texture(const SplitSumSampler& s, const Vec3& d, float average_slope, float out[3]);
// The base: pbrBlockReflection.fx reflectionBlock (the sample, mixed with the irradiance by alphaG),
// pbrBlockReflectivity.fx and pbrBlockFinalLitComponents.fx (finalRadianceScaled + finalIrradiance).
void reflection_block(const SplitSumSampler& s, const PreviewMaterial& m, const BaseInputs& in, float out[3]);
// pbrBlockSheen.fx sheenBlock and pbrBlockClearcoat.fx clearcoatBlock, IBL part, over the shaded base.
void sheen_block(const SplitSumSampler& s, const Vec3& n, const Vec3& v, const PreviewMaterial& m, float aa_alpha_g,
                 float out[3]);
void clearcoat_block(const SplitSumSampler& s, const Vec3& n, const Vec3& v, const PreviewMaterial& m, float aa_alpha_g,
                     float out[3]);
// The sheen block renders from a bake with a charlie table; what it does, for the notes.
bool renders_sheen(const SplitSumSampler& s);
std::string sheen_note(const SplitSumSampler& s);
// The steps of PBRMaterial's IBL for the JSON; `loader`: what the material's and the light's loader adds to
// them (the .env's PBRMaterial: its own texts below; the glTF loader: gltf/splitsum.cpp).
struct LoaderSteps {
  std::string frame, alpha_g_suffix, lod_source, sample_suffix, irradiance_source;
};
Metadata pbr_steps(const SplitSumSampler& s, const LoaderSteps& loader);

}  // namespace brdfbake::detail::engines::babylon
