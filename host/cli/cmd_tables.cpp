// The one-table commands: lut, thin-film, prefilter, irradiance, eval, tabulate (fresnel, which has
// modes of its own, is in cmd_fresnel.cpp). Their options come from the kinds' schemas.
#include "cli_table.hpp"

namespace brdfbake::cli {

namespace {

const TableCommand kCommands[] = {
    {"lut", "Bake a split-sum DFG lookup table (ggx, ggx-multiscatter, charlie)",
     "brdfbake lut --kind ggx-multiscatter --size 128 -o dfg.exr", {}, {}, {}},
    {"thin-film", "Bake a thin-film interference Fresnel table over (cos_theta, thickness) (KHR_materials_iridescence)",
     "brdfbake thin-film --film-ior 1.3 --base-ior 1.5 --thickness-min 100 --thickness-max 400 -o film.exr", {}, {}, {}},
    {"prefilter", "Prefilter an environment into a GGX or Charlie radiance mip chain",
     "brdfbake prefilter --env studio.hdr --size 256 --distribution ggx -o studio_ggx.ktx2", {}, {}, {}},
    {"irradiance", "Diffuse irradiance of an environment: spherical harmonics (.json) and an irradiance cube",
     "brdfbake irradiance --env studio.hdr --sh 3 -o studio_sh.json", {}, {}, {}},
    {"eval", "Evaluate a BRDF at (wi, wo) pairs, streaming CSV or float32",
     "brdfbake eval --material examples/materials.json --name gold -i examples/pairs.csv -o gold_f.csv", {}, {}, {}},
    {"tabulate", "Tabulate a BRDF: MERL binary, grid, directional albedo or a slice image",
     "brdfbake tabulate --material examples/materials.json --name gold --layout merl -o gold.binary", {}, {}, {}},
};

}  // namespace

const TableCommand* table_command(const std::string& name) {
  for (const auto& c : kCommands)
    if (c.name == name) return &c;
  return nullptr;
}

}  // namespace brdfbake::cli
