// Internal: the environment's quadtree that the reference render walks (kernels/preview.cl): level
// 0 holds the pixels of the equirect, each constant over its cell of longitude x latitude (the
// environment's continuous model), level k + 1 the sums of 2 x 2 cells of level k, up to two root
// cells of a hemisphere of longitude each. Built on the host in double, stored as float.
#pragma once

#include <array>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/math/types.hpp"

namespace brdfbake::detail::preview {

// 20 floats a cell: the unit mean direction g = int l dl / |int l dl| and the mean's length
// |int l dl| / Omega (<= 1); the solid angle Omega; the angular radius rho (the largest angle from g
// to a point of the cell: a corner, for a cell of longitude x latitude); L Omega (r, g, b) and its
// luminance; the first moments int l L_c dl of the three channels (3 x 3); a zero.
inline constexpr int kTreeFloats = 20;

struct EnvTree {
  int image_width = 0, image_height = 0;
  // Level 0 is a grid of 2^(top + 1) x 2^top cells (the image padded to powers of two with cells of
  // no solid angle); level k a grid of 2^(top + 1 - k) x 2^(top - k); level top, two roots.
  int top = 0;
  int start = 0;  // the first level the walk visits whole (at most 64 x 32 cells: 0.05 to 0.1 rad)
  // Per level: its first cell in `data` (20 floats a cell), its cell count, grid width and height.
  std::vector<std::array<int, 4>> levels;
  std::vector<float> data;
  std::vector<float> image;  // the equirect's RGB, row 0 first (the mirror of roughness 0 reads it)
  // The bright pixels (the prefilter's environment sampling, kDefaultBrightTexels): at most 256, each
  // brighter than 16 x the mean luminance (solid-angle weighted). They leave the tree's sums (their
  // cells keep their solid angle and no radiance) and are walked on their own, each from the pixel
  // down: no cell of varying radiance ever carries the sun.
  std::vector<int> bright_index;  // quadtree index at level 0
  std::vector<float> bright_rgb;  // 3 a pixel
  double solid_angle = 0.0;       // the sum over level 0 (4 pi up to rounding)
};

// The cells of a level in quadtree (Morton) order: the four children of cell p of level k + 1 are
// cells 4p .. 4p + 3 of level k, in the order (x, y) = (0, 0), (1, 0), (0, 1), (1, 1).
int tree_index(int top, int k, int x, int y);
void tree_cell_position(int top, int k, int index, int& x, int& y);

// Throws Error for an environment that is not an equirect (callers convert cubes first).
// `bright` false: no pixel leaves the tree (tests).
EnvTree build_env_tree(const EnvImage& equirect, bool bright = true);

// The exact solid angle and first moment int l dl of the cell of the equirect u in [u0, u1], v in
// [v0, v1] (docs/CONVENTIONS.md's mapping).
double equirect_rect_solid_angle(double u0, double u1, double v0, double v1);
Vec3 equirect_rect_moment(double u0, double u1, double v0, double v1);

}  // namespace brdfbake::detail::preview
