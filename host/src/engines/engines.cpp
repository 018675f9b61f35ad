// Engine targets: the descriptor of each engine (schedule, sizes, format, SH convention, files) and
// the SH conversions into each engine's convention. The writers are in engine_writers.cpp.
#include "brdfbake/engines.hpp"

#include <algorithm>
#include <cmath>

#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"

namespace brdfbake {
namespace {

using brdfbake::math::kPi;

struct TargetName {
  EngineTarget target;
  const char* name;
};
constexpr TargetName kTargetNames[] = {{EngineTarget::Generic, "generic"},
                                       {EngineTarget::Filament, "filament"},
                                       {EngineTarget::Gltf, "gltf"},
                                       {EngineTarget::Babylon, "babylon"},
                                       {EngineTarget::KhronosViewer, "khronos-viewer"}};

// The basis constants of the real SH of bands 0..2 (docs/CONVENTIONS.md, without the
// Condon-Shortley phase): Y_k = kShBasis[k] poly_k(x, y, z), poly = 1, y, z, x, xy, yz, 3z^2 - 1,
// xz, x^2 - y^2.
const double kShBasis[9] = {0.28209479177387814, 0.4886025119029199, 0.4886025119029199,
                            0.4886025119029199,  1.0925484305920792, 1.0925484305920792,
                            0.31539156525252005, 1.0925484305920792, 0.5462742152960396};
// The Condon-Shortley sign of Filament's and Babylon's bases relative to ours: they carry
// (-1)^m for m > 0 and the matching sign for m < 0 (Filament CubemapSH::computeShBasis, Babylon
// SH3ylmBasisConstants), i.e. negative for l1-1, l11, l2-1, l21.
const double kCondonShortley[9] = {1, -1, 1, -1, 1, -1, 1, -1, 1};

void check_sh(const ShCoefficients& sh) {
  if (sh.order < 3 || sh.irradiance_over_pi.size() < 27)
    throw Error("engine SH: need at least 3 bands (9 RGB coefficients), have " + std::to_string(sh.order));
  for (size_t i = 0; i < 27; ++i)
    if (!std::isfinite(sh.irradiance_over_pi[i])) throw Error("engine SH: a coefficient is not finite");
}

}  // namespace

EngineTarget engine_target_from_name(const std::string& name) {
  for (const TargetName& t : kTargetNames)
    if (name == t.name) return t.target;
  throw Error("unknown engine target '" + name + "' (expected generic, filament, gltf, babylon or khronos-viewer)");
}

const char* engine_target_name(EngineTarget target) {
  for (const TargetName& t : kTargetNames)
    if (t.target == target) return t.name;
  return "generic";
}

std::vector<std::string> engine_target_names() {
  std::vector<std::string> names;
  for (const TargetName& t : kTargetNames) names.emplace_back(t.name);
  return names;
}

// What each target's split-sum emulation was held to (tests/python/test_engine_*.py measure it; the
// figures are the last measurement, docs/ENGINES.md "Engine truth").
const char* const kHeldToBabylon =
    "Babylon.js 8.46.2 (the gradio 6.31.0 wheel; headless Chromium, WebGL2 on SwiftShader) renders the .env "
    "within 0.11 % median, 0.51 % p95 of the split-sum render over the spheres of roughness >= 0.1 (mirrors "
    "0.16 % / 4.3 %): venice_sunset_1k, 480 x 240, tests/python/test_engine_babylon.py";
const char* const kHeldToGltf =
    "Babylon.js 8.46.2's glTF loader (the gradio 6.31.0 wheel; headless Chromium, WebGL2 on SwiftShader, its "
    "default left-handed scene) renders the light within 0.18 % median, 1.6 % p95 of the split-sum render over "
    "the spheres of roughness >= 0.1 (mirrors 0.40 % / 4.1 %): venice_sunset_1k, 480 x 240, "
    "tests/python/test_engine_babylon.py";
const char* const kHeldToFilament =
    "Filament 1.76 (the open3d-cpu 0.20.0 wheel, Vulkan on Mesa's lavapipe; 8-bit frames merged over exposures) "
    "renders the _ibl.ktx within 0.018 % median, 0.056 % p95 of the split-sum render (venice_sunset_1k and "
    "rooitou_park_1k, 320 x 160, every sphere; the DFG table is Filament's own, held to the one it ships): "
    "tests/python/test_engine_filament.py";
const char* const kHeldToFilamentShort =
    "Filament 1.76 renders it within 0.018 % median, 0.056 % p95 (every sphere; venice, rooitou)";
const char* const kHeldToKhronos =
    "no renderer here runs the glTF-Sample-Viewer: its shader (ibl.glsl at 2c3c5a5) was checked by reading only";

EngineSettings engine_settings(EngineTarget target) {
  EngineSettings s;
  s.target = target;
  const std::string faces =
      "faces +X, -X, +Y, -Y, +Z, -Z (KTX / OpenGL order and orientation, +Y up), row 0 the top row of each "
      "face; texel (i, j) of a face of size S looks along the OpenGL cube table at a = 2 (i + 0.5)/S - 1, "
      "b = 2 (j + 0.5)/S - 1 (docs/CONVENTIONS.md)";
  switch (target) {
    case EngineTarget::Generic:
      s.engine = "brdfbake's own convention";
      s.held_to = "no engine: brdfbake's own runtime convention (docs/CONVENTIONS.md)";
      s.held_to_short = s.held_to;
      s.schedule = RoughnessSchedule::Linear;
      s.schedule_source = "docs/CONVENTIONS.md (the glTF-IBL-Sampler's linear mapping)";
      s.lod_formula = schedule_lod_formula(s.schedule);
      s.pixel = PixelType::F16;
      s.pixel_format = "KTX2 VK_FORMAT_R16G16B16A16_SFLOAT (or ASTC HDR 4x4 / 6x6 SFLOAT blocks)";
      s.sh_convention = ShConvention::IrradianceOverPi;
      s.sh_description =
          "JSON: radiance L_lm and irradiance_over_pi c_lm = (A_l/pi) w_l L_lm, E(n)/pi = sum c_lm Y_lm(n)";
      s.orientation = faces + "; KTXorientation rd";
      s.files = {"NAME_ggx.ktx2", "NAME_sh.json"};
      break;
    case EngineTarget::Filament:
      s.engine = "Filament 1.9 (what cmgen -x DIR -f ktx writes; image::KtxBundle, KtxUtility)";
      s.held_to = kHeldToFilament;
      s.held_to_short = kHeldToFilamentShort;
      s.schedule = RoughnessSchedule::Filament;
      s.schedule_source =
          "cmgen iblRoughnessPrefilter: lodToPerceptualRoughness(l / (L - 1)) = 1 - sqrt(1 - l / (L - 1)); "
          "shader perceptualRoughnessToLod = iblRoughnessOneLevel r (2 - r), iblRoughnessOneLevel = L - 1";
      s.lod_formula = schedule_lod_formula(s.schedule);
      s.size = 256;           // cmgen's IBL_DEFAULT_SIZE
      s.min_size = 16;        // cmgen's IBL_DEFAULT_MIN_LOD_SIZE
      s.power_of_two = true;  // cmgen refuses other sizes
      s.pixel = PixelType::R11G11B10;
      s.pixel_format = "KTX1 GL_R11F_G11F_B10F (glType 0x8C3A as Filament's KtxUtility reads it)";
      s.sh_window = ShWindow::Auto;  // cmgen's default, so that swapping cmgen keeps the look
      s.sh_convention = ShConvention::FilamentPrescaled;
      s.sh_description =
          "KTX1 key \"sh\": 9 lines \"r g b\" (bands 0..2, index l(l+1)+m), each the irradiance SH with the basis "
          "constant and 1/pi folded in (CubemapSH::preprocessSHForShader): E(n)/pi = sh0 + sh1 y + sh2 z + sh3 x + "
          "sh4 xy + sh5 yz + sh6 (3z^2 - 1) + sh7 xz + sh8 (x^2 - y^2); windowed as cmgen does by default "
          "(--sh-window auto: sinc^4 with the widest cutoff that keeps the irradiance non-negative; "
          "--sh-window none gives cmgen --sh-window=no)";
      s.orientation = faces +
                      " (for an equirect source the same cube cmgen makes: its mirrored lat-long "
                      "lookup and its mirrorCubemap cancel); KTXorientation S=r,T=d";
      s.files = {"NAME_ibl.ktx", "NAME_skybox.ktx", "sh.txt"};
      s.skybox = true;
      break;
    case EngineTarget::Gltf:
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
      break;
    case EngineTarget::Babylon:
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
      break;
    case EngineTarget::KhronosViewer:
      s.engine = "Khronos glTF-Sample-Viewer / glTF-IBL-Sampler convention";
      s.held_to = kHeldToKhronos;
      s.held_to_short = "the glTF-Sample-Viewer's ibl.glsl (2c3c5a5), by reading only (no renderer here runs it)";
      s.schedule = RoughnessSchedule::Linear;
      s.schedule_source =
          "glTF-IBL-Sampler: roughness = currentMipLevel / (mipLevelCount - 1); glTF-Sample-Viewer ibl.glsl: "
          "lod = roughness * float(u_MipCount - 1)";
      s.lod_formula = schedule_lod_formula(s.schedule);
      s.size = 256;
      s.min_size = 16;  // the viewer's sampler stops at lowestMipLevel 4 (16x16)
      s.power_of_two = true;
      s.pixel = PixelType::F16;
      s.pixel_format = "KTX2 VK_FORMAT_R16G16B16A16_SFLOAT (or ASTC HDR)";
      s.sh_convention = ShConvention::IrradianceOverPi;
      s.sh_description = "none in the files: diffuse light is the Lambertian cube (E/pi per texel)";
      s.orientation = faces + "; KTXorientation rd";
      s.files = {"NAME_ggx.ktx2", "NAME_lambertian.ktx2", "NAME_charlie.ktx2 (with a Charlie chain)"};
      break;
  }
  return s;
}

std::array<Rgb3, 9> filament_sh(const ShCoefficients& sh) {
  check_sh(sh);
  // Filament: c_k = A_k^F (A_l / pi) L_k^F with Y_k^F = A_k^F poly_k its signed basis, and
  // L_k^F = s_k L_k (s the Condon-Shortley sign), A_k^F = s_k kShBasis[k]: the signs cancel and
  // c_k = kShBasis[k] (A_l / pi) L_k = kShBasis[k] irradiance_over_pi[k] (windowed alike).
  std::array<Rgb3, 9> out{};
  for (size_t k = 0; k < 9; ++k)
    for (size_t c = 0; c < 3; ++c) out[k][c] = kShBasis[k] * sh.irradiance_over_pi[3 * k + c];
  return out;
}

std::array<Rgb3, 9> gltf_irradiance_coefficients(const ShCoefficients& sh) {
  check_sh(sh);
  // E_lm in the Condon-Shortley basis: s_k A_l w_l L_k = s_k pi irradiance_over_pi[k].
  std::array<Rgb3, 9> out{};
  for (size_t k = 0; k < 9; ++k)
    for (size_t c = 0; c < 3; ++c) out[k][c] = kCondonShortley[k] * kPi * sh.irradiance_over_pi[3 * k + c];
  return out;
}

std::array<Rgb3, 9> babylon_polynomial(const ShCoefficients& sh) {
  check_sh(sh);
  // Babylon's cube pipeline (CubeMapToSphericalPolynomialTools): radiance SH in its basis ->
  // convertIncidentRadianceToIrradiance (x A_l) -> convertIrradianceToLambertianRadiance (/ pi)
  // -> SphericalPolynomial.FromHarmonics, whose constants (1.02333, 0.886277, 0.247708, 0.429043,
  // 0.495417, 0.858086; the first the product (2 pi / 3) Y_1, and so on) and final / pi are
  // reproduced exactly, 0.886277 included.
  std::array<Rgb3, 9> h{};
  for (size_t k = 0; k < 9; ++k)
    for (size_t c = 0; c < 3; ++c) h[k][c] = kCondonShortley[k] * sh.irradiance_over_pi[3 * k + c];
  std::array<Rgb3, 9> p{};
  for (size_t c = 0; c < 3; ++c) {
    const double l00 = h[0][c], l1m1 = h[1][c], l10 = h[2][c], l11 = h[3][c], l2m2 = h[4][c], l2m1 = h[5][c],
                 l20 = h[6][c], l21 = h[7][c], l22 = h[8][c];
    p[0][c] = -1.02333 * l11;                                    // x
    p[1][c] = -1.02333 * l1m1;                                   // y
    p[2][c] = 1.02333 * l10;                                     // z
    p[3][c] = 0.886277 * l00 - 0.247708 * l20 + 0.429043 * l22;  // xx
    p[4][c] = 0.886277 * l00 - 0.247708 * l20 - 0.429043 * l22;  // yy
    p[5][c] = 0.886277 * l00 + 0.495417 * l20;                   // zz
    p[6][c] = -0.858086 * l2m1;                                  // yz
    p[7][c] = -0.858086 * l21;                                   // zx
    p[8][c] = 0.858086 * l2m2;                                   // xy
    for (size_t k = 0; k < 9; ++k) p[k][c] /= kPi;
  }
  return p;
}

}  // namespace brdfbake
