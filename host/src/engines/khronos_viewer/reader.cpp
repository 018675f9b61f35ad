// The `khronos-viewer` target's files as the glTF-Sample-Viewer loads them (its KTX2 loader; ibl.glsl's
// u_GGXEnvSampler, u_LambertianEnvSampler and u_CharlieEnvSampler).
#include "engines/khronos_viewer/khronos_viewer.hpp"
#include "families/preview/bake_files.hpp"
#include "io/gpu_cube_read.hpp"

namespace brdfbake::detail::engines::khronos_viewer {

using bake_read::Field;
using preview::BakeFiles;

void read_ggx_and_lambertian(const Field& manifest, BakeFiles& b) {
  b.specular_file = bake_read::engine_file(manifest, b.folder, "_ggx.ktx2");
  b.specular = io::read_gpu_cube(b.specular_file, &b.specular_format);
  b.diffuse = preview::DiffuseSource::IrradianceCube;
  b.diffuse_file = bake_read::engine_file(manifest, b.folder, "_lambertian.ktx2");
  b.irradiance = io::read_gpu_cube(b.diffuse_file);
}

void read_charlie(const Field& manifest, BakeFiles& b) {
  if (const std::optional<std::string> f = bake_read::find_engine_file(manifest, b.folder, "_charlie.ktx2")) {
    b.sheen_file = *f;
    b.sheen = io::read_gpu_cube(b.sheen_file);
  }
}

}  // namespace brdfbake::detail::engines::khronos_viewer
