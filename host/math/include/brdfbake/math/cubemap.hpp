// Cube map geometry (docs/CONVENTIONS.md, "Environment maps"): faces in KTX / OpenGL order
// +X, -X, +Y, -Y, +Z, -Z (index 0..5), OpenGL face orientation, texel (i, j) of a face of `size`
// at face coordinates a = 2 (i + 0.5) / size - 1 (along the row), b = 2 (j + 0.5) / size - 1 (down
// the rows), and exact solid angles.
#pragma once

#include "brdfbake/math/types.hpp"

namespace brdfbake::math {

// The point at face coordinates (a, b) of `face` on the face plane at distance 1 (unnormalised).
// Defined for |a|, |b| > 1 too (the plane extended past the face). Throws std::invalid_argument for
// a face outside 0..5.
Vec3 cube_plane_point(int face, double a, double b);
// The face a direction falls on (major axis; ties go to x, then y) and its face coordinates in
// [-1, 1]. d need not be unit but must not be zero.
void cube_face_coords(const Vec3& d, int& face, double& a, double& b);
// The unit direction through the centre of texel (i, j) of a face of `size`.
Vec3 cube_texel_direction(int face, int size, int i, int j);

// The exact solid angle of the face rectangle [a0, a1] x [b0, b1]: the integral of the face's area
// element (1 + a^2 + b^2)^(-3/2) over it, through its antiderivative atan2(a b, sqrt(1 + a^2 + b^2)).
double cube_rect_solid_angle(double a0, double b0, double a1, double b1);
// The exact solid angle of texel (i, j) of a face of `size` (the same on every face).
double cube_texel_solid_angle(int size, int i, int j);

}  // namespace brdfbake::math
