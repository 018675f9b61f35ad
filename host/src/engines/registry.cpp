// The engine targets (registry.hpp): the only file besides each target's folder that names one.
#include "engines/registry.hpp"

#include <algorithm>

#include "brdfbake/error.hpp"

namespace brdfbake {

namespace detail::engines {

const std::vector<const TargetDef*>& targets() {
  static const std::vector<const TargetDef*> all = {&generic_target(), &filament_target(), &gltf_target(),
                                                    &babylon_target(), &khronos_viewer_target()};
  return all;
}

const TargetDef& target_def(EngineTarget target) {
  for (const TargetDef* t : targets())
    if (t->target == target) return *t;
  return generic_target();
}

std::string opengl_faces_text() {
  return "faces +X, -X, +Y, -Y, +Z, -Z (KTX / OpenGL order and orientation, +Y up), row 0 the top row of each "
         "face; texel (i, j) of a face of size S looks along the OpenGL cube table at a = 2 (i + 0.5)/S - 1, "
         "b = 2 (j + 0.5)/S - 1 (docs/CONVENTIONS.md)";
}

}  // namespace detail::engines

using detail::engines::TargetDef;
using detail::engines::targets;

EngineTarget engine_target_from_name(const std::string& name) {
  std::string list;
  for (size_t i = 0; i < targets().size(); ++i) {
    if (name == targets()[i]->name) return targets()[i]->target;
    list += std::string(i == 0 ? "" : i + 1 == targets().size() ? " or " : ", ") + targets()[i]->name;
  }
  throw Error("unknown engine target '" + name + "' (expected " + list + ")");
}

const char* engine_target_name(EngineTarget target) { return detail::engines::target_def(target).name; }

std::vector<std::string> engine_target_names() {
  std::vector<std::string> names;
  for (const TargetDef* t : targets()) names.emplace_back(t->name);
  return names;
}

EngineSettings engine_settings(EngineTarget target) { return detail::engines::target_def(target).settings(); }

}  // namespace brdfbake
