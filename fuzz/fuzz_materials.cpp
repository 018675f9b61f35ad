// Material files of eval and tabulate: our JSON (parse_materials_json) and glTF documents
// (parse_gltf_materials); every material read must pass validate_material and print as JSON.
#include "brdfbake/brdf.hpp"
#include "fuzz.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace brdfbake;
  const std::string text = fuzz::text(data, size);
  for (int gltf = 0; gltf < 2; ++gltf) {
    const auto materials = fuzz::accepted(
        [&] { return gltf ? parse_gltf_materials(text, "fuzz.gltf") : parse_materials_json(text, "fuzz.json"); });
    if (!materials) continue;
    for (const NamedMaterial& m : *materials) {
      // what the parser accepted is valid, and prints
      fuzz::invariant("an accepted material passes validate_material", [&] { validate_material(m.params, m.name); });
      fuzz::invariant("an accepted material prints as JSON", [&] { (void)material_to_json(m); });
    }
  }
  return 0;
}
