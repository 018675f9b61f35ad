// Internal: how Babylon.js reads the cube faces and the frame of the files it loads (docs/ENGINES.md,
// "Row order and frame"), shared by the writers of the `babylon` and `gltf` targets and by every reader
// that must see what Babylon.js sees (the preview's split-sum render, `view`).
//
// Row order: Babylon.js 8.46.2 takes row 0 of a face image (a .env's PNGs, EXT_lights_image_based's
// PNGs) as the face's last row, t = 1 in OpenGL's cube face coordinates, when it loads one and when it
// writes its own. So the faces are written bottom row first (io::decode_rgbd_cube reads them so).
//
// Frame: Babylon.js's world is left-handed by default, and its loaders bring right-handed content into
// it mirrored in x: the glTF loader puts glTF content under a root of rotation (0, 1, 0, 0) and scale
// (1, 1, -1), and HDRCubeTexture reads an equirectangular map so that its +X is seen at world -X. A
// cube texture (a .env, the glTF light's cube) is not mirrored by anything. So both targets store the
// environment mirrored in x, (x, y, z) -> (-x, y, z), with its harmonics: a default scene then sees the
// glTF content lit as in the glTF frame, and a .env as Babylon.js shows the same map loaded as an .hdr
// (measured with Babylon.js 8.46.2, tests/engines/babylon/). A right-handed scene
// (scene.useRightHandedSystem) does not mirror the content but flips every cube lookup's z
// (REFLECTIONMAP_OPPOSITEZ): a glTF light for it carries rotation (0, 1, 0, 0) (the loader applies it
// as the reflection texture's matrix), which with that flip is the same mirror in x: the stored cube
// is the same, only the rotation differs.
#pragma once

#include <array>
#include <string>

#include "brdfbake/engines.hpp"
#include "brdfbake/environment.hpp"

namespace brdfbake::detail {

// The cube of directions (x, y, z) -> cube(-x, y, z): an exact texel permutation, level by level.
CubeLevels mirror_cube_x(const CubeLevels& cube);

// The irradiance coefficients of EXT_lights_image_based (order l00, l1-1, l10, l11, l2-2, l2-1, l20,
// l21, l22: y, z, x, xy, yz, 3z^2 - 1, xz, x^2 - y^2) of the environment mirrored in x: the terms odd
// in x (l11, l2-2, l21) change sign.
std::array<Rgb3, 9> mirror_gltf_coefficients_x(std::array<Rgb3, 9> c);

// The cube of a Babylon.js .env's spherical polynomial (x, y, z, xx, yy, zz, yz, zx, xy) mirrored in
// x: the terms odd in x (x, zx, xy) change sign.
std::array<Rgb3, 9> mirror_babylon_polynomial_x(std::array<Rgb3, 9> p);

// The rotation an EXT_lights_image_based file carries for the scene it is written for.
std::array<double, 4> gltf_scene_rotation(GltfScene scene);
const char* gltf_scene_name(GltfScene scene);
// "left-handed" / "right-handed"; throws Error naming `what` for anything else.
GltfScene parse_gltf_scene(const std::string& name, const std::string& what);
// The scene a light's `rotation` (x, y, z, w; absent: identity) is read in by the readers that show
// what Babylon.js shows: identity, Babylon.js's default left-handed scene; (0, 1, 0, 0), a right-handed
// one. Throws Error naming `what` for any other rotation (not emulated).
GltfScene gltf_scene_of_rotation(const std::array<double, 4>& rotation, const std::string& what);
// A light's cube and coefficients in the glTF scene's frame, as that scene samples them (un-mirrored:
// both scenes read the stored cube at (-x, y, z) of a glTF direction).
void gltf_light_to_scene_frame(CubeLevels& cube, std::array<Rgb3, 9>& coefficients);

}  // namespace brdfbake::detail
