// The bulk BRDF kernels (kernels/brdf_eval.cl) against the scalar double reference, every model, fp32
// and fp64: random valid inputs, the corners, no NaN or Inf, reciprocity, lobe specialisation, the
// tables (MERL, grid, slice, albedo) and energy.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "brdfbake/brdf.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/reference/brdf.hpp"
#include "brdfbake/reference/dfg_lut.hpp"
#include "families/brdf_eval/reference_convert.hpp"
#include "families/brdf_eval/sheen_albedo.hpp"
#include "support/brdf_cases.hpp"
#include "support/device_fixture.hpp"
#include "support/tolerances.hpp"

namespace brdfbake {
namespace {

using detail::to_reference;
using test::corner_materials;
using test::corner_pairs;
using test::random_material;
using test::random_pairs;

// What the device sees of a direction: normalised in double, then (fp32) rounded to float with
// components below FLT_MIN flushed to zero (host/src/families/brdf_eval/evaluator.cpp).
Vec3 device_view(const Vec3& v, Precision p) {
  const double m = std::max(std::fabs(v.x), std::max(std::fabs(v.y), std::fabs(v.z)));
  const double x = v.x / m, y = v.y / m, z = v.z / m;
  const double len = std::sqrt(x * x + y * y + z * z);
  Vec3 u{x / len, y / len, z / len};
  if (p == Precision::Fp32) {
    auto f = [](double c) {
      const float r = static_cast<float>(c);
      return std::fabs(r) < std::numeric_limits<float>::min() ? 0.0 : double(r);
    };
    u = {f(u.x), f(u.y), f(u.z)};
  }
  return u;
}

// "1.23e-10": measured errors for the test report (std::to_string keeps 6 decimals).
std::string sci(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

std::string label(BrdfModel model, Precision p) {
  std::string n = brdf_model_name(model);
  std::replace(n.begin(), n.end(), '-', '_');
  return n + "_" + precision_name(p);
}

// Relative above 1, absolute below (f spans 0 to ~1e13 at a mirror peak).
double error(double got, double want) { return std::fabs(got - want) / std::max(1.0, std::fabs(want)); }

struct Worst {
  double err = 0.0;
  std::string where;
};

// Evaluates every pair for every material on the device and by the reference (at the directions the
// device saw) and returns the worst error; fails on a non-finite value or a non-zero one below the
// horizon.
Worst compare(Device& dev, BrdfModel model, const std::vector<Material>& mats,
              const std::vector<std::pair<Vec3, Vec3>>& pairs, const EvalOptions& options,
              const std::vector<std::string>& names = {}) {
  std::vector<double> in;
  std::vector<std::pair<Vec3, Vec3>> seen;
  for (const auto& [wi, wo] : pairs) {
    const Vec3 a = device_view(wi, options.precision), b = device_view(wo, options.precision);
    for (const Vec3& v : {a, b}) {
      in.push_back(v.x);
      in.push_back(v.y);
      in.push_back(v.z);
    }
    seen.push_back({device_view(a, options.precision), device_view(b, options.precision)});
  }
  BrdfEvaluator ev(dev, model, mats, options);
  std::vector<double> out(3 * pairs.size() * mats.size());
  ev.eval(in.data(), pairs.size(), out.data());
  Worst w;
  for (size_t m = 0; m < mats.size(); ++m)
    for (size_t i = 0; i < pairs.size(); ++i) {
      const auto& [wi, wo] = seen[i];
      const Rgb want = reference::brdf(to_reference(model), to_reference(mats[m]), wi, wo);
      const double* got = &out[(m * pairs.size() + i) * 3];
      const double wants[3] = {want.r, want.g, want.b};
      for (int c = 0; c < 3; ++c) {
        const std::string where = (names.empty() ? "material " + std::to_string(m) : names[m]) + ", pair " +
                                  std::to_string(i) + " wi (" + std::to_string(wi.x) + ", " + std::to_string(wi.y) +
                                  ", " + std::to_string(wi.z) + ") wo (" + std::to_string(wo.x) + ", " +
                                  std::to_string(wo.y) + ", " + std::to_string(wo.z) + "), channel " +
                                  std::to_string(c) + ": " + std::to_string(got[c]) + " vs " + std::to_string(wants[c]);
        EXPECT_TRUE(std::isfinite(got[c])) << where;
        if (!(wi.z > 0.0 && wo.z > 0.0)) {
          EXPECT_EQ(got[c], 0.0) << "below the horizon: " << where;
        }
        EXPECT_GE(got[c], 0.0) << where;
        const double e = error(got[c], wants[c]);
        if (e > w.err) w = {e, where};
      }
    }
  return w;
}

double tolerance(Precision p) { return p == Precision::Fp64 ? test::kBrdfFp64 : test::kBrdfFp32; }

class BrdfVsReference : public ::testing::TestWithParam<std::tuple<BrdfModel, Precision>> {};

TEST_P(BrdfVsReference, RandomValidInputs) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  const auto [model, precision] = GetParam();
  if (precision == Precision::Fp64) {
    BRDFBAKE_REQUIRE_FP64(dev);
  }
  std::mt19937 rng(1234u + static_cast<unsigned>(model));
  std::vector<Material> mats;
  for (int k = 0; k < 12; ++k) mats.push_back(random_material<Material>(model, rng));
  EvalOptions o;
  o.precision = precision;
  const Worst w = compare(*dev, model, mats, random_pairs(rng, 600), o);
  EXPECT_LE(w.err, tolerance(precision)) << w.where;
  RecordProperty("max_error", sci(w.err));
}

TEST_P(BrdfVsReference, Corners) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  const auto [model, precision] = GetParam();
  if (precision == Precision::Fp64) {
    BRDFBAKE_REQUIRE_FP64(dev);
  }
  std::vector<Material> mats;
  std::vector<std::string> names;
  for (const auto& [name, m] : corner_materials<Material>(model)) {
    names.push_back(name);
    mats.push_back(m);
  }
  EvalOptions o;
  o.precision = precision;
  const Worst w = compare(*dev, model, mats, corner_pairs(), o, names);
  EXPECT_LE(w.err, tolerance(precision)) << w.where;
  RecordProperty("max_error", sci(w.err));
}

INSTANTIATE_TEST_SUITE_P(AllModels, BrdfVsReference,
                         ::testing::Combine(::testing::ValuesIn(test::all_models<BrdfModel>()),
                                            ::testing::Values(Precision::Fp32, Precision::Fp64)),
                         [](const auto& param_info) {
                           return label(std::get<0>(param_info.param), std::get<1>(param_info.param));
                         });

}  // namespace
}  // namespace brdfbake

