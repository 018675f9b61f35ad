// The `gltf` target's split-sum shading: Babylon.js 8.46.2's glTF loader (EXT_lights_image_based.ts,
// glTFLoader.ts) and the PBRMaterial it makes, which shades as the `babylon` target's (babylon/splitsum.hpp) with
// what the loader changes: its RawCubeTexture (gamma space, zero levels past the file's) and specular
// anti-aliasing. The registry's shading row (splitsum_sampling.hpp).
#include "engines/babylon/splitsum.hpp"

#include <cmath>

#include "engines/gltf/gltf.hpp"

namespace brdfbake::detail::engines::gltf {

using preview::SplitSumSampler;

namespace {

void load_light_texture(SplitSumSampler& s) {
  // Babylon.js 8.46.2's glTF loader (EXT_lights_image_based.ts): a RawCubeTexture, whose gammaSpace
  // stays true, so the PBR shader raises every reflection sample to 2.2 (GAMMAREFLECTION); and
  // `enableSpecularAntiAliasing = true` on every material it makes (glTFLoader.ts, _createDefaultMaterial)
  s.reflection_gamma = true;
  s.specular_aa = true;
  // Babylon.js evaluates harmonics pre-scaled from the polynomial its glTF loader makes of
  // irradianceCoefficients (EXT_lights_image_based.ts: FromArray, convertIrradianceToLambertianRadiance,
  // SphericalPolynomial.FromHarmonics).
  if (s.files.diffuse == preview::DiffuseSource::GltfSh) {
    std::vector<double> lambertian = s.files.sh;
    for (double& v : lambertian) v /= M_PI;
    s.harmonics = babylon::prescaled_harmonics(babylon::polynomial_from(lambertian));
  }
  // EXT_lights_image_based.ts's RawCubeTexture has log2(specularImageSize) + 1 levels and
  // _UploadLevelsAsync fills those beyond the file's specularImages with zeros: a LOD past the last
  // level (alphaG above 1 with specular anti-aliasing) blends towards black
  const int full = int(std::lround(std::log2(double(s.files.specular.size)))) + 1;
  for (int l = s.files.specular.level_count(); l < full; ++l) {
    preview::PaddedLevel z;
    z.size = s.files.specular.level_size(l);
    z.rgb.assign(6 * size_t(z.size + 2) * size_t(z.size + 2) * 3, 0.0f);
    s.levels.push_back(std::move(z));
  }
}

Metadata loader_steps(const SplitSumSampler& s) {
  babylon::LoaderSteps loader;
  loader.frame = std::string("EXT_lights_image_based in Babylon.js's ") +
                 (s.files.gltf_scene == GltfScene::LeftHanded
                      ? "default left-handed scene: the loader mirrors the glTF content in x, not the "
                        "cube (the file stores it mirrored, rotation identity)"
                      : "right-handed scene: every cube turned 180 degrees about +Y, undone by the "
                        "light's rotation (0, 1, 0, 0)");
  loader.alpha_g_suffix =
      " + 0.75 sqrt(max(|dFdx n|^2, |dFdy n|^2)) (SPECULARAA: the loader's "
      "enableSpecularAntiAliasing; coarse derivatives of the analytic normal over each 2 x "
      "2 pixel quad)";
  loader.lod_source = " ((N - 1) / log2 size, EXT_lights_image_based.ts)";
  loader.sample_suffix =
      ", then toLinearSpace (x^2.2): the loader's RawCubeTexture keeps gammaSpace true "
      "(GAMMAREFLECTION), so every reflection sample is decoded a second time";
  loader.irradiance_source = "irradianceCoefficients / pi, SphericalHarmonics";
  return babylon::pbr_steps(s, loader);
}

}  // namespace

const preview::SplitSumShading& shading() {
  static const preview::SplitSumShading row = [] {
    preview::SplitSumShading r;
    r.prepare = load_light_texture;
    r.base = babylon::reflection_block;
    r.sheen = babylon::sheen_block;
    r.coat = babylon::clearcoat_block;
    r.renders_sheen = babylon::renders_sheen;
    r.sheen_note = babylon::sheen_note;
    r.steps = loader_steps;
    r.clamp_at_zero = true;  // pbrBlockFinalColorComposition.fx: max(finalColor, 0)
    return r;
  }();
  return row;
}

}  // namespace brdfbake::detail::engines::gltf
