// The `gltf` target's descriptor: what Babylon.js's glTF loader loads from an EXT_lights_image_based light, and how
// (docs/ENGINES.md).
#include "engines/gltf/gltf.hpp"
#include "engines/write_common.hpp"

namespace brdfbake::detail::engines::gltf {

namespace {

const char* const kHeldToGltf =
    "Babylon.js 8.46.2's glTF loader (the gradio 6.31.0 wheel; headless Chromium, WebGL2 on SwiftShader, its "
    "default left-handed scene) renders the light within 0.18 % median, 1.6 % p95 of the split-sum render over "
    "the spheres of roughness >= 0.1 (mirrors 0.40 % / 4.1 %): venice_sunset_1k, 480 x 240, "
    "tests/python/test_engine_babylon.py";
}  // namespace

EngineSettings settings() {
  EngineSettings s;
  s.target = EngineTarget::Gltf;
  const std::string faces = opengl_faces_text();
  s.engine = "glTF 2.0 EXT_lights_image_based (loaded by Babylon.js's glTF loader)";
  s.held_to = kHeldToGltf;
  s.held_to_short =
      "Babylon.js 8.46.2's glTF loader renders it within 0.18 % median, 1.6 % p95 (roughness >= 0.1; venice)";
  s.schedule = RoughnessSchedule::Linear;
  s.schedule_source =
      "EXT_lights_image_based README: \"The various mip levels evenly map to roughness values from 0 to 1\"";
  s.lod_formula = schedule_lod_formula(s.schedule) +
                  " (the extension's text; Babylon.js's loader instead sets lodGenerationScale = (N - 1) / "
                  "log2(specularImageSize) and looks up lod = scale log2(size (r^2 + 0.0005)))";
  s.size = 256;
  s.min_size = 16;        // the README: the lowest mip "(say, 16x16)" holds roughness 1
  s.power_of_two = true;  // the README: square, power-of-two images
  s.pixel = PixelType::F32;
  s.pixel_format = "PNG 8-bit RGBA holding RGBD (4-channel PNGs are RGBD per the extension)";
  s.sh_convention = ShConvention::GltfIrradiance;
  s.sh_description =
      "irradianceCoefficients: 9 x RGB E_lm = A_l w_l L_lm in the SH basis with the Condon-Shortley phase "
      "(the Babylon.js loader divides by pi twice on the way to its polynomial, as for its own cubes)";
  s.orientation = faces +
                  "; each face PNG bottom row first (Babylon.js reads row 0 as the face's last row); the cube "
                  "mirrored in x for Babylon.js's default left-handed scene (rotation identity), or as it is with "
                  "rotation (0, 1, 0, 0) for a right-handed one";
  s.files = {"NAME.gltf", "NAME_specular_<level>_<px|nx|py|ny|pz|nz>.png"};
  return s;
}

}  // namespace brdfbake::detail::engines::gltf

namespace brdfbake::detail::engines {

const TargetDef& gltf_target() {
  static const TargetDef def = [] {
    TargetDef d{EngineTarget::Gltf, "gltf", gltf::settings, gltf::ext_lights_image_based, gltf::load_light};
    d.read_sheen_chain = nullptr;
    d.engine_dfg = nullptr;
    d.shading = gltf::shading;
    d.needs_sh = true;
    d.astc = false;
    return d;
  }();
  return def;
}

}  // namespace brdfbake::detail::engines