namespace brdfbake {
namespace {

NamedMaterial named(const std::string& name, const Material& m) {
  return NamedMaterial{name, std::nullopt, m, {}, {}, {}};
}

// The directions of a MERL bin centre (merl.hpp's half_diff_to_directions, in double).
std::pair<Vec3, Vec3> merl_directions(int i, int j, int k) {
  const double pi = 3.14159265358979323846, u = (i + 0.5) / 90.0;
  const double th = u * u * pi / 2, td = (j + 0.5) / 90.0 * pi / 2, pd = (k + 0.5) / 180.0 * pi;
  const double st = std::sin(th), ct = std::cos(th), sd = std::sin(td), cd = std::cos(td);
  const double dx = sd * std::cos(pd);
  const Vec3 wi{dx * ct + cd * st, sd * std::sin(pd), cd * ct - dx * st};
  return {wi, Vec3{2 * cd * st - wi.x, -wi.y, 2 * cd * ct - wi.z}};
}

// The tables generate their directions on the device: in fp32 a cosine near the horizon is the
// difference of O(1) terms, ~1e-7 off in absolute terms, which the 1/n.l and 1/n.v of the
// visibilities turn into ~1e-7 / cos relative (kBrdfTableDirection).
double table_tolerance(Precision p, const std::pair<Vec3, Vec3>& d) {
  if (p == Precision::Fp64) return test::kBrdfFp64;
  return test::kBrdfTableFp32 + test::kBrdfTableDirection / std::min(d.first.z, d.second.z);
}

// A random material whose every lobe is at least alpha = 0.09 wide: the table kernels generate their
// directions from angles on the device, and a direction rounded by 1e-7 rad moves a lobe of width
// alpha by ~2e-7 / alpha relative (kBrdfTableFp32).
Material smooth_material(BrdfModel model, std::mt19937& rng) {
  Material m = random_material<Material>(model, rng);
  m.roughness = std::max(m.roughness, 0.3);
  m.clearcoat_roughness = std::max(m.clearcoat_roughness, 0.3);
  m.clearcoat_gloss = std::min(m.clearcoat_gloss, 0.5);
  if (m.sheen_roughness < 0.3 && (m.sheen_color.r > 0 || m.sheen_color.g > 0 || m.sheen_color.b > 0))
    m.sheen_roughness = 0.3;
  if (m.shininess) m.shininess = std::min(*m.shininess, 100.0);
  return m;
}

// Device albedo (fixed quadrature) against the reference's adaptive quadrature.
TEST(BrdfAlbedo, DeviceMatchesReference) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  std::mt19937 rng(99u);
  for (BrdfModel model : test::all_models<BrdfModel>()) {
    TabulateSpec s;
    s.model = model;
    s.layout = TableLayout::Albedo;
    s.res = {5};
    for (int k = 0; k < 3; ++k)
      s.materials.push_back(named("random" + std::to_string(k), random_material<Material>(model, rng)));
    for (const auto& [name, m] : corner_materials<Material>(model)) s.materials.push_back(named(name, m));
    const Table want = tabulate_reference(s);
    for (Precision p : {Precision::Fp32, Precision::Fp64}) {
      if (p == Precision::Fp64 && !dev->info().fp64) continue;
      s.options.precision = p;
      const Table got = tabulate(*dev, s);
      double worst = 0.0;
      std::string where;
      for (int j = 0; j < got.height; ++j)
        for (int i = 0; i < got.width; ++i)
          for (int c = 0; c < 3; ++c) {
            ASSERT_TRUE(std::isfinite(got.at(i, j, c))) << s.materials[size_t(j)].name;
            const double e = error(got.at(i, j, c), want.at(i, j, c));
            if (e > worst) {
              worst = e;
              where = s.materials[size_t(j)].name + " theta_o " + std::to_string(got.x[size_t(i)]) + ": " +
                      std::to_string(got.at(i, j, c)) + " vs " + std::to_string(want.at(i, j, c));
            }
          }
      EXPECT_LE(worst, model == BrdfModel::Phong ? test::kPhongAlbedoKink : test::kBrdfAlbedoQuadrature)
          << brdf_model_name(model) << " " << precision_name(p) << ": " << where;
    }
  }
}

// Energy. The directional albedo of the energy-conserving models stays below 1; where a model does
// not conserve energy, it stays below its documented bound (docs/CONVENTIONS.md, "Energy"):
//   gltf: max(1 + (1 - metallic) max3(baseColor), max3(sheenColor) E(n.v)): Appendix B weights the
//     diffuse by 1 - F(v.h) per light direction, so at grazing view the mirror's F -> 1 comes on top
//     of an almost unweakened diffuse; a metal (metallic 1) without sheen conserves energy;
//   Blinn-Phong's (n + 8)/(8 pi) normalisation is an approximation (measured max 1.075 at n = 10);
//   Disney's diffuse retro-reflection (measured max 1.566 for a white base at roughness 1, grazing).
struct EnergyCase {
  BrdfModel model;
  std::string what;
  std::function<void(Material&)> set;
  std::function<double(const Material&, double)> bound;  // (material, theta_o) -> bound
};

std::vector<EnergyCase> energy_cases() {
  auto one = [](const Material&, double) { return 1.0; };
  auto gltf_bound = [](const Material& m, double theta_o) {
    const double smax = std::max(m.sheen_color.r, std::max(m.sheen_color.g, m.sheen_color.b));
    const double base = std::max(m.base_color.r, std::max(m.base_color.g, m.base_color.b));
    double b = 1.0 + (1.0 - m.metallic) * base;
    if (smax > 0.0) b = std::max(b, smax * reference::sheen_albedo(std::cos(theta_o), m.sheen_roughness));
    return b;
  };
  auto normalise = [](Material& m) {
    m.normalized = true;
    const Rgb kd = reference::classic_diffuse(to_reference(m));
    m.specular_color = Rgb{1.0 - kd.r, 1.0 - kd.g, 1.0 - kd.b};
  };
  auto metal = [](Material& m) {
    m.metallic = 1.0;
    m.sheen_color = {0, 0, 0};
  };
  auto blinn = [](const Material&, double) { return test::kBlinnPhongAlbedoBound; };
  return {
      {BrdfModel::Lambert, "any", [](Material&) {}, one},
      {BrdfModel::Phong, "normalised, kd + ks <= 1", normalise, one},
      {BrdfModel::CookTorrance, "kd = 0",
       [](Material& m) {
         m.diffuse_color = Rgb{0, 0, 0};
       },
       one},
      {BrdfModel::Gltf, "metal without sheen", metal, one},
      {BrdfModel::GltfCorrelated, "metal without sheen", metal, one},
      {BrdfModel::Disney, "metal, no clearcoat",
       [](Material& m) {
         m.metallic = 1.0;
         m.clearcoat = 0.0;
       },
       one},
      {BrdfModel::Gltf, "any", [](Material&) {}, gltf_bound},
      {BrdfModel::GltfCorrelated, "any", [](Material&) {}, gltf_bound},
      {BrdfModel::BlinnPhong, "normalised, kd + ks <= 1", normalise, blinn},
      {BrdfModel::BlinnPhongFromPbr, "any", [](Material&) {}, blinn},
      {BrdfModel::Disney, "white diffuse only",
       [](Material& m) {
         m.base_color = {1, 1, 1};
         m.metallic = m.specular = m.sheen = m.clearcoat = 0.0;
       },
       [](const Material&, double) { return test::kDisneyDiffuseAlbedoBound; }},
  };
}

TEST(BrdfAlbedo, EnergyBounds) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  std::mt19937 rng(5u);
  for (const EnergyCase& ec : energy_cases()) {
    TabulateSpec s;
    s.model = ec.model;
    s.layout = TableLayout::Albedo;
    s.res = {16};
    for (int k = 0; k < 8; ++k) {
      Material m = random_material<Material>(ec.model, rng);
      ec.set(m);
      s.materials.push_back(named("m" + std::to_string(k), m));
    }
    const Table got = tabulate(*dev, s);
    for (int j = 0; j < got.height; ++j)
      for (int i = 0; i < got.width; ++i)
        for (int c = 0; c < 3; ++c)
          EXPECT_LE(got.at(i, j, c), ec.bound(s.materials[size_t(j)].params, got.x[size_t(i)]) + test::kPhongAlbedoKink)
              << brdf_model_name(ec.model) << " (" << ec.what << ") theta_o " << got.x[size_t(i)] << " "
              << material_to_json(s.materials[size_t(j)]);
  }
}

