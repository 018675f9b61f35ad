// The `filament` target's files as Filament loads them (KtxUtility::createIndirectLight of
// NAME_ibl.ktx: its levels as the reflections cube, its "sh" key as IndirectLight::irradiance), and
// the DFG table Filament samples, its own (filament_dfg.hpp), never the bake's.
#include "brdfbake/error.hpp"
#include "engines/filament/filament.hpp"
#include "engines/filament_dfg.hpp"
#include "families/preview/bake_files.hpp"
#include "io/gpu_cube_read.hpp"

namespace brdfbake::detail::engines::filament {

using bake_read::Field;
using preview::BakeFiles;

void create_indirect_light(const Field& manifest, BakeFiles& b) {
  std::vector<std::pair<std::string, std::string>> kv;
  b.specular_file = bake_read::engine_file(manifest, b.folder, "_ibl.ktx");
  b.specular = io::read_gpu_cube(b.specular_file, &b.specular_format, &kv);
  b.diffuse = preview::DiffuseSource::FilamentSh;
  b.diffuse_file = b.specular_file + " (sh key)";
  // the "sh" key: 9 lines of "r g b" (cmgen's layout)
  for (const auto& [k, v] : kv)
    if (k == "sh") {
      b.sh = bake_read::sh_text_numbers(v, 27, "'" + b.specular_file + "': the sh key");
      return;
    }
  throw Error("'" + b.specular_file + "': no sh key (Filament's spherical harmonics)");
}

void light_ibl_dfg(BakeFiles& b) {
  b.dfg = detail::filament_dfg_table();
  b.dfg_file = "Filament's built-in DFG table (light_iblDFG; its cmgen's DFV_Multiscatter and DFV_Charlie)";
  b.dfg_multiscatter = true;
  b.dfg_sqrt_n_dot_v = false;
}

}  // namespace brdfbake::detail::engines::filament
