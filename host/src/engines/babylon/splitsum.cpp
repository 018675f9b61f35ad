// The `babylon` target's split-sum shading, Babylon.js 8.46.2's PBRMaterial on the .env's cube (splitsum.hpp), as
// the registry's shading row (splitsum_sampling.hpp); the `gltf` target shades with the same functions.
#include "engines/babylon/splitsum.hpp"

#include <algorithm>
#include <cmath>

#include "engines/babylon/babylon.hpp"

namespace brdfbake::detail::engines::babylon {

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

// The polynomials' harmonics, l00, l1-1, l10, l11, l2-2, l2-1, l20, l21, l22 (times SH3ylmBasisConstants,
// which carry the Condon-Shortley signs).
std::vector<double> prescaled_harmonics(const std::vector<double>& p) {
  auto at = [&](int k, int c) { return p[size_t(3 * k + c)]; };
  const double basis[9] = {
      std::sqrt(1.0 / (4.0 * M_PI)),  -std::sqrt(3.0 / (4.0 * M_PI)),  std::sqrt(3.0 / (4.0 * M_PI)),
      -std::sqrt(3.0 / (4.0 * M_PI)), std::sqrt(15.0 / (4.0 * M_PI)),  -std::sqrt(15.0 / (4.0 * M_PI)),
      std::sqrt(5.0 / (16.0 * M_PI)), -std::sqrt(15.0 / (4.0 * M_PI)), std::sqrt(15.0 / (16.0 * M_PI))};
  std::vector<double> h(27);
  for (int c = 0; c < 3; ++c) {
    const double x = at(0, c), y = at(1, c), z = at(2, c), xx = at(3, c), yy = at(4, c), zz = at(5, c), yz = at(6, c),
                 zx = at(7, c), xy = at(8, c);
    const double l[9] = {xx * 0.376127 + yy * 0.376127 + zz * 0.376126,
                         -y * 0.977204,
                         z * 0.977204,
                         -x * 0.977204,
                         xy * 1.16538,
                         -yz * 1.16538,
                         zz * 1.34567 - xx * 0.672834 - yy * 0.672834,
                         -zx * 1.16538,
                         xx * 1.16538 - yy * 1.16538};
    for (int k = 0; k < 9; ++k) h[size_t(3 * k + c)] = l[k] * M_PI * basis[k];
  }
  return h;
}

std::vector<double> polynomial_from(const std::vector<double>& h) {
  std::vector<double> p(27);
  for (int c = 0; c < 3; ++c) {
    auto at = [&](int k) { return h[size_t(3 * k + c)]; };
    const double v[9] = {-1.02333 * at(3),
                         -1.02333 * at(1),
                         1.02333 * at(2),
                         0.886277 * at(0) - 0.247708 * at(6) + 0.429043 * at(8),
                         0.886277 * at(0) - 0.247708 * at(6) - 0.429043 * at(8),
                         0.886277 * at(0) + 0.495417 * at(6),
                         -0.858086 * at(5),
                         -0.858086 * at(7),
                         0.858086 * at(4)};
    for (int k = 0; k < 9; ++k) p[size_t(3 * k + c)] = v[k] / M_PI;
  }
  return p;
}

void sample_reflection_texture(const SplitSumSampler& s, const Vec3& d, float average_slope, float out[3]) {
  s.reflection(d, reflection_lod(float(s.files.specular.size), average_slope, float(s.files.lod_scale)), out);
}

void reflection_block(const SplitSumSampler& s, const PreviewMaterial& m, const BaseInputs& in, float out[3]) {
  const float nx = in.nx, ny = in.ny, nz = in.nz, vx = in.vx, vy = in.vy, vz = in.vz, dot_nv = in.dot_nv;
  const float* irr = in.irr;
  float f0[3] = {in.f0[0], in.f0[1], in.f0[2]};
  const float specular = in.specular;
  // pbrBlockGeometryInfo: NdotV = absEps(dot(n, v)) = |NdotV| + 1e-7;
  // alphaG = convertRoughnessToAverageSlope(roughness) = roughness^2 + MINIMUMVARIANCE (0.0005),
  // + AARoughnessFactors.y under SPECULARAA (getAARoughnessFactors: 0.75 sqrt(slopeSquare))
  const float nv = std::fabs(dot_nv) + 1e-7f, r = float(m.roughness);
  const float alpha_g = r * r + 0.0005f + in.aa_alpha_g;
  // sampleReflectionTexture: lod = getLodFromAlphaG(size, alphaG) * lodGenerationScale + offset
  const float lod = std::log2(float(s.files.specular.size) * alpha_g) * float(s.files.lod_scale);
  const Vec3 refl{double(2.0f * dot_nv * nx - vx), double(2.0f * dot_nv * ny - vy), double(2.0f * dot_nv * nz - vz)};
  float light[3], bias = 0, albedo = 0;
  s.reflection(refl, lod, light);
  // reflectionBlock, MIX_IBL_RADIANCE_WITH_IRRADIANCE (PBRBRDFConfiguration's default since 7.45):
  // environmentRadiance = mix(environmentRadiance, environmentIrradiance, alphaG)
  if (s.options.babylon_mix_ibl_radiance_with_irradiance)
    for (int c = 0; c < 3; ++c) light[c] = preview::mixf(light[c], irr[c], alpha_g);
  s.dfg(nv, r, &bias, &albedo);  // getBRDFLookup(NdotV, roughness)
  // pbrBlockReflectivity.fx, LEGACY_SPECULAR_ENERGY_CONSERVATION (PBRBRDFConfiguration's default in
  // 8.46.2), metallic workflow: dielectricF0 = reflectivityColor.a (((ior - 1) / (ior + 1))^2) x
  // specularWeight (specularFactor); surfaceAlbedo = baseColor (1 - dielectricF0 surfaceReflectivityColor)
  // (1 - metallic); reflectanceF90 = colorReflectanceF90 = specularWeight
  const float f0_ior = float(std::pow((m.ior - 1.0) / (m.ior + 1.0), 2.0));
  const float spec_color[3] = {float(m.specular_color.r), float(m.specular_color.g), float(m.specular_color.b)};
  const float base[3] = {float(m.base_color.r), float(m.base_color.g), float(m.base_color.b)};
  const float r90 = specular;
  // pbrBlockIridescence.fx iridescenceBlock (KHR_materials_iridescence.ts: intensity, IOR, maximum
  // thickness): specularEnvironmentR0 = mix(R0, evalIridescence(1, IOR, NdotV, thickness, R0), intensity)
  preview::iridescent_f0(m, nv, f0);
  for (int c = 0; c < 3; ++c) {
    // getReflectanceFromBRDFLookup (height-correlated, metallic workflow): (R90 - R0) x + R0 y;
    // getEnergyConservationFactor: 1 + R0 (1 / y - 1)
    const float reflectance = (r90 - f0[c]) * bias + f0[c] * albedo;
    const float k = 1.0f + f0[c] * (1.0f / albedo - 1.0f);
    const float surface_albedo = base[c] * (1.0f - f0_ior * specular * spec_color[c]) * (1.0f - float(m.metallic));
    out[c] = light[c] * reflectance * k + irr[c] * surface_albedo;  // finalRadianceScaled + finalIrradiance
  }
}

void sheen_block(const SplitSumSampler& s, const Vec3& nd, const Vec3& vd, const PreviewMaterial& m, float aa_alpha_g,
                 float out[3]) {
  const float nx = float(nd.x), ny = float(nd.y), nz = float(nd.z), vx = float(vd.x), vy = float(vd.y),
              vz = float(vd.z);
  const float dot_nv = nx * vx + ny * vy + nz * vz;
  const Vec3 refl{double(2.0f * dot_nv * nx - vx), double(2.0f * dot_nv * ny - vy), double(2.0f * dot_nv * nz - vz)};
  const float c[3] = {float(m.sheen_color.r), float(m.sheen_color.g), float(m.sheen_color.b)};
  float light[3];
  // pbrBlockSheen.fx, sheenBlock (SHEEN_ROUGHNESS, SHEEN_ALBEDOSCALING; sheen.intensity 1 from the
  // glTF loader): the reflection texture at reflectionCoords (the base's) and the sheen's alphaG,
  // times sheenColor x environmentSheenBrdf.b, environmentSheenBrdf = getBRDFLookup(NdotV,
  // sheenRoughness) (NdotV the base's absEps); pbrBlockFinalLitComponents.fx: surfaceAlbedo and
  // finalRadianceScaled times sheenAlbedoScaling. b is the charlie table's E (sheen_note)
  const float nv = abs_eps(dot_nv), r = float(m.sheen_roughness);
  // sheenAlphaG += AARoughnessFactors.y under SPECULARAA
  sample_reflection_texture(s, refl, alpha_g(r) + aa_alpha_g, light);
  const Sheen sh = sheen(c, 1.0f, s.charlie(nv, r));
  for (int k = 0; k < 3; ++k) out[k] = out[k] * sh.albedo_scaling + light[k] * sh.reflectance[k];
}

void clearcoat_block(const SplitSumSampler& s, const Vec3& nd, const Vec3& vd, const PreviewMaterial& m,
                     float aa_alpha_g, float out[3]) {
  // KHR_materials_clearcoat with the geometric normal (the sphere's)
  const float nx = float(nd.x), ny = float(nd.y), nz = float(nd.z), vx = float(vd.x), vy = float(vd.y),
              vz = float(vd.z);
  const float dot_nv = nx * vx + ny * vy + nz * vz;
  const Vec3 refl{double(2.0f * dot_nv * nx - vx), double(2.0f * dot_nv * ny - vy), double(2.0f * dot_nv * nz - vz)};
  const float cc = float(m.clearcoat);
  float light[3];
  // pbrBlockClearcoat.fx, clearcoatBlock (the glTF loader: remapF0OnInterfaceChange false, so the
  // base's R0 stays; no tint, no bump: clearCoatNormalW = the geometric normal): the reflection
  // texture at the coat's alphaG along computeReflectionCoords (the base's direction), times
  // getReflectanceFromBRDFLookup(0.04, getBRDFLookup(clearCoatNdotV, clearCoatRoughness)) x
  // intensity; the base (irradiance, radiance) and the sheen's radiance times conservationFactor
  // (pbrBlockReflectance.fx, pbrBlockFinalLitComponents.fx)
  const float nv = abs_eps(dot_nv), r = float(m.clearcoat_roughness);
  // clearCoatAlphaG += clearCoatAARoughnessFactors.y under SPECULARAA (the same normal here)
  sample_reflection_texture(s, refl, alpha_g(r) + aa_alpha_g, light);
  float x = 0, y = 0;
  s.dfg(nv, r, &x, &y);  // height-correlated: (bias, albedo), as the base's lookup
  const ClearCoat k = clear_coat(cc, nv, x, y);
  for (int c = 0; c < 3; ++c) out[c] = out[c] * k.conservation + light[c] * k.coat_reflectance;
}

bool renders_sheen(const SplitSumSampler& s) { return s.files.charlie.width > 0; }

std::string sheen_note(const SplitSumSampler& s) {
  return "KHR_materials_sheen: in the split-sum render, Babylon.js's sheen block (pbrBlockSheen.fx, the glTF "
         "loader's albedoScaling): the reflection texture at getLodFromAlphaG(sheenRoughness^2 + 0.0005) x "
         "sheenColor x b, the base x 1 - max(sheenColor) b, b = the BRDF lookup's sheen channel at (n.v, "
         "sheenRoughness), here E(n.v, sheenRoughness) of " +
         preview::file_name(s.files.charlie_file) + " (" +
         (s.files.charlie_visibility.empty() ? std::string("its") : s.files.charlie_visibility) +
         " visibility; Babylon.js's own BRDF texture's blue channel integrates Ashikhmin's, 1 / (4 (n.l + n.v - "
         "n.l n.v)), "
         "which a charlie table of sheen_visibility neubelt holds)";
}

Metadata pbr_steps(const SplitSumSampler& s, const LoaderSteps& loader) {
  return {
      {"engine", "Babylon.js 8.46.2 defaults (PBRMaterial; the glTF loader's materials for gltf)"},
      {"frame", loader.frame},
      {"alpha_g", "convertRoughnessToAverageSlope: roughness^2 + 0.0005" + loader.alpha_g_suffix},
      {"lod", "getLodFromAlphaG: log2(size alphaG) x lodGenerationScale " + std::to_string(s.files.lod_scale) +
                  loader.lod_source + " (pbrBlockReflection.fx, sampleReflectionTexture)"},
      {"specular_sample", s.cube_text() +
                              ", faces read bottom row first, RGBD expanded to half float (environmentTextureTools.ts, "
                              "_UploadLevelsAsync)" +
                              loader.sample_suffix},
      {"mix_ibl_radiance_with_irradiance",
       s.options.babylon_mix_ibl_radiance_with_irradiance
           ? "on (PBRBRDFConfiguration.DEFAULT_MIX_IBL_RADIANCE_WITH_IRRADIANCE): environmentRadiance = "
             "mix(environmentRadiance, environmentIrradiance, alphaG) (reflectionBlock)"
           : "off (--no-mix-ibl-radiance-with-irradiance)"},
      {"dfg", s.lut_text() + " (pbrBRDFFunctions.fx, getBRDFLookup(NdotV = |n.v| + 1e-7, roughness))"},
      {"specular",
       "getReflectanceFromBRDFLookup: (R90 - R0) x + R0 y, R90 = specularWeight (specularFactor: "
       "LEGACY_SPECULAR_ENERGY_CONSERVATION's reflectanceF90), x getEnergyConservationFactor 1 + R0 (1 / y - 1) "
       "(pbrBlockFinalLitComponents.fx)"},
      {"diffuse", "surfaceAlbedo x environmentIrradiance (" + loader.irradiance_source +
                      ", computeEnvironmentIrradiance); surfaceAlbedo = baseColor (1 - dielectricF0 "
                      "specularColor) (1 - metallic), dielectricF0 = ((ior - 1) / (ior + 1))^2 specularFactor "
                      "(LEGACY_SPECULAR_ENERGY_CONSERVATION, PBRBRDFConfiguration's default in 8.46.2)"}};
}

namespace {

void upload_env_harmonics(SplitSumSampler& s) {
  // Babylon.js evaluates harmonics pre-scaled from the .env's spherical polynomial
  if (s.files.diffuse == preview::DiffuseSource::BabylonPolynomial) s.harmonics = prescaled_harmonics(s.files.sh);
}

Metadata env_steps(const SplitSumSampler& s) {
  LoaderSteps loader;
  loader.frame = "the .env's cube as stored";
  loader.lod_source = " (the .env's)";
  loader.irradiance_source = "the .env's spherical polynomial";
  return pbr_steps(s, loader);
}

}  // namespace

const preview::SplitSumShading& shading() {
  static const preview::SplitSumShading row = [] {
    preview::SplitSumShading r;
    r.prepare = upload_env_harmonics;
    r.base = reflection_block;
    r.sheen = sheen_block;
    r.coat = clearcoat_block;
    r.renders_sheen = renders_sheen;
    r.sheen_note = sheen_note;
    r.steps = env_steps;
    r.clamp_at_zero = true;  // pbrBlockFinalColorComposition.fx: max(finalColor, 0)
    return r;
  }();
  return row;
}

}  // namespace brdfbake::detail::engines::babylon
