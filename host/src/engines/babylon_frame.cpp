// Babylon.js's row order and frame (babylon_frame.hpp).
#include "engines/babylon_frame.hpp"

#include <algorithm>
#include <cmath>

#include "brdfbake/error.hpp"
#include "brdfbake/math/cubemap.hpp"

namespace brdfbake::detail {

CubeLevels mirror_cube_x(const CubeLevels& cube) {
  CubeLevels out = cube;
  for (int l = 0; l < cube.level_count(); ++l) {
    const int s = cube.level_size(l);
    for (int f = 0; f < 6; ++f)
      for (int j = 0; j < s; ++j)
        for (int i = 0; i < s; ++i) {
          const Vec3 d = math::cube_texel_direction(f, s, i, j);
          int nf = 0;
          double a = 0.0, b = 0.0;
          math::cube_face_coords({-d.x, d.y, d.z}, nf, a, b);
          // a mirror maps texel centres onto texel centres: the nearest index is exact
          const int ni = std::clamp(int(std::floor(0.5 * (a + 1.0) * s)), 0, s - 1);
          const int nj = std::clamp(int(std::floor(0.5 * (b + 1.0) * s)), 0, s - 1);
          std::copy_n(cube.texel(l, nf, ni, nj), 4, out.texel(l, f, i, j));
        }
  }
  return out;
}

std::array<Rgb3, 9> mirror_gltf_coefficients_x(std::array<Rgb3, 9> c) {
  for (size_t k : {size_t(3), size_t(4), size_t(7)})
    for (double& v : c[k]) v = -v;
  return c;
}

std::array<Rgb3, 9> mirror_babylon_polynomial_x(std::array<Rgb3, 9> p) {
  for (size_t k : {size_t(0), size_t(7), size_t(8)})
    for (double& v : p[k]) v = -v;
  return p;
}

std::array<double, 4> gltf_scene_rotation(GltfScene scene) {
  return scene == GltfScene::RightHanded ? std::array<double, 4>{0.0, 1.0, 0.0, 0.0}
                                         : std::array<double, 4>{0.0, 0.0, 0.0, 1.0};
}

const char* gltf_scene_name(GltfScene scene) {
  return scene == GltfScene::RightHanded ? "right-handed" : "left-handed";
}

GltfScene parse_gltf_scene(const std::string& name, const std::string& what) {
  if (name == "left-handed") return GltfScene::LeftHanded;
  if (name == "right-handed") return GltfScene::RightHanded;
  throw Error(what + ": '" + name + "' is not a Babylon.js scene (left-handed, right-handed)");
}

GltfScene gltf_scene_of_rotation(const std::array<double, 4>& q, const std::string& what) {
  auto near = [&](const std::array<double, 4>& r) {
    double d = 0.0;
    for (size_t k = 0; k < 4; ++k) d = std::max(d, std::fabs(q[k] - r[k]));
    return d < 1e-6;
  };
  if (near(gltf_scene_rotation(GltfScene::LeftHanded))) return GltfScene::LeftHanded;
  if (near(gltf_scene_rotation(GltfScene::RightHanded))) return GltfScene::RightHanded;
  throw Error(what + ": rotation [" + std::to_string(q[0]) + ", " + std::to_string(q[1]) + ", " + std::to_string(q[2]) +
              ", " + std::to_string(q[3]) +
              "] is not emulated: identity (Babylon.js's default left-handed scene) and [0, 1, 0, 0] (a "
              "right-handed scene) are, the two brdfbake writes");
}

void gltf_light_to_scene_frame(CubeLevels& cube, std::array<Rgb3, 9>& coefficients) {
  cube = mirror_cube_x(cube);
  coefficients = mirror_gltf_coefficients_x(coefficients);
}

}  // namespace brdfbake::detail