// A MERL table on the device equals the reference's bin for bin (f at each bin centre, the -1
// marker in the same bins).
TEST(BrdfTables, MerlMatchesReference) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  for (BrdfModel model : {BrdfModel::Disney, BrdfModel::GltfCorrelated, BrdfModel::CookTorrance}) {
    TabulateSpec s;
    s.model = model;
    s.layout = TableLayout::Merl;
    std::mt19937 rng(17u);
    s.materials = {named("m", smooth_material(model, rng))};
    const MerlTable want = tabulate_merl_reference(s);
    for (Precision p : {Precision::Fp32, Precision::Fp64}) {
      if (p == Precision::Fp64 && !dev->info().fp64) continue;
      s.options.precision = p;
      const MerlTable got = tabulate_merl(*dev, s);
      ASSERT_EQ(got.values.size(), want.values.size());
      double worst = 0.0;
      size_t below = 0, at = 0;
      for (size_t k = 0; k < got.values.size(); ++k) {
        ASSERT_TRUE(std::isfinite(got.values[k])) << k;
        if (want.values[k] == kMerlBelowHorizon) {
          ASSERT_EQ(got.values[k], kMerlBelowHorizon) << "bin " << k;
          ++below;
          continue;
        }
        const size_t b = k % kMerlBins;
        const double e = error(got.values[k], want.values[k]) /
                         table_tolerance(p, merl_directions(int(b / 16200), int((b / 180) % 90), int(b % 180)));
        if (e > worst) {
          worst = e;
          at = k;
        }
      }
      const size_t b = at % kMerlBins;
      EXPECT_GT(below, 0u);
      EXPECT_LE(worst, 1.0) << "error / tolerance, " << brdf_model_name(model) << " " << precision_name(p) << " bin ("
                            << b / 16200 << ", " << (b / 180) % 90 << ", " << b % 180 << "): " << got.values[at]
                            << " vs " << want.values[at] << " " << material_to_json(s.materials[0]);
    }
  }
}

