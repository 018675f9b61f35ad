// The `babylon` target's descriptor: what Babylon.js loads from a .env (EnvironmentTextureTools), and how
// (docs/ENGINES.md).
#include "engines/babylon/babylon.hpp"
#include "engines/write_common.hpp"

namespace brdfbake::detail::engines::babylon {

namespace {

const char* const kHeldToBabylon =
    "Babylon.js 8.46.2 (the gradio 6.31.0 wheel; headless Chromium, WebGL2 on SwiftShader) renders the .env "
    "within 0.11 % median, 0.51 % p95 of the split-sum render over the spheres of roughness >= 0.1 (mirrors "
    "0.16 % / 4.3 %): venice_sunset_1k, 480 x 240, tests/python/test_engine_babylon.py";
}  // namespace

EngineSettings settings() {
  EngineSettings s;
  s.target = EngineTarget::Babylon;
  const std::string faces = opengl_faces_text();
  s.engine = "Babylon.js .env (EnvironmentTextureTools, CubeTexture)";
  s.held_to = kHeldToBabylon;
  s.held_to_short = "Babylon.js 8.46.2 renders it within 0.11 % median, 0.51 % p95 (roughness >= 0.1; venice)";
  s.schedule = RoughnessSchedule::Babylon;
  s.schedule_source =
      "Babylon.js HDRFiltering: alphaG = 2^(lod / lodGenerationScale) / width (0 at lod 0), "
      "lodGenerationScale 0.8; pbrBlockReflection: lod = log2(width alphaG) lodGenerationScale, "
      "alphaG = roughness^2 + MINIMUMVARIANCE (0.0005)";
  s.lod_formula = schedule_lod_formula(s.schedule);
  s.size = 256;
  s.min_size = 1;  // .env stores the full chain (CreateImageDataArrayBufferViews checks it)
  s.power_of_two = true;
  s.pixel = PixelType::F32;
  s.pixel_format = "PNG 8-bit RGBA holding RGBD, one per face and level";
  s.sh_convention = ShConvention::BabylonPolynomial;
  s.sh_description =
      "manifest irradiance: Babylon's spherical polynomial (x, y, z, xx, yy, zz, yz, zx, xy) = "
      "SphericalPolynomial.FromHarmonics of the irradiance SH / pi, with Babylon's constants";
  s.orientation = faces + "; each face PNG bottom row first (Babylon.js reads row 0 as the face's last row)";
  s.files = {"NAME.env"};
  return s;
}

}  // namespace brdfbake::detail::engines::babylon

namespace brdfbake::detail::engines {

const TargetDef& babylon_target() {
  static const TargetDef def = [] {
    TargetDef d{EngineTarget::Babylon, "babylon", babylon::settings, babylon::create_env_texture,
                babylon::upload_env_levels};
    d.read_sheen_chain = nullptr;
    d.engine_dfg = nullptr;
    d.shading = babylon::shading;
    d.needs_sh = true;
    d.astc = false;
    return d;
  }();
  return def;
}

}  // namespace brdfbake::detail::engines
