// The `khronos-viewer` target's descriptor: what the glTF-Sample-Viewer loads (the glTF-IBL-Sampler convention), and
// how (docs/ENGINES.md).
#include "engines/khronos_viewer/khronos_viewer.hpp"
#include "engines/write_common.hpp"

namespace brdfbake::detail::engines::khronos_viewer {

namespace {

const char* const kHeldToKhronos =
    "no renderer here runs the glTF-Sample-Viewer: its shader (ibl.glsl at 2c3c5a5) was checked by reading only";
}  // namespace

EngineSettings settings() {
  EngineSettings s;
  s.target = EngineTarget::KhronosViewer;
  const std::string faces = opengl_faces_text();
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
  return s;
}

}  // namespace brdfbake::detail::engines::khronos_viewer

namespace brdfbake::detail::engines {

const TargetDef& khronos_viewer_target() {
  static const TargetDef def = [] {
    TargetDef d{EngineTarget::KhronosViewer, "khronos-viewer", khronos_viewer::settings,
                khronos_viewer::ibl_sampler_ktx2, khronos_viewer::read_ggx_and_lambertian};
    d.read_sheen_chain = khronos_viewer::read_charlie;
    d.engine_dfg = nullptr;
    d.shading = khronos_viewer::shading;
    d.needs_sh = false;
    d.astc = true;
    return d;
  }();
  return def;
}

}  // namespace brdfbake::detail::engines