// The grid and the slice on the device against the reference.
TEST(BrdfTables, GridAndSliceMatchReference) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  std::mt19937 rng(23u);
  for (BrdfModel model : test::all_models<BrdfModel>()) {
    for (TableLayout layout : {TableLayout::Grid, TableLayout::Slice}) {
      TabulateSpec s;
      s.model = model;
      s.layout = layout;
      s.res = layout == TableLayout::Grid ? std::vector<int>{7, 9, 5} : std::vector<int>{17, 11};
      s.slice_phi_d = 1.0;
      s.materials = {named("m", smooth_material(model, rng))};
      const Table got = tabulate(*dev, s), want = tabulate_reference(s);
      ASSERT_EQ(got.width, want.width);
      ASSERT_EQ(got.height, want.height);
      double worst = 0.0;
      const double pi = 3.14159265358979323846;
      for (int j = 0; j < got.height; ++j)
        for (int i = 0; i < got.width; ++i) {
          std::pair<Vec3, Vec3> d;
          if (layout == TableLayout::Grid) {  // column: theta_o; row k * n_ti + i: theta_i, phi_d
            const double ti = got.y[size_t(j)], to = got.x[size_t(i)], pd = (j / 7 + 0.5) / 5 * pi;
            d = {Vec3{std::sin(ti), 0, std::cos(ti)},
                 Vec3{std::sin(to) * std::cos(pd), std::sin(to) * std::sin(pd), std::cos(to)}};
          } else {
            const double th = got.x[size_t(i)], td = got.y[size_t(j)], st = std::sin(th), ct = std::cos(th);
            const double dx = std::sin(td) * std::cos(1.0), cd = std::cos(td);
            const Vec3 wi{dx * ct + cd * st, std::sin(td) * std::sin(1.0), cd * ct - dx * st};
            d = {wi, Vec3{2 * cd * st - wi.x, -wi.y, 2 * cd * ct - wi.z}};
          }
          if (!(d.first.z > 1e-6 && d.second.z > 1e-6)) continue;  // at the horizon: both 0 or marker
          for (int c = 0; c < 3; ++c)
            worst = std::max(worst, error(got.at(i, j, c), want.at(i, j, c)) / table_tolerance(Precision::Fp32, d));
        }
      EXPECT_LE(worst, 1.0) << "error / tolerance, " << brdf_model_name(model) << " " << table_layout_name(layout);
    }
  }
}

