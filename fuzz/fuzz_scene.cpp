// glTF scenes: parse_scene_json (.gltf) and parse_glb (.glb; the first four bytes "glTF" choose
// it), then the planner's rules on what was read (plan_scene), which must accept any scene the
// reader accepts.
#include "brdfbake/plan.hpp"
#include "brdfbake/scene.hpp"
#include "fuzz.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace brdfbake;
  const std::string bytes = fuzz::text(data, size);
  Scene scene;
  bool read = false;
  fuzz::expect_answer([&] {
    scene = bytes.rfind("glTF", 0) == 0 ? parse_glb(bytes, "fuzz.glb", "") : parse_scene_json(bytes, "fuzz.gltf", "");
    read = true;
  });
  if (read) {
    const Plan plan = plan_scene(scene, PlanOptions{});  // no Error expected: the scene was accepted
    (void)plan_to_json(plan);
  }
  return 0;
}
