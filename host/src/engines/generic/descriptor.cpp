// The `generic` target's descriptor: what brdfbake's own runtime convention (docs/CONVENTIONS.md) fixes, and how
// (docs/ENGINES.md).
#include "engines/generic/generic.hpp"
#include "engines/write_common.hpp"

namespace brdfbake::detail::engines::generic {

EngineSettings settings() {
  EngineSettings s;
  s.target = EngineTarget::Generic;
  const std::string faces = opengl_faces_text();
  s.engine = "brdfbake's own convention";
  s.held_to = "no engine: brdfbake's own runtime convention (docs/CONVENTIONS.md)";
  s.held_to_short = s.held_to;
  s.schedule = RoughnessSchedule::Linear;
  s.schedule_source = "docs/CONVENTIONS.md (the glTF-IBL-Sampler's linear mapping)";
  s.lod_formula = schedule_lod_formula(s.schedule);
  s.pixel = PixelType::F16;
  s.pixel_format = "KTX2 VK_FORMAT_R16G16B16A16_SFLOAT (or ASTC HDR 4x4 / 6x6 SFLOAT blocks)";
  s.sh_convention = ShConvention::IrradianceOverPi;
  s.sh_description = "JSON: radiance L_lm and irradiance_over_pi c_lm = (A_l/pi) w_l L_lm, E(n)/pi = sum c_lm Y_lm(n)";
  s.orientation = faces + "; KTXorientation rd";
  s.files = {"NAME_ggx.ktx2", "NAME_sh.json"};
  return s;
}

}  // namespace brdfbake::detail::engines::generic

namespace brdfbake::detail::engines {

const TargetDef& generic_target() {
  static const TargetDef def = [] {
    TargetDef d{EngineTarget::Generic, "generic", generic::settings, generic::write, generic::read_prefiltered_and_sh};
    d.read_sheen_chain = generic::read_charlie_chain;
    d.engine_dfg = nullptr;
    d.shading = generic::shading;
    d.needs_sh = true;
    d.astc = true;
    return d;
  }();
  return def;
}

}  // namespace brdfbake::detail::engines