// f(wi, wo) = f(wo, wi) on the device for every reciprocal model (everything but glTF with a
// clearcoat, whose layering Fresnel takes n.v).
TEST(BrdfProperties, Reciprocity) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  std::mt19937 rng(31u);
  for (BrdfModel model : test::all_models<BrdfModel>()) {
    std::vector<Material> mats;
    for (int k = 0; k < 6; ++k) {
      Material m = random_material<Material>(model, rng);
      m.clearcoat = model == BrdfModel::Gltf || model == BrdfModel::GltfCorrelated ? 0.0 : m.clearcoat;
      ASSERT_TRUE(reference::brdf_is_reciprocal(to_reference(model), to_reference(m)));
      mats.push_back(m);
    }
    const auto pairs = random_pairs(rng, 400);
    std::vector<double> ab, ba;
    for (const auto& [a, b] : pairs) {
      for (const Vec3& v : {a, b}) ab.insert(ab.end(), {v.x, v.y, v.z});
      for (const Vec3& v : {b, a}) ba.insert(ba.end(), {v.x, v.y, v.z});
    }
    BrdfEvaluator ev(*dev, model, mats);
    std::vector<double> f(3 * pairs.size() * mats.size()), g(f.size());
    ev.eval(ab.data(), pairs.size(), f.data());
    ev.eval(ba.data(), pairs.size(), g.data());
    double worst = 0.0;
    for (size_t k = 0; k < f.size(); ++k) worst = std::max(worst, error(f[k], g[k]));
    EXPECT_LE(worst, test::kBrdfFp32) << brdf_model_name(model);
  }
}

