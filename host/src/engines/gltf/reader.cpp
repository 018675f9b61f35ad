// The `gltf` target's EXT_lights_image_based light as Babylon.js's glTF loader reads it
// (EXT_lights_image_based.ts: the specular images as a RawCubeTexture, lodGenerationScale =
// (N - 1) / log2(specularImageSize), irradianceCoefficients, the rotation), in the glTF scene's frame
// (engines/babylon_frame.hpp).
#include <cmath>

#include "brdfbake/error.hpp"
#include "engines/babylon_frame.hpp"
#include "engines/gltf/gltf.hpp"
#include "families/preview/bake_files.hpp"
#include "io/gpu_cube_read.hpp"
#include "io/json_input.hpp"
#include "io/png_image.hpp"

namespace brdfbake::detail::engines::gltf {

using bake_read::Field;
using preview::BakeFiles;

void load_light(const Field& manifest, BakeFiles& b) {
  b.specular_file = bake_read::engine_file(manifest, b.folder, ".gltf");
  const nlohmann::ordered_json document =
      io::parse_json(io::read_text_file(b.specular_file, "glTF file"), b.specular_file);
  const Field doc(document, b.specular_file);
  const std::vector<Field> lights = doc.at("extensions").at("EXT_lights_image_based").at("lights").elements();
  if (lights.empty()) doc.at("extensions").at("EXT_lights_image_based").at("lights").fail("no light");
  const Field& light = lights.front();
  const int size = light.at("specularImageSize").integer(1, 16384);
  const std::vector<Field> images = doc.at("images").elements();
  std::vector<std::vector<std::vector<uint8_t>>> levels;
  for (const Field& level : light.at("specularImages").elements()) {
    levels.emplace_back();
    for (const Field& index : level.elements()) {
      const int i = index.integer(0, int(images.size()) - 1);
      const std::string uri = images[size_t(i)].at("uri").file_name();
      levels.back().push_back(io::read_binary_file(bake_read::join_path(b.folder, uri), "specular image"));
    }
  }
  b.specular = io::decode_rgbd_cube(levels, size, b.specular_file);
  b.specular_format = "RGBD PNG, expanded to RGBA16F";
  // Babylon.js's EXT_lights_image_based loader: lodGenerationScale = (N - 1) / log2(specularImageSize)
  b.lod_scale = double(levels.size() - 1) / std::log2(double(size));
  b.diffuse = preview::DiffuseSource::GltfSh;
  b.diffuse_file = b.specular_file + " (irradianceCoefficients)";
  b.sh = bake_read::sh_numbers(light.at("irradianceCoefficients"), 27);
  // the scene its rotation is for, and the cube and harmonics as that scene samples them in the glTF
  // frame (engines/babylon_frame.hpp)
  std::array<double, 4> rotation = {0.0, 0.0, 0.0, 1.0};
  if (const std::optional<Field> r = light.find("rotation")) {
    const std::vector<Field> q = r->elements();
    if (q.size() != 4) r->fail("expected 4 numbers (x, y, z, w), not " + std::to_string(q.size()));
    for (size_t k = 0; k < 4; ++k) rotation[k] = q[k].number(-1.0, 1.0);
  }
  b.gltf_scene = detail::gltf_scene_of_rotation(rotation, b.specular_file);
  std::array<Rgb3, 9> c{};
  for (size_t k = 0; k < 27; ++k) c[k / 3][k % 3] = b.sh[k];
  detail::gltf_light_to_scene_frame(b.specular, c);
  for (size_t k = 0; k < 27; ++k) b.sh[k] = c[k / 3][k % 3];
}

}  // namespace brdfbake::detail::engines::gltf
