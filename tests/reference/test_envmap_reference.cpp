// The environment-map reference: addressing against the KTX / OpenGL table, exact solid angles,
// the SH basis, the lobe normalisation in closed form, and the brute-force integrals' identities
// and convergence.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "brdfbake/reference/envmap.hpp"
#include "brdfbake/reference/quadrature.hpp"
#include "support/tolerances.hpp"

namespace brdfbake::reference {
namespace {

constexpr double kPi = 3.14159265358979323846;

double dot(const Dir3& a, const Dir3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

EnvCube constant_cube(int size, double r, double g, double b) {
  EnvCube c;
  c.size = size;
  c.rgb.resize(18u * size_t(size) * size_t(size));
  for (size_t t = 0; t < c.rgb.size(); t += 3) {
    c.rgb[t] = r;
    c.rgb[t + 1] = g;
    c.rgb[t + 2] = b;
  }
  return c;
}

// A smooth environment with structure in every band: texel values of
// 1 + 0.5 x + 0.25 y z + 0.3 z^2 (channel 0), scaled per channel.
EnvCube smooth_cube(int size) {
  EnvCube c;
  c.size = size;
  c.rgb.resize(18u * size_t(size) * size_t(size));
  for (int f = 0; f < 6; ++f)
    for (int j = 0; j < size; ++j)
      for (int i = 0; i < size; ++i) {
        const Dir3 d = cube_texel_direction(f, size, i, j);
        const double v = 1.0 + 0.5 * d.x + 0.25 * d.y * d.z + 0.3 * d.z * d.z;
        for (int ch = 0; ch < 3; ++ch) c.at(f, i, j, ch) = v * (1.0 + 0.1 * ch);
      }
  return c;
}

// OpenGL 4.6, table 8.19: the major axis and (sc, tc) of each face, written out independently.
TEST(EnvmapAddressing, FollowsTheOpenGlCubeTable) {
  struct Row {
    int face;
    Dir3 major;
    Dir3 sc_axis, tc_axis;  // s grows along sc_axis, t along tc_axis
  };
  const Row rows[] = {
      {0, {1, 0, 0}, {0, 0, -1}, {0, -1, 0}}, {1, {-1, 0, 0}, {0, 0, 1}, {0, -1, 0}},
      {2, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}},   {3, {0, -1, 0}, {1, 0, 0}, {0, 0, -1}},
      {4, {0, 0, 1}, {1, 0, 0}, {0, -1, 0}},  {5, {0, 0, -1}, {-1, 0, 0}, {0, -1, 0}},
  };
  for (const Row& row : rows) {
    for (double a : {-0.9, -0.3, 0.0, 0.6}) {
      for (double b : {-0.7, 0.0, 0.2, 0.95}) {
        const Dir3 p = cube_plane_point(row.face, a, b);
        const Dir3 want = {row.major.x + a * row.sc_axis.x + b * row.tc_axis.x,
                           row.major.y + a * row.sc_axis.y + b * row.tc_axis.y,
                           row.major.z + a * row.sc_axis.z + b * row.tc_axis.z};
        EXPECT_DOUBLE_EQ(p.x, want.x);
        EXPECT_DOUBLE_EQ(p.y, want.y);
        EXPECT_DOUBLE_EQ(p.z, want.z);
        int face = -1;
        double ra = 0, rb = 0;
        cube_face_coords({2.5 * p.x, 2.5 * p.y, 2.5 * p.z}, face, ra, rb);
        EXPECT_EQ(face, row.face);
        EXPECT_NEAR(ra, a, test::kRounding);
        EXPECT_NEAR(rb, b, test::kRounding);
      }
    }
  }
  // the first texel of +X (top-left as stored) looks up and towards +Z
  const Dir3 d = cube_texel_direction(0, 4, 0, 0);
  EXPECT_GT(d.y, 0.0);
  EXPECT_GT(d.z, 0.0);
}

TEST(EnvmapAddressing, SolidAnglesTileTheSphere) {
  for (int size : {1, 2, 3, 7, 32}) {
    double sum = 0;
    for (int j = 0; j < size; ++j)
      for (int i = 0; i < size; ++i) sum += cube_texel_solid_angle(size, i, j);
    EXPECT_NEAR(6.0 * sum, 4.0 * kPi, test::kRounding * 10) << size;
  }
  // the whole face is a sixth of the sphere; the centre texel of a large face is (2/S)^2
  EXPECT_NEAR(cube_rect_solid_angle(-1, -1, 1, 1), 4.0 * kPi / 6.0, test::kRounding);
  EXPECT_NEAR(cube_texel_solid_angle(1000, 500, 500) / (4e-6), 1.0, 1e-5);
}

TEST(EnvmapAddressing, EquirectMapping) {
  // docs/CONVENTIONS.md: top row +Y, centre +Z, u = 1/4 +X, u = 3/4 -X, the edges -Z
  const Dir3 top = equirect_direction(0.3, 0.0), centre = equirect_direction(0.5, 0.5);
  const Dir3 px = equirect_direction(0.25, 0.5), nx = equirect_direction(0.75, 0.5);
  const Dir3 nz = equirect_direction(0.0, 0.5);
  EXPECT_NEAR(top.y, 1.0, test::kRounding);
  EXPECT_NEAR(centre.z, 1.0, test::kRounding);
  EXPECT_NEAR(px.x, 1.0, test::kRounding);
  EXPECT_NEAR(nx.x, -1.0, test::kRounding);
  EXPECT_NEAR(nz.z, -1.0, test::kRounding);
  for (double u : {0.1, 0.37, 0.5, 0.81}) {
    for (double v : {0.05, 0.4, 0.77}) {
      double ru = 0, rv = 0;
      equirect_coords(equirect_direction(u, v), ru, rv);
      EXPECT_NEAR(ru, u, 1e-12);
      EXPECT_NEAR(rv, v, 1e-12);
    }
  }
}

TEST(EnvmapBilinear, TexelCentresAndSeams) {
  const EnvCube c = smooth_cube(8);
  // at a texel centre the interpolation is the texel
  for (int f = 0; f < 6; ++f) {
    const auto v = cube_bilinear(c, cube_texel_direction(f, 8, 3, 5));
    EXPECT_NEAR(v[0], c.at(f, 3, 5, 0), test::kRounding);
  }
  // continuous across an edge: just either side of the +X / +Z edge
  const double e = 1e-9;
  const auto left = cube_bilinear(c, {1.0, 0.3, 1.0 - e}), right = cube_bilinear(c, {1.0 - e, 0.3, 1.0});
  EXPECT_NEAR(left[0], right[0], 1e-6);
  // a border position takes the neighbouring face's edge texel: left of +Z is -X's right column
  const auto b = cube_fetch_extended(c, 4, -1, 3);
  EXPECT_DOUBLE_EQ(b[0], c.at(1, 7, 3, 0));
}

TEST(EnvmapSh, BasisIsOrthonormal) {
  // Gauss-Legendre in z times the midpoint rule in phi: exact for these polynomial products
  const auto& gl = gauss_legendre(16);
  const int n_phi = 32;
  std::vector<double> gram(25 * 25, 0.0);
  for (size_t a = 0; a < gl.nodes.size(); ++a)
    for (int m = 0; m < n_phi; ++m) {
      const double z = gl.nodes[a], phi = 2.0 * kPi * (m + 0.5) / n_phi, r = std::sqrt(1 - z * z);
      const auto y = sh_basis(5, {r * std::cos(phi), r * std::sin(phi), z});
      const double w = gl.weights[a] * 2.0 * kPi / n_phi;
      for (size_t i = 0; i < 25; ++i)
        for (size_t j = 0; j < 25; ++j) gram[i * 25 + j] += w * y[i] * y[j];
    }
  for (size_t i = 0; i < 25; ++i)
    for (size_t j = 0; j < 25; ++j)
      EXPECT_NEAR(gram[i * 25 + j], i == j ? 1.0 : 0.0, test::kAnalytic) << i << "," << j;
  // the Condon-Shortley-free signs: Y_1,-1 ~ +y, Y_10 ~ +z, Y_11 ~ +x
  const auto y = sh_basis(2, {0.0, 1.0, 0.0});
  EXPECT_GT(y[1], 0.0);
}

TEST(EnvmapLobe, NormalisationInClosedForm) {
  // GGX: W = 4 int_0^xi_max (2 cos^2 - 1) d xi in the CDF variable, with b = 1 - alpha^2,
  // xi_max = 1 / (1 + alpha^2): W = 4 [2 xi_max / b + (2 alpha^2 / b^2) ln(2 alpha^2 / (1 + alpha^2)) - xi_max]
  for (double alpha : {0.01, 0.1, 0.3, 0.5, 0.8}) {
    const double b = 1 - alpha * alpha, xm = 1 / (1 + alpha * alpha);
    const double want =
        4 * (2 * xm / b + 2 * alpha * alpha / (b * b) * std::log(2 * alpha * alpha / (1 + alpha * alpha)) - xm);
    EXPECT_NEAR(env_lobe_normalization(EnvLobe::Ggx, alpha) / want, 1.0, test::kAnalytic) << alpha;
  }
  // alpha = 1: D = 1 / pi, K = c / pi, W = 1
  EXPECT_NEAR(env_lobe_normalization(EnvLobe::Ggx, 1.0), 1.0, test::kAnalytic);
  // Charlie at alpha = 1: D = 3 sin(theta_h) / (2 pi) with sin(theta_h) = sqrt((1 - c) / 2), so
  // W = 2 pi int_0^1 K dc = (3 / sqrt 2) B(2, 3/2) = (3 / sqrt 2)(4 / 15)
  EXPECT_NEAR(env_lobe_normalization(EnvLobe::Charlie, 1.0), 4.0 / (5.0 * std::sqrt(2.0)), test::kAnalytic);
}

TEST(EnvmapPrefilter, ConstantEnvironmentIsReturnedExactly) {
  const EnvCube c = constant_cube(4, 2.0, 0.5, 1e6);
  for (EnvLobe lobe : {EnvLobe::Ggx, EnvLobe::Charlie})
    for (double r : {0.0, 0.3, 1.0}) {
      const EnvCube out = prefilter_cube(c, lobe, r, 2, 0, 1);
      for (size_t t = 0; t < out.rgb.size(); t += 3) {
        EXPECT_NEAR(out.rgb[t] / 2.0, 1.0, test::kRounding);
        EXPECT_NEAR(out.rgb[t + 1] / 0.5, 1.0, test::kRounding);
        EXPECT_NEAR(out.rgb[t + 2] / 1e6, 1.0, test::kRounding);
      }
    }
}

TEST(EnvmapPrefilter, MirrorIsTheBilinearEnvironment) {
  const EnvCube c = smooth_cube(8);
  const EnvCube out = prefilter_cube(c, EnvLobe::Ggx, 0.0, 8);
  for (size_t k = 0; k < out.rgb.size(); ++k) EXPECT_NEAR(out.rgb[k], c.rgb[k], test::kRounding);
}

// The sum's normaliser converges to W: the sub-cells resolve the lobe.
TEST(EnvmapPrefilter, SubCellsResolveTheLobe) {
  for (EnvLobe lobe : {EnvLobe::Ggx, EnvLobe::Charlie})
    for (double r : {0.25, 0.6}) {
      const double alpha = r * r;
      const int q = env_default_subdivision(lobe, alpha, 16);
      // sum of K Omega over the sub-cells around one direction
      const Dir3 d = cube_texel_direction(4, 16, 5, 9);
      double sum = 0;
      for (int f = 0; f < 6; ++f)
        for (int j = 0; j < 16 * q; ++j)
          for (int i = 0; i < 16 * q; ++i) {
            const double a0 = -1 + 2.0 * i / (16 * q), a1 = -1 + 2.0 * (i + 1) / (16 * q);
            const double b0 = -1 + 2.0 * j / (16 * q), b1 = -1 + 2.0 * (j + 1) / (16 * q);
            Dir3 p = cube_plane_point(f, 0.5 * (a0 + a1), 0.5 * (b0 + b1));
            const double n = std::sqrt(dot(p, p));
            p = {p.x / n, p.y / n, p.z / n};
            sum += env_lobe_kernel(lobe, alpha, dot(d, p)) * cube_rect_solid_angle(a0, b0, a1, b1);
          }
      EXPECT_NEAR(sum / env_lobe_normalization(lobe, alpha), 1.0, test::kEnvReferenceSubCells)
          << (lobe == EnvLobe::Ggx ? "ggx" : "charlie") << " r " << r << " q " << q;
    }
}

// Doubling the sub-cells changes the prefiltered radiance by far less than any device tolerance.
TEST(EnvmapPrefilter, SelfConvergence) {
  const EnvCube c = smooth_cube(8);
  for (EnvLobe lobe : {EnvLobe::Ggx, EnvLobe::Charlie}) {
    const double r = 0.4, alpha = r * r;
    const int q = env_default_subdivision(lobe, alpha, 8);
    const EnvCube a = prefilter_cube(c, lobe, r, 4, q), b = prefilter_cube(c, lobe, r, 4, 2 * q);
    for (size_t k = 0; k < a.rgb.size(); ++k)
      EXPECT_NEAR(a.rgb[k] / b.rgb[k], 1.0, test::kEnvReferenceSubCells) << k;
  }
}

// One bright texel in a black environment spreads into the lobe: P(R) = L Omega K(R.l) / W where
// the lobe is wide against the texel.
TEST(EnvmapPrefilter, SingleTexelSpreadsIntoTheLobe) {
  EnvCube c = constant_cube(16, 0, 0, 0);
  const int f = 4, i = 7, j = 8;
  for (int ch = 0; ch < 3; ++ch) c.at(f, i, j, ch) = 1000.0;
  const double r = 0.7, alpha = r * r;
  const Dir3 l = cube_texel_direction(f, 16, i, j);
  const double omega = cube_texel_solid_angle(16, i, j);
  const std::vector<Dir3> dirs = {cube_texel_direction(4, 8, 3, 4), cube_texel_direction(4, 8, 1, 6),
                                  cube_texel_direction(0, 8, 2, 4)};
  const auto p = prefilter_directions(c, EnvLobe::Ggx, r, dirs);
  for (size_t k = 0; k < dirs.size(); ++k) {
    const double want = 1000.0 * omega * env_lobe_kernel(EnvLobe::Ggx, alpha, dot(dirs[k], l)) /
                        env_lobe_normalization(EnvLobe::Ggx, alpha);
    // the bilinear tent spreads the texel over its neighbours: a second-order change here
    EXPECT_NEAR(p[3 * k] / want, 1.0, 0.02) << k;
  }
}

TEST(EnvmapSh, ConstantEnvironmentHasOnlyL00) {
  const EnvCube c = constant_cube(8, 1.0, 2.0, 3.0);
  const auto sh = sh_project(c, 5);
  for (size_t k = 0; k < 25; ++k)
    for (size_t ch = 0; ch < 3; ++ch) {
      const double level = double(ch) + 1.0;
      const double want = k == 0 ? level * 2.0 * std::sqrt(kPi) : 0.0;  // 4 pi Y_00 L
      EXPECT_NEAR(sh[3 * k + ch], want, test::kEnvShDiscretisation * 2.0 * std::sqrt(kPi) * level) << k << "," << ch;
    }
}

TEST(EnvmapIrradiance, ConstantAndSmoothEnvironments) {
  // a constant L: E / pi = L
  const EnvCube c = constant_cube(4, 1.5, 1.5, 1.5);
  const std::vector<Dir3> dirs = {{0, 1, 0}, {0.6, 0, 0.8}, cube_texel_direction(3, 4, 1, 2)};
  for (double v : irradiance_directions(c, dirs)) EXPECT_NEAR(v / 1.5, 1.0, test::kEnvReferenceCosine);
  // a smooth L of degree <= 2: the 9-coefficient SH irradiance is exact, so both routes agree
  const EnvCube s = smooth_cube(16);
  const auto sh = sh_project(s, 3);
  const auto direct = irradiance_directions(s, dirs);
  for (size_t k = 0; k < dirs.size(); ++k) {
    const auto y = sh_basis(3, dirs[k]);
    double e = 0;
    for (int l = 0; l < 3; ++l)
      for (int m = -l; m <= l; ++m) e += sh_cosine_lobe(l) / kPi * sh[3 * size_t(l * (l + 1) + m)] * y[size_t(l * (l + 1) + m)];
    EXPECT_NEAR(e / direct[3 * k], 1.0, test::kEnvIrradianceRoutes) << k;
  }
}

}  // namespace
}  // namespace brdfbake::reference