// Lobe specialisation changes nothing but speed: a program built with only the materials' lobes and
// one built with every lobe of the model give the same values (up to the order of fp32 operations).
TEST(BrdfProperties, SpecialisationGivesTheSameValues) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  std::mt19937 rng(41u);
  for (BrdfModel model : test::all_models<BrdfModel>()) {
    Material plain;
    plain.base_color = {0.7, 0.4, 0.2};
    plain.roughness = 0.35;
    const std::vector<Material> mats = {plain};
    EvalOptions spec, all;
    all.specialize = false;
    BrdfEvaluator a(*dev, model, mats, spec), b(*dev, model, mats, all);
    if (model == BrdfModel::Disney) {
      EXPECT_FALSE(a.lobes().sheen || a.lobes().clearcoat || a.lobes().subsurface || a.lobes().anisotropic);
      EXPECT_TRUE(a.lobes().diffuse);
    }
    const auto pairs = random_pairs(rng, 300);
    std::vector<double> in;
    for (const auto& [x, y] : pairs)
      for (const Vec3& v : {x, y}) in.insert(in.end(), {v.x, v.y, v.z});
    std::vector<double> f(3 * pairs.size()), g(f.size());
    a.eval(in.data(), pairs.size(), f.data());
    b.eval(in.data(), pairs.size(), g.data());
    for (size_t k = 0; k < f.size(); ++k)
      ASSERT_LE(error(f[k], g[k]), test::kBrdfFp32) << brdf_model_name(model) << " " << k;
  }
}

// Many materials in one launch give what each gives alone.
TEST(BrdfProperties, MaterialsAreIndependent) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  std::mt19937 rng(43u);
  const BrdfModel model = BrdfModel::Gltf;
  std::vector<Material> mats;
  for (int k = 0; k < 5; ++k) mats.push_back(random_material<Material>(model, rng));
  const auto pairs = random_pairs(rng, 100);
  std::vector<double> in;
  for (const auto& [x, y] : pairs)
    for (const Vec3& v : {x, y}) in.insert(in.end(), {v.x, v.y, v.z});
  BrdfEvaluator together(*dev, model, mats, {});
  std::vector<double> all(3 * pairs.size() * mats.size());
  together.eval(in.data(), pairs.size(), all.data());
  for (size_t m = 0; m < mats.size(); ++m) {
    EvalOptions o;
    o.specialize = false;  // the same program as the combined one
    BrdfEvaluator one(*dev, model, {mats[m]}, o);
    std::vector<double> f(3 * pairs.size());
    one.eval(in.data(), pairs.size(), f.data());
    for (size_t k = 0; k < f.size(); ++k)
      ASSERT_LE(error(all[m * f.size() + k], f[k]), test::kBrdfFp32) << "material " << m << " value " << k;
  }
}

TEST(BrdfErrors, BadDirectionsAndMaterials) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  BrdfEvaluator ev(*dev, BrdfModel::Lambert, {Material{}});
  std::vector<double> out(6);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> zero = {0, 0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 1};
  try {
    ev.eval(zero.data(), 2, out.data());
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("direction pair 1: wi"), std::string::npos) << e.what();
  }
  const std::vector<double> bad = {0, 0, 1, 0, nan, 1};
  EXPECT_THROW(ev.eval(bad.data(), 1, out.data()), Error);
  Material m;
  m.roughness = 1.5;
  try {
    BrdfEvaluator b(*dev, BrdfModel::Disney, {m});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("roughness"), std::string::npos) << e.what();
  }
  m.roughness = nan;
  EXPECT_THROW(BrdfEvaluator(*dev, BrdfModel::Disney, {m}), Error);
}

// ---- The engine's own inputs to the kernels, against the reference's -----------------------------

