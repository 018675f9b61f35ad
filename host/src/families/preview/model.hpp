// Internal: the preview's scene, shared by the descriptor, the renders and the writers: the spheres'
// materials and layout, the camera, the pixels each sphere covers and their normals.
#pragma once

#include <string>
#include <vector>

#include "brdfbake/preview.hpp"
#include "enum_names.hpp"

namespace brdfbake::detail::preview {

// The backgrounds' names (model.cpp's preview_background_from_name and _name; the schema offers them).
inline constexpr EnumName<PreviewBackground> kBackgroundNames[] = {{PreviewBackground::Environment, "environment"},
                                                                   {PreviewBackground::Grey, "grey"}};

// Fills the spheres (from materials_file, or the default grid) and the columns; checks the sizes.
// Throws Error naming the field ("material", "width", ...).
PreviewSpec resolve_spec(const PreviewSpec& spec);

struct Layout {
  std::vector<PreviewSphere> spheres;
  PreviewCamera camera;
  int width = 0, height = 0;
};
// Spheres in a grid of equal cells, row by row; every centre on a pixel corner, so that every
// sphere covers the same pixel offsets (and the same n.v values).
Layout make_layout(const PreviewSpec& resolved);

// The pixels a sphere covers (their centres within its disc), with the normal and n.v of each.
struct SpherePixel {
  int x = 0, y = 0;
  int sphere = 0;
  Vec3 n{0.0, 0.0, 1.0};
  double n_dot_v = 1.0;
  // max(|dn/dx|^2, |dn/dy|^2): the normal's screen-space derivatives as a GPU takes them, coarse (one
  // pair a 2 x 2 quad: the difference along its top row and down its left column, as SwiftShader's
  // dFdx / dFdy), analytic where the quad leaves the sphere. For Babylon.js's specular anti-aliasing.
  double normal_slope2 = 0.0;
};
std::vector<SpherePixel> sphere_pixels(const Layout& layout);

// The direction a background pixel sees: a pinhole of the camera's background_fov (vertical).
Vec3 background_direction(const Layout& layout, int x, int y);

// The unit vector towards the viewer (-view_direction).
Vec3 view_vector(const PreviewCamera& camera);

// F0, the diffuse colour and alpha of a material (brdfbake/preview.hpp).
double material_alpha(const PreviewMaterial& m);

}  // namespace brdfbake::detail::preview
