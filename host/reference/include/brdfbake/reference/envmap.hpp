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

#include "brdfbake/math/types.hpp"

namespace brdfbake::reference {

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

// Cube addressing, exact texel solid angles and the equirect mapping are the shared maths'
// (brdfbake/math/cubemap.hpp, brdfbake/math/equirect.hpp); the SH basis too (brdfbake/math/sh.hpp).

// ---- The environment function ---------------------------------------------------------------------

// The texel (i, j) of `face` for i, j in [-1, size]: inside the face, the texel; one index outside,
// the texel of the neighbouring face nearest to the extended texel centre (cube_plane_point at
// |a| or |b| > 1); both outside (a corner), the mean of the three texels around it.
std::array<double, 3> cube_fetch_extended(const EnvCube& cube, int face, int i, int j);
// The seamless bilinear interpolation of the texels at direction d (any length > 0).
std::array<double, 3> cube_bilinear(const EnvCube& cube, const Vec3& d);

// ---- Conversion ----------------------------------------------------------------------------------

// An equirectangular image in double (docs/CONVENTIONS.md): width x height pixels, row 0 (+Y) first,
// pixel (x, y) at rgb[3 * (y * width + x) + channel]. Its environment function is the bilinear
// interpolation of the pixels at (u w - 0.5, v h - 0.5), periodic in u and clamped in v.
struct EnvEquirect {
  int width = 0;
  int height = 0;
  std::vector<double> rgb;
};
// That bilinear interpolation at direction d (any length > 0).
std::array<double, 3> equirect_bilinear(const EnvEquirect& image, const Vec3& d);

// A cube of `size` whose texels hold the mean of an environment function over their footprints:
// every texel split into q x q sub-cells, each weighted by its exact solid angle (q = 0: enough
// sub-cells to sample the source at least 4 x 4 times per source pixel or texel, at most 64).
// From an equirect ...
EnvCube equirect_to_cube(const EnvEquirect& source, int size, int subdivision = 0, unsigned threads = 0);
// ... or from another cube's seamless bilinear environment (cube_bilinear).
EnvCube cube_resample(const EnvCube& source, int size, int subdivision = 0, unsigned threads = 0);

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
                                         const std::vector<Vec3>& dirs, int subdivision = 0, unsigned threads = 0);
// The same at every texel centre of an out_size cube.
EnvCube prefilter_cube(const EnvCube& source, EnvLobe lobe, double roughness, int out_size, int subdivision = 0,
                       unsigned threads = 0);

// ---- Spherical harmonics and irradiance --------------------------------------------------------------

// Radiance coefficients L_lm = int L(l) Y_lm(l) dl: order^2 coefficients x 3 channels, brute force
// with q x q sub-cells per texel (0: q = ceil(128 / size), so that the midpoint rule's O(h^2)
// error is ~1e-5), in the basis of brdfbake/math/sh.hpp. The irradiance follows with the cosine
// lobe's A_l (math::sh_cosine_lobe): E(n) = sum A_l L_lm Y_lm(n).
std::vector<double> sh_project(const EnvCube& source, int order, int subdivision = 0);

// E(n) / pi = (1 / pi) int L(l) (n.l)+ dl for each unit normal, brute force (q x q sub-cells;
// 0: q = ceil(128 / size), which resolves the cosine's kink at the horizon to ~2e-5; the error
// falls as 1 / (size q)^2). 3 doubles per normal.
std::vector<double> irradiance_directions(const EnvCube& source, const std::vector<Vec3>& normals, int subdivision = 0,
                                          unsigned threads = 0);

}  // namespace brdfbake::reference
