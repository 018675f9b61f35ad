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

// 16 floats a cell (one cache line): the unit mean direction g = int l dl / |int l dl| and the mean's
// length |int l dl| / Omega (<= 1); the unit luminance-weighted mean direction m and its length
// (g where the cell is black); the solid angle Omega; L Omega (r, g, b); the angular radius rho (the
// largest angle from g to a point of the cell: a corner, for a cell of longitude x latitude); the
// luminance of L Omega; two zeros.
inline constexpr int kTreeFloats = 16;

struct EnvTree {
  int image_width = 0, image_height = 0;
  // Level 0 is a grid of 2^(top + 1) x 2^top cells (the image padded to powers of two with cells of
  // no solid angle); level k a grid of 2^(top + 1 - k) x 2^(top - k); level top, two roots.
  int top = 0;
  int start = 0;  // the first level the walk visits whole (at most 32 x 16 cells)
  // Per level: its first cell in `data` (16 floats a cell), its cell count, grid width and height.
  std::vector<std::array<int, 4>> levels;
  std::vector<float> data;
  std::vector<float> image;  // the equirect's RGB, row 0 first (the walk's sub-pixel cells read it)
  double solid_angle = 0.0;  // the sum over level 0 (4 pi up to rounding)
};

// The cells of a level in quadtree (Morton) order: the four children of cell p of level k + 1 are
// cells 4p .. 4p + 3 of level k, in the order (x, y) = (0, 0), (1, 0), (0, 1), (1, 1).
int tree_index(int top, int k, int x, int y);
void tree_cell_position(int top, int k, int index, int& x, int& y);

// Throws Error for an environment that is not an equirect (callers convert cubes first).
EnvTree build_env_tree(const EnvImage& equirect);

// The exact solid angle and first moment int l dl of the cell of the equirect u in [u0, u1], v in
// [v0, v1] (docs/CONVENTIONS.md's mapping).
double equirect_rect_solid_angle(double u0, double u1, double v0, double v1);
Vec3 equirect_rect_moment(double u0, double u1, double v0, double v1);

}  // namespace brdfbake::detail::preview
