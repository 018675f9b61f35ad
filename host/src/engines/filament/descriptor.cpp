// The `filament` target's descriptor: what Filament loads (what cmgen -x DIR -f ktx writes, KtxUtility reads), and how
// (docs/ENGINES.md).
#include "engines/filament/filament.hpp"
#include "engines/write_common.hpp"

namespace brdfbake::detail::engines::filament {

namespace {

const char* const kHeldToFilament =
    "Filament 1.76 (the open3d-cpu 0.20.0 wheel, Vulkan on Mesa's lavapipe; 8-bit frames merged over exposures) "
    "renders the _ibl.ktx within 0.018 % median, 0.056 % p95 of the split-sum render (venice_sunset_1k and "
    "rooitou_park_1k, 320 x 160, every sphere; the DFG table is Filament's own, held to the one it ships): "
    "tests/python/test_engine_filament.py";
const char* const kHeldToFilamentShort =
    "Filament 1.76 renders it within 0.018 % median, 0.056 % p95 (every sphere; venice, rooitou)";
}  // namespace

EngineSettings settings() {
  EngineSettings s;
  s.target = EngineTarget::Filament;
  const std::string faces = opengl_faces_text();
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
  s.reads_dfg_tables = false;  // light_iblDFG, built into Filament (filament_dfg.hpp)
  s.reads_charlie = false;     // evaluateSheenIBL: the GGX chain and light_iblDFG's z
  return s;
}

}  // namespace brdfbake::detail::engines::filament

namespace brdfbake::detail::engines {

const TargetDef& filament_target() {
  static const TargetDef def = [] {
    TargetDef d{EngineTarget::Filament, "filament", filament::settings, filament::cmgen_ktx,
                filament::create_indirect_light};
    d.read_sheen_chain = nullptr;
    d.engine_dfg = filament::light_ibl_dfg;
    d.shading = filament::shading;
    d.needs_sh = true;
    d.astc = false;
    return d;
  }();
  return def;
}

}  // namespace brdfbake::detail::engines
