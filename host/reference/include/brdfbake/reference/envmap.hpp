// Scalar double-precision reference for environment maps: cube addressing, exact texel solid
// angles, the prefiltered radiance of a GGX or Charlie lobe by brute force over every source
// texel, spherical-harmonic projection and diffuse irradiance.
//
// Written from docs/CONVENTIONS.md ("Environment maps"), independently of kernels/cubemap.cl,
// kernels/prefilter.cl and kernels/irradiance.cl. No sampling: every integral is a deterministic
// sum over every source texel, each split into q x q sub-cells weighted by their exact solid angle.
//
// The environment is the seamless bilinear interpolation of the source cube's texels (the function
// a GPU's seamless cube sampler reconstructs at the source level), so "level 0 equals the source"
// and every rougher level filters that same function.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

namespace brdfbake::reference {

// A direction (not necessarily normalised where a function says so).
struct Dir3 {
  double x, y, z;
};

// A cubemap in double: faces in KTX/OpenGL order +X, -X, +Y, -Y, +Z, -Z, each face size x size
// texels, row j = 0 first, texel (i, j) at rgb[3 * ((face * size + j) * size + i) + channel].
struct EnvCube {
  int size = 0;
  std::vector<double> rgb;

  double& at(int face, int i, int j, int c) {
    return rgb[3 * ((static_cast<size_t>(face) * static_cast<size_t>(size) + static_cast<size_t>(j)) *
                        static_cast<size_t>(size) +
                    static_cast<size_t>(i)) +
               static_cast<size_t>(c)];
  }
  double at(int face, int i, int j, int c) const {
    return rgb[3 * ((static_cast<size_t>(face) * static_cast<size_t>(size) + static_cast<size_t>(j)) *
                        static_cast<size_t>(size) +
                    static_cast<size_t>(i)) +
               static_cast<size_t>(c)];
  }
};

// ---- Addressing (docs/CONVENTIONS.md, "Environment maps") ---------------------------------------

// The direction through face coordinates (a, b) in [-1, 1]^2 of `face` (a along the row, b down
// the rows; a = 2 (i + 0.5) / size - 1 at a texel centre), unnormalised: the point on the face
// plane at distance 1. Defined for |a|, |b| > 1 too (the plane extended past the face).
Dir3 cube_plane_point(int face, double a, double b);
// The face a direction falls on (major axis; ties go to x, then y) and its face coordinates.
void cube_face_coords(const Dir3& d, int& face, double& a, double& b);
// The unit direction of texel (i, j)'s centre on a face of `size`.
Dir3 cube_texel_direction(int face, int size, int i, int j);

// The exact solid angle of the face rectangle [a0, a1] x [b0, b1]: the integral of
// (1 + a^2 + b^2)^(-3/2) over it, through its antiderivative atan2(a b, sqrt(1 + a^2 + b^2)).
double cube_rect_solid_angle(double a0, double b0, double a1, double b1);
// The exact solid angle of texel (i, j) of a face of `size`.
double cube_texel_solid_angle(int size, int i, int j);

// Equirectangular mapping (OpenEXR's LatLongMap orientation, texel centres at (x + 0.5) / width):
// u = (x + 0.5) / width, v = (y + 0.5) / height, longitude phi = 2 pi (0.5 - u), latitude
// theta = pi (0.5 - v), direction (sin phi cos theta, sin theta, cos phi cos theta).
Dir3 equirect_direction(double u, double v);
void equirect_coords(const Dir3& d, double& u, double& v);

// ---- The environment function ---------------------------------------------------------------------

// The texel (i, j) of `face` for i, j in [-1, size]: inside the face, the texel; one index outside,
// the texel of the neighbouring face nearest to the extended texel centre (cube_plane_point at
// |a| or |b| > 1); both outside (a corner), the mean of the three texels around it.
std::array<double, 3> cube_fetch_extended(const EnvCube& cube, int face, int i, int j);
// The seamless bilinear interpolation of the texels at direction d (any length > 0).
std::array<double, 3> cube_bilinear(const EnvCube& cube, const Dir3& d);

// ---- Lobes -----------------------------------------------------------------------------------------

enum class EnvLobe { Ggx, Charlie };

// The filter kernel of a prefiltered level with n = v = R (Karis 2013): K = D(h) (n.l)+ as a
// function of c = R.l; with n = v, n.h = sqrt((1 + c) / 2). alpha = roughness^2 (floored at
// kMinAlpha).
double env_lobe_kernel(EnvLobe lobe, double alpha, double cos_rl);
// W = the integral of K over the sphere, by adaptive Gauss-Kronrod quadrature in the angle between
// R and l (converged to 1e-12 relative).
double env_lobe_normalization(EnvLobe lobe, double alpha);

// The number q of sub-cells per texel side that resolves a lobe of this width on a source of this
// face size, and on small sources the bilinear interpolation itself: q = clamp(max(ceil(8 (2 / size)
// / width), ceil(64 / size)), 1, 32) with width = 2 alpha (GGX) or 1 (Charlie); the tests check that
// doubling q changes the result by far less than their tolerances.
int env_default_subdivision(EnvLobe lobe, double alpha, int source_size);

// ---- Prefiltered radiance ---------------------------------------------------------------------------

// P(R) = int L(l) K(R.l) dl / int K(R.l) dl for each direction in `dirs` (unit), L the seamless
// bilinear environment of `source`. Brute force: every source texel, split into q x q sub-cells,
// each weighted by its exact solid angle (q = 0: env_default_subdivision). roughness 0 returns
// L(R) itself. The normaliser is the same sum with L = 1, so a constant environment returns its
// constant. Returns 3 doubles per direction. threads = 0: all cores.
std::vector<double> prefilter_directions(const EnvCube& source, EnvLobe lobe, double roughness,
                                         const std::vector<Dir3>& dirs, int subdivision = 0,
                                         unsigned threads = 0);
// The same at every texel centre of an out_size cube.
EnvCube prefilter_cube(const EnvCube& source, EnvLobe lobe, double roughness, int out_size,
                       int subdivision = 0, unsigned threads = 0);

// ---- Spherical harmonics and irradiance --------------------------------------------------------------

// Real spherical harmonics without the Condon-Shortley phase (Ramamoorthi & Hanrahan 2001's
// convention): index k = l (l + 1) + m, bands l < order (order 3: 9 functions, order 5: 25).
// Y_00 = 1 / (2 sqrt(pi)), Y_1-1 = sqrt(3 / 4pi) y, Y_10 = sqrt(3 / 4pi) z, Y_11 = sqrt(3 / 4pi) x, ...
// (the table is in docs/CONVENTIONS.md). d must be a unit vector.
std::vector<double> sh_basis(int order, const Dir3& d);
// Radiance coefficients L_lm = int L(l) Y_lm(l) dl: order^2 coefficients x 3 channels, brute force
// with q x q sub-cells per texel (0: q = ceil(128 / size), so that the midpoint rule's O(h^2)
// error is ~1e-5).
std::vector<double> sh_project(const EnvCube& source, int order, int subdivision = 0);
// Ramamoorthi & Hanrahan 2001, eq. 8-9: the cosine lobe's SH coefficients A_l, so that
// E(n) = sum A_l L_lm Y_lm(n): A_0 = pi, A_1 = 2 pi / 3, A_2 = pi / 4, A_3 = 0, A_4 = -pi / 24.
double sh_cosine_lobe(int l);

// E(n) / pi = (1 / pi) int L(l) (n.l)+ dl for each unit normal, brute force (q x q sub-cells;
// 0: q = ceil(128 / size), which resolves the cosine's kink at the horizon to ~2e-5; the error
// falls as 1 / (size q)^2). 3 doubles per normal.
std::vector<double> irradiance_directions(const EnvCube& source, const std::vector<Dir3>& normals,
                                          int subdivision = 0, unsigned threads = 0);

}  // namespace brdfbake::reference
