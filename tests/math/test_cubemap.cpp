// Cube and equirect geometry of the shared maths (host/math): addressing against the KTX / OpenGL
// table, exact texel solid angles against the sphere and an independent quadrature, the equirect
// mapping's documented axes.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/math/equirect.hpp"
#include "brdfbake/math/gauss_legendre.hpp"
#include "support/tolerances.hpp"

namespace brdfbake::math {
namespace {

// OpenGL 4.6, table 8.19: the major axis and (sc, tc) of each face, written out independently.
TEST(CubeGeometry, FollowsTheOpenGlCubeTable) {
  struct Row {
    int face;
    Vec3 major;
    Vec3 sc_axis, tc_axis;  // s grows along sc_axis, t along tc_axis
  };
  const Row rows[] = {
      {0, {1, 0, 0}, {0, 0, -1}, {0, -1, 0}}, {1, {-1, 0, 0}, {0, 0, 1}, {0, -1, 0}},
      {2, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}},   {3, {0, -1, 0}, {1, 0, 0}, {0, 0, -1}},
      {4, {0, 0, 1}, {1, 0, 0}, {0, -1, 0}},  {5, {0, 0, -1}, {-1, 0, 0}, {0, -1, 0}},
  };
  for (const Row& row : rows) {
    for (double a : {-0.9, -0.3, 0.0, 0.6}) {
      for (double b : {-0.7, 0.0, 0.2, 0.95}) {
        const Vec3 p = cube_plane_point(row.face, a, b);
        const Vec3 want = {row.major.x + a * row.sc_axis.x + b * row.tc_axis.x,
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
  const Vec3 d = cube_texel_direction(0, 4, 0, 0);
  EXPECT_GT(d.y, 0.0);
  EXPECT_GT(d.z, 0.0);
  EXPECT_NEAR(dot(d, d), 1.0, test::kRounding);
  EXPECT_THROW(cube_plane_point(6, 0.0, 0.0), std::invalid_argument);
}

TEST(CubeGeometry, SolidAnglesTileTheSphere) {
  for (int size : {1, 2, 3, 7, 32}) {
    double sum = 0;
    for (int j = 0; j < size; ++j)
      for (int i = 0; i < size; ++i) sum += cube_texel_solid_angle(size, i, j);
    EXPECT_NEAR(6.0 * sum, 4.0 * kPi, test::kRoundingFewOps) << size;
  }
  // the whole face is a sixth of the sphere; the centre texel of a large face is (2/S)^2
  EXPECT_NEAR(cube_rect_solid_angle(-1, -1, 1, 1), 4.0 * kPi / 6.0, test::kRounding);
  EXPECT_NEAR(cube_texel_solid_angle(1000, 500, 500) / (4e-6), 1.0, test::kSmallTexelSolidAngle);
  // symmetric under the face's symmetries
  EXPECT_NEAR(cube_texel_solid_angle(7, 1, 2), cube_texel_solid_angle(7, 5, 4), test::kRounding);
  EXPECT_NEAR(cube_texel_solid_angle(7, 1, 2), cube_texel_solid_angle(7, 2, 1), test::kRounding);
}

// The antiderivative against a product Gauss-Legendre rule of the area element
// (1 + a^2 + b^2)^(-3/2), which is analytic on every rectangle: 40 x 40 nodes are exact to rounding.
TEST(CubeGeometry, SolidAngleIsTheIntegralOfTheAreaElement) {
  const GaussLegendreRule& rule = gauss_legendre(40);
  const double rects[][4] = {{-1, -1, 1, 1}, {0.2, -0.9, 0.7, -0.3}, {-1, 0.75, -0.75, 1}, {0.5, 0.5, 3.0, 2.0}};
  for (const auto& r : rects) {
    double sum = 0.0;
    const double ha = 0.5 * (r[2] - r[0]), hb = 0.5 * (r[3] - r[1]);
    for (size_t i = 0; i < rule.nodes.size(); ++i)
      for (size_t j = 0; j < rule.nodes.size(); ++j) {
        const double a = r[0] + ha * (1.0 + rule.nodes[i]), b = r[1] + hb * (1.0 + rule.nodes[j]);
        sum += rule.weights[i] * rule.weights[j] * ha * hb * std::pow(1.0 + a * a + b * b, -1.5);
      }
    EXPECT_NEAR(cube_rect_solid_angle(r[0], r[1], r[2], r[3]), sum, test::kAnalytic) << r[0] << " " << r[1];
  }
}

TEST(CubeGeometry, TexelDirectionsRoundTrip) {
  for (int size : {1, 4, 9})
    for (int f = 0; f < 6; ++f)
      for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i) {
          const Vec3 d = cube_texel_direction(f, size, i, j);
          int face = -1;
          double a = 0, b = 0;
          cube_face_coords(d, face, a, b);
          EXPECT_EQ(face, f);
          EXPECT_NEAR(a, 2.0 * (i + 0.5) / size - 1.0, test::kRounding);
          EXPECT_NEAR(b, 2.0 * (j + 0.5) / size - 1.0, test::kRounding);
        }
}

TEST(EquirectGeometry, DocumentedAxesAndInverse) {
  // docs/CONVENTIONS.md: top row +Y, centre +Z, u = 1/4 +X, u = 3/4 -X, the edges -Z
  const Vec3 top = equirect_direction(0.3, 0.0), centre = equirect_direction(0.5, 0.5);
  const Vec3 px = equirect_direction(0.25, 0.5), nx = equirect_direction(0.75, 0.5);
  const Vec3 nz = equirect_direction(0.0, 0.5);
  EXPECT_NEAR(top.y, 1.0, test::kRounding);
  EXPECT_NEAR(centre.z, 1.0, test::kRounding);
  EXPECT_NEAR(px.x, 1.0, test::kRounding);
  EXPECT_NEAR(nx.x, -1.0, test::kRounding);
  EXPECT_NEAR(nz.z, -1.0, test::kRounding);
  for (double u : {0.1, 0.37, 0.5, 0.81}) {
    for (double v : {0.05, 0.4, 0.77}) {
      double ru = 0, rv = 0;
      const Vec3 d = equirect_direction(u, v);
      EXPECT_NEAR(dot(d, d), 1.0, test::kRounding);
      equirect_coords({3.0 * d.x, 3.0 * d.y, 3.0 * d.z}, ru, rv);
      EXPECT_NEAR(ru, u, test::kRoundingFewOps);
      EXPECT_NEAR(rv, v, test::kRoundingFewOps);
    }
  }
}

}  // namespace
}  // namespace brdfbake::math