// The reference backend's conversion carries every field of the public Material to the reference's
// own type (brdfbake/reference/brdf.hpp): each set to a value other than its default.
TEST(BrdfConversion, EveryFieldReachesTheReference) {
  Material m;
  m.base_color = {0.1, 0.2, 0.3};
  m.metallic = 0.4;
  m.roughness = 0.6;
  m.subsurface = 0.7;
  m.specular = 0.8;
  m.specular_tint = 0.9;
  m.anisotropic = 0.15;
  m.sheen = 0.25;
  m.sheen_tint = 0.35;
  m.clearcoat = 0.45;
  m.clearcoat_gloss = 0.55;
  m.sheen_color = {0.65, 0.75, 0.85};
  m.sheen_roughness = 0.95;
  m.clearcoat_roughness = 0.05;
  m.ior = 1.33;
  m.specular_factor = 0.66;
  m.specular_color_factor = {1.1, 1.2, 1.3};
  m.diffuse_color = Rgb{0.01, 0.02, 0.03};
  m.specular_color = Rgb{0.04, 0.05, 0.06};
  m.shininess = 77.0;
  m.normalized = false;
  m.distribution = MicrofacetDistribution::Beckmann;
  const reference::BrdfMaterial r = to_reference(m);
  EXPECT_EQ(r.base_color.g, 0.2);
  EXPECT_EQ(r.metallic, 0.4);
  EXPECT_EQ(r.roughness, 0.6);
  EXPECT_EQ(r.subsurface, 0.7);
  EXPECT_EQ(r.specular, 0.8);
  EXPECT_EQ(r.specular_tint, 0.9);
  EXPECT_EQ(r.anisotropic, 0.15);
  EXPECT_EQ(r.sheen, 0.25);
  EXPECT_EQ(r.sheen_tint, 0.35);
  EXPECT_EQ(r.clearcoat, 0.45);
  EXPECT_EQ(r.clearcoat_gloss, 0.55);
  EXPECT_EQ(r.sheen_color.b, 0.85);
  EXPECT_EQ(r.sheen_roughness, 0.95);
  EXPECT_EQ(r.clearcoat_roughness, 0.05);
  EXPECT_EQ(r.ior, 1.33);
  EXPECT_EQ(r.specular_factor, 0.66);
  EXPECT_EQ(r.specular_color_factor.r, 1.1);
  ASSERT_TRUE(r.diffuse_color && r.specular_color && r.shininess);
  EXPECT_EQ(r.diffuse_color->b, 0.03);
  EXPECT_EQ(r.specular_color->r, 0.04);
  EXPECT_EQ(*r.shininess, 77.0);
  EXPECT_FALSE(r.normalized);
  EXPECT_EQ(r.distribution, reference::MicrofacetDistribution::Beckmann);
  for (BrdfModel model : test::all_models<BrdfModel>())
    EXPECT_EQ(std::string(brdf_model_name(model)).empty(), false) << static_cast<int>(to_reference(model));
  EXPECT_EQ(to_reference(BrdfModel::BlinnPhongFromPbr), reference::BrdfModel::BlinnPhongFromPbr);
  EXPECT_EQ(to_reference(BrdfModel::GltfCorrelated), reference::BrdfModel::GltfCorrelated);
}

// KHR_materials_sheen's E(mu): the engine's own quadrature over l (host/src/families/brdf_eval/sheen_albedo.cpp), which
// the kernels' table is built from, against the reference's charlie_albedo over h at twice its order
// and refinement.
TEST(SheenAlbedo, EngineQuadratureMatchesTheReference) {
  for (double r : {0.0, 0.3, 1.0})
    for (double mu : {1e-7, 3e-5, 2e-3, 0.1, 0.45, 0.8, 0.999, 1.0}) {
      const double want =
          reference::charlie_albedo(mu, r, reference::SheenVisibility::EstevezKulla, reference::Quadrature{20, 2});
      EXPECT_NEAR(detail::sheen_albedo_quadrature(mu, r) / std::max(1.0, want), want / std::max(1.0, want),
                  test::kSheenAlbedoEngine)
          << "sheen roughness " << r << " mu " << mu;
    }
}

}  // namespace
}  // namespace brdfbake
