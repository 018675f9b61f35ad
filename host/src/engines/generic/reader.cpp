// The `generic` target's files as brdfbake's own runtime convention reads them (docs/CONVENTIONS.md):
// the GGX chain of the manifest's prefilter entry, the irradiance SH JSON (c_lm, E/pi) and, for
// KHR_materials_sheen, the prefilter entry of distribution charlie.
#include "brdfbake/error.hpp"
#include "brdfbake/math/sh.hpp"
#include "engines/generic/generic.hpp"
#include "families/preview/bake_files.hpp"
#include "io/gpu_cube_read.hpp"
#include "io/json_input.hpp"

namespace brdfbake::detail::engines::generic {

using bake_read::Field;
using preview::BakeFiles;

void read_prefiltered_and_sh(const Field& manifest, BakeFiles& b) {
  const std::optional<Field> chain = bake_read::manifest_entry(manifest, "prefilter");
  const std::optional<Field> irr = bake_read::manifest_entry(manifest, "irradiance");
  if (!chain) throw Error("'" + b.folder + "': the bake has no GGX chain");
  b.specular_file = bake_read::entry_file(*chain, b.folder);
  b.specular = io::read_gpu_cube(b.specular_file, &b.specular_format);
  if (!irr) {
    // a scene of metals plans no irradiance: only spheres without a diffuse lobe can be shaded
    // (render_preview refuses the others)
    b.diffuse = preview::DiffuseSource::None;
    b.diffuse_file.clear();
    b.sh.clear();
    return;
  }
  b.diffuse_file = bake_read::entry_file(*irr, b.folder);
  const nlohmann::ordered_json sh = io::parse_json(io::read_text_file(b.diffuse_file, "SH JSON"), b.diffuse_file);
  const Field doc(sh, b.diffuse_file);
  b.diffuse = preview::DiffuseSource::OurSh;
  b.sh_order = doc.at("order").integer(3, math::kMaxShOrder);
  b.sh = bake_read::sh_numbers(doc.at("irradiance_over_pi"), 3 * size_t(b.sh_order) * size_t(b.sh_order));
}

void read_charlie_chain(const Field& manifest, BakeFiles& b) {
  if (const std::optional<Field> chain = bake_read::manifest_entry(manifest, "prefilter", "charlie")) {
    b.sheen_file = bake_read::entry_file(*chain, b.folder);
    b.sheen = io::read_gpu_cube(b.sheen_file);
  }
}

}  // namespace brdfbake::detail::engines::generic
