// Identities, closed forms and properties of the scalar BRDF reference (brdfbake/reference/brdf.hpp),
// each model checked against an independent route where one exists (the DFG reference's
// quadratures, closed-form albedos, spec spot values).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "brdfbake/math/conventions.hpp"
#include "brdfbake/reference/brdf.hpp"
#include "brdfbake/reference/dfg_lut.hpp"
#include "brdfbake/reference/fresnel.hpp"
#include "brdfbake/reference/ggx.hpp"
#include "brdfbake/reference/quadrature.hpp"
#include "support/brdf_cases.hpp"
#include "support/tolerances.hpp"

namespace brdfbake {
namespace {

using namespace reference;
using brdfbake::math::kPi;

Vec3 dir(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

double rel(double a, double b) { return std::fabs(a - b) / std::max(1.0, std::fabs(b)); }

// Integral of g(theta, phi) sin(theta) over the upper hemisphere by Gauss-Legendre in cos(theta)
// (graded towards the pole) and the midpoint rule in phi.
template <class G>
double hemisphere(const G& g, int n_phi = 256) {
  const GaussLegendreRule& rule = gauss_legendre(32);
  double sum = 0.0;
  // panels in t = theta, graded towards 0 (narrow lobes at the normal)
  std::vector<double> breaks{0.0};
  for (double t = 1e-5; t < 0.5 * kPi; t *= 2.0) breaks.push_back(t);
  breaks.push_back(0.5 * kPi);
  for (size_t p = 0; p + 1 < breaks.size(); ++p) {
    const double a = breaks[p], b = breaks[p + 1];
    for (size_t k = 0; k < rule.nodes.size(); ++k) {
      const double t = 0.5 * (a + b) + 0.5 * (b - a) * rule.nodes[k];
      double row = 0.0;
      for (int j = 0; j < n_phi; ++j) row += g(t, (j + 0.5) * 2.0 * kPi / n_phi);
      sum += 0.5 * (b - a) * rule.weights[k] * std::sin(t) * row * 2.0 * kPi / n_phi;
    }
  }
  return sum;
}

TEST(BrdfReference, ZeroAtAndBelowTheHorizon) {
  std::mt19937 rng(1u);
  for (BrdfModel model : test::all_models<BrdfModel>()) {
    const BrdfMaterial m = test::random_material<BrdfMaterial>(model, rng);
    const Vec3 up = dir(0.3, 0.2), flat{1.0, 0.0, 0.0}, below{0.3, 0.1, -0.2};
    for (const auto& [a, b] : {std::pair{up, flat}, std::pair{flat, up}, std::pair{up, below}, std::pair{below, up},
                               std::pair{flat, flat}}) {
      const Rgb f = brdf(model, m, a, b);
      EXPECT_EQ(f.r, 0.0);
      EXPECT_EQ(f.g, 0.0);
      EXPECT_EQ(f.b, 0.0);
    }
  }
}

TEST(BrdfReference, FiniteAndNonNegativeAtTheCorners) {
  for (BrdfModel model : test::all_models<BrdfModel>())
    for (const auto& [name, m] : test::corner_materials<BrdfMaterial>(model))
      for (const auto& [a, b] : test::corner_pairs()) {
        const Rgb f = brdf(model, m, a, b);
        for (double c : {f.r, f.g, f.b}) {
          ASSERT_TRUE(std::isfinite(c)) << name;
          ASSERT_GE(c, 0.0) << name;
        }
      }
}

TEST(BrdfReference, ReciprocityWhereTheModelIsReciprocal) {
  std::mt19937 rng(2u);
  for (BrdfModel model : test::all_models<BrdfModel>()) {
    for (int k = 0; k < 6; ++k) {
      BrdfMaterial m = test::random_material<BrdfMaterial>(model, rng);
      if (model == BrdfModel::Gltf || model == BrdfModel::GltfCorrelated) m.clearcoat = 0.0;
      ASSERT_TRUE(brdf_is_reciprocal(model, m));
      for (const auto& [a, b] : test::random_pairs(rng, 50)) {
        const Rgb f = brdf(model, m, a, b), g = brdf(model, m, b, a);
        EXPECT_LE(rel(f.r, g.r), test::kBrdfReciprocity) << brdf_is_reciprocal(model, m);
        EXPECT_LE(rel(f.b, g.b), test::kBrdfReciprocity);
      }
    }
  }
  // and glTF's clearcoat is not: its layering Fresnel takes n.v
  BrdfMaterial coat;
  coat.clearcoat = 1.0;
  EXPECT_FALSE(brdf_is_reciprocal(BrdfModel::Gltf, coat));
  const Rgb f = brdf(BrdfModel::Gltf, coat, dir(0.2, 0.0), dir(1.4, kPi));
  const Rgb g = brdf(BrdfModel::Gltf, coat, dir(1.4, kPi), dir(0.2, 0.0));
  EXPECT_GT(rel(f.r, g.r), 1e-3);
}

TEST(BrdfReference, DirectionsNeedNotBeUnitButMustBeFinite) {
  const BrdfMaterial m;
  const Rgb a = brdf(BrdfModel::Disney, m, {0.3, 0.1, 0.9}, {-0.2, 0.4, 0.7});
  const Rgb b = brdf(BrdfModel::Disney, m, {3e-30, 1e-30, 9e-30}, {-2e30, 4e30, 7e30});
  EXPECT_LE(rel(a.g, b.g), test::kRounding * 10);
  EXPECT_THROW(brdf(BrdfModel::Disney, m, {0, 0, 0}, {0, 0, 1}), std::invalid_argument);
  EXPECT_THROW(brdf(BrdfModel::Disney, m, {0, 0, 1}, {std::numeric_limits<double>::quiet_NaN(), 0, 1}),
               std::invalid_argument);
  EXPECT_THROW(brdf(BrdfModel::Disney, m, {0, 0, 1}, {std::numeric_limits<double>::infinity(), 0, 1}),
               std::invalid_argument);
}

// Lambert: f = kd / pi, and its albedo is kd.
TEST(BrdfReference, LambertClosedForm) {
  BrdfMaterial m;
  m.base_color = {0.5, 0.25, 1.0};
  m.metallic = 0.2;
  const Rgb f = brdf(BrdfModel::Lambert, m, dir(0.4, 0.0), dir(1.1, 2.0));
  EXPECT_NEAR(f.r, 0.5 * 0.8 / kPi, test::kRounding);
  for (double t : {0.0, 0.8, 1.5}) {
    const Rgb a = directional_albedo(BrdfModel::Lambert, m, t);
    EXPECT_NEAR(a.g, 0.25 * 0.8, test::kBrdfAlbedoReference);
  }
}

// Disney's specular lobe of a metal without anisotropy, sheen or clearcoat is glTF's separable GGX
// metal (the same D, G1 G1 / (4 n.l n.v) and Schlick at l.h) wherever roughness^2 >= 0.001.
TEST(BrdfReference, DisneyMetalEqualsGltfMetal) {
  std::mt19937 rng(3u);
  for (double r : {0.1, 0.4, 0.9}) {
    BrdfMaterial m;
    m.base_color = {0.9, 0.6, 0.3};
    m.metallic = 1.0;
    m.roughness = r;
    for (const auto& [a, b] : test::random_pairs(rng, 100)) {
      const Rgb d = brdf(BrdfModel::Disney, m, a, b), g = brdf(BrdfModel::Gltf, m, a, b);
      EXPECT_LE(rel(d.r, g.r), test::kRounding * 100) << r;
      EXPECT_LE(rel(d.b, g.b), test::kRounding * 100) << r;
    }
  }
}

// Disney's diffuse lobe has the albedo of Burley's lobe that the DFG reference integrates with its own
// quadrature. The specular lobe never vanishes (Schlick's F90 = 1 stays with specular = 0), but it
// does not depend on the base colour at metallic 0: the difference of two base colours isolates the
// diffuse, which is linear in it.
TEST(BrdfReference, DisneyDiffuseAlbedoIsBurleys) {
  for (double r : {0.0, 0.5, 1.0})
    for (double t : {0.1, 0.9, 1.45}) {
      BrdfMaterial m;
      m.base_color = {1.0, 0.5, 0.25};
      m.specular = 0.0;
      m.roughness = r;
      BrdfMaterial black = m;
      black.base_color = {0.0, 0.0, 0.0};
      const Rgb a = directional_albedo(BrdfModel::Disney, m, t), z = directional_albedo(BrdfModel::Disney, black, t);
      const double want = burley_albedo(std::cos(t), r);
      EXPECT_NEAR(a.r - z.r, want, test::kBrdfAlbedoReference) << r << " " << t;
      EXPECT_NEAR(a.b - z.b, 0.25 * want, test::kBrdfAlbedoReference) << r << " " << t;
    }
}

// A white glTF metal with the height-correlated visibility: its albedo is the DFG table's
// scale + bias (F0 = 1), from the DFG reference's independent quadrature.
TEST(BrdfReference, GltfCorrelatedMetalAlbedoIsDfg) {
  for (double r : {0.05, 0.3, 0.7, 1.0})
    for (double t : {0.0, 0.7, 1.3, 1.5}) {
      BrdfMaterial m;
      m.base_color = {1.0, 1.0, 1.0};
      m.metallic = 1.0;
      m.roughness = r;
      const Rgb a = directional_albedo(BrdfModel::GltfCorrelated, m, t);
      const DfgGgx d = dfg_ggx(std::cos(t), r);
      EXPECT_NEAR(a.g, d.scale + d.bias, test::kBrdfAlbedoReference) << r << " " << t;
    }
}

// glTF's fresnel_mix limits: specularFactor 0 leaves Lambert's baseColor / pi; ior 0 makes F = 1, so a
// dielectric becomes the specular lobe alone.
TEST(BrdfReference, GltfFresnelMixLimits) {
  std::mt19937 rng(4u);
  for (const auto& [a, b] : test::random_pairs(rng, 60)) {
    BrdfMaterial m;
    m.base_color = {0.3, 0.6, 0.9};
    m.roughness = 0.4;
    m.specular_factor = 0.0;
    const Rgb f = brdf(BrdfModel::Gltf, m, a, b);
    if (a.z > 0 && b.z > 0) {
      EXPECT_NEAR(f.g, 0.6 / kPi, test::kRounding);
    }
    m.specular_factor = 1.0;
    m.ior = 0.0;
    BrdfMaterial white_metal = m;
    white_metal.base_color = {1.0, 1.0, 1.0};
    white_metal.metallic = 1.0;
    const Rgb g = brdf(BrdfModel::Gltf, m, a, b), h = brdf(BrdfModel::Gltf, white_metal, a, b);
    EXPECT_LE(rel(g.r, h.r), test::kRounding * 10);
  }
}

// KHR_materials_sheen's E: the Chebyshev series against charlie_albedo at a finer quadrature.
TEST(BrdfReference, SheenAlbedoSeriesMatchesTheQuadrature) {
  for (double r : {0.0, 0.1, 0.5, 1.0})
    for (int k = 0; k < 12; ++k) {
      const double mu = std::exp(-16.0 * (k + 0.37) / 12.0);
      const double want = charlie_albedo(mu, r, SheenVisibility::EstevezKulla, Quadrature{20, 2});
      EXPECT_LE(rel(sheen_albedo(mu, r), want), test::kSheenAlbedoSeries) << r << " " << mu;
    }
}

// Normalisations: every D integrates to 1 over the projected hemisphere; Phong's normalised lobe has
// albedo 1 at normal incidence; the anisotropic G1 at equal widths is the isotropic one.
TEST(BrdfReference, DistributionsAreNormalised) {
  for (double a : {0.05, 0.3, 1.0}) {
    const double ggx = hemisphere([&](double t, double p) { return D_GGXAniso(dir(t, p), a, 0.5 * a) * std::cos(t); });
    const double beck = hemisphere([&](double t, double p) { return D_Beckmann(dir(t, p), a) * std::cos(t); });
    EXPECT_NEAR(ggx, 1.0, test::kNdfNormalisation) << a;
    EXPECT_NEAR(beck, 1.0, test::kNdfNormalisation) << a;
  }
  for (double a : {0.001, 0.1, 0.5}) {
    const double gtr1 = hemisphere([&](double t, double) { return D_GTR1(std::cos(t), a) * std::cos(t); }, 8);
    EXPECT_NEAR(gtr1, 1.0, test::kNdfNormalisation) << a;
  }
  for (double c : {0.05, 0.5, 1.0})
    for (double a : {0.01, 0.5})
      EXPECT_NEAR(G1_SmithGGXAniso(c, std::sqrt(1 - c * c), 0.0, a, a), G1_SmithGGX(c, a), test::kRounding);
  for (double n : {1.0, 10.0, 500.0}) {
    BrdfMaterial m;
    m.diffuse_color = Rgb{0, 0, 0};
    m.specular_color = Rgb{1, 1, 1};
    m.shininess = n;
    EXPECT_NEAR(directional_albedo(BrdfModel::Phong, m, 0.0).r, 1.0, test::kBrdfAlbedoReference) << n;
  }
}

// Cook-Torrance's Fresnel is the exact dielectric one for the index that gives F0 at normal incidence.
TEST(BrdfReference, CookTorranceFresnelAtNormalIncidence) {
  BrdfMaterial m;
  m.diffuse_color = Rgb{0, 0, 0};
  m.specular_color = Rgb{0.04, 0.5, 1.0};
  m.roughness = 0.5;
  const Vec3 n{0, 0, 1};
  const Rgb f = brdf(BrdfModel::CookTorrance, m, n, n);
  const double d = D_GGX(1.0, 0.25), g = 1.0, geometry = d * g / 4.0;
  EXPECT_NEAR(f.r / geometry, 0.04, test::kRoundingLong);
  EXPECT_NEAR(f.g / geometry, 0.5, test::kRoundingLong);
  EXPECT_NEAR(f.b / geometry, 1.0, test::kRoundingLong);
}

// The guard of Disney's subsurface term: 1 / (n.l + n.v) with both cosines floored at 1e-7, so a
// pair at the horizon's edge gives the value at the floor, finite.
TEST(BrdfReference, DisneySubsurfaceGuard) {
  BrdfMaterial m;
  m.subsurface = 1.0;
  m.roughness = 1.0;
  const Vec3 a{1.0, 0.0, 1e-30}, b{0.0, 1.0, 1e-30}, a7{1.0, 0.0, 1e-7}, b7{0.0, 1.0, 1e-7};
  const Rgb f = brdf(BrdfModel::Disney, m, a, b), g = brdf(BrdfModel::Disney, m, a7, b7);
  EXPECT_TRUE(std::isfinite(f.r));
  EXPECT_LE(rel(f.r, g.r), 1e-6);
  EXPECT_LT(f.r, 1e7);
}

// Energy in the reference: the documented bounds (docs/CONVENTIONS.md) hold at their worst points.
TEST(BrdfReference, DocumentedAlbedoBounds) {
  BrdfMaterial blinn;
  blinn.diffuse_color = Rgb{0, 0, 0};
  blinn.specular_color = Rgb{1, 1, 1};
  blinn.shininess = 10.0;
  const double b = directional_albedo(BrdfModel::BlinnPhong, blinn, 0.0).r;
  EXPECT_GT(b, 1.07);                          // the (n + 8)/(8 pi) normalisation overshoots ...
  EXPECT_LE(b, test::kBlinnPhongAlbedoBound);  // ... by at most this
  BrdfMaterial disney;
  disney.base_color = {1, 1, 1};
  disney.specular = 0.0;
  disney.roughness = 1.0;
  const double d = directional_albedo(BrdfModel::Disney, disney, 1.565).r;
  EXPECT_GT(d, 1.5);  // retro-reflection
  EXPECT_LE(d, test::kDisneyDiffuseAlbedoBound);
}

// The adaptive albedo converges: the default tolerance against a 100x tighter one.
TEST(BrdfReference, AlbedoSelfConvergence) {
  std::mt19937 rng(6u);
  for (BrdfModel model : {BrdfModel::Disney, BrdfModel::Gltf, BrdfModel::CookTorrance, BrdfModel::BlinnPhongFromPbr}) {
    BrdfMaterial m = test::random_material<BrdfMaterial>(model, rng);
    m.sheen_color = {0, 0, 0};
    for (double t : {0.3, 1.4}) {
      const Rgb a = directional_albedo(model, m, t), b = directional_albedo(model, m, t, 1e-9);
      EXPECT_NEAR(a.r, b.r, test::kBrdfAlbedoReference) << static_cast<int>(model);
    }
  }
  EXPECT_THROW(directional_albedo(BrdfModel::Lambert, BrdfMaterial{}, 0.5 * kPi), std::invalid_argument);
}

}  // namespace
}  // namespace brdfbake
