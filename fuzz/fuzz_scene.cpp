// glTF scenes: parse_scene_json (.gltf) and parse_glb (.glb; the first four bytes "glTF" choose
// it), then the planner's rules on what was read (plan_scene), which must accept any scene the
// reader accepts.
#include "brdfbake/plan.hpp"
#include "brdfbake/scene.hpp"
#include "fuzz.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace brdfbake;
  const std::string bytes = fuzz::text(data, size);
  const auto scene = fuzz::accepted([&] {
    return bytes.rfind("glTF", 0) == 0 ? parse_glb(bytes, "fuzz.glb", "") : parse_scene_json(bytes, "fuzz.gltf", "");
  });
  if (!scene) return 0;
  fuzz::invariant("the planner accepts a scene the reader accepted", [&] {
    const Plan plan = plan_scene(*scene, PlanOptions{});
    (void)plan_to_json(plan);
  });
  return 0;
}
