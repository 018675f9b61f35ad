// The `babylon` target's .env as Babylon.js loads it (EnvironmentTextureTools: GetEnvInfo,
// UploadEnvLevelsAsync, UploadEnvSpherical): RGBD PNG faces per level, read bottom row first, the
// irradiance polynomial, lodGenerationScale; in the environment's frame as Babylon.js's left-handed
// world sees it (engines/babylon_frame.hpp).
#include <cmath>

#include "brdfbake/error.hpp"
#include "engines/babylon/babylon.hpp"
#include "engines/babylon_frame.hpp"
#include "families/preview/bake_files.hpp"
#include "io/babylon_env.hpp"
#include "io/gpu_cube_read.hpp"
#include "io/png_image.hpp"
#include "text.hpp"

namespace brdfbake::detail::engines::babylon {

using bake_read::Field;
using preview::BakeFiles;

void upload_env_levels(const Field& manifest, BakeFiles& b) {
  b.specular_file = bake_read::engine_file(manifest, b.folder, ".env");
  const io::BabylonEnv env = io::decode_babylon_env(io::read_binary_file(b.specular_file, ".env file"));
  std::vector<std::vector<std::vector<uint8_t>>> levels;
  for (size_t i = 0; i < env.images.size(); ++i) {
    if (i % 6 == 0) levels.emplace_back();
    levels.back().push_back(env.images[i]);
  }
  b.specular = detail::mirror_cube_x(io::decode_rgbd_cube(levels, env.width, b.specular_file));
  b.specular_format = "RGBD PNG, expanded to RGBA16F";
  // GetEnvInfo: lodGenerationScale, the .env's own (0.8 as Babylon.js writes it)
  if (!std::isfinite(env.lod_generation_scale) || !(env.lod_generation_scale > 0.0 && env.lod_generation_scale <= 16.0))
    throw Error("'" + b.specular_file + "': lodGenerationScale " + fmt_number(env.lod_generation_scale) +
                " is outside (0, 16]");
  b.lod_scale = env.lod_generation_scale;
  b.diffuse = preview::DiffuseSource::BabylonPolynomial;
  b.diffuse_file = b.specular_file + " (irradiance polynomial)";
  for (const auto& c : detail::mirror_babylon_polynomial_x(env.polynomial)) b.sh.insert(b.sh.end(), c.begin(), c.end());
  for (size_t k = 0; k < b.sh.size(); ++k)
    if (!std::isfinite(b.sh[k]) || std::fabs(b.sh[k]) > bake_read::kMaxShCoefficient)
      throw Error("'" + b.specular_file + "': irradiance." + kBabylonPolynomialNames[k / 3] + "[" +
                  std::to_string(k % 3) + "]: " + fmt_number(b.sh[k]) + " (finite, within 1e+20)");
}

}  // namespace brdfbake::detail::engines::babylon
