// The material presets (product data, host/src/material_presets.cpp): the table's shape, their exact
// F0 against the scalar reference's conductor, the published hard-coded F0 values, and what the
// F82-tint fit leaves on the preset metals.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <utility>
#include <vector>

#include "brdfbake/fresnel.hpp"
#include "brdfbake/material_presets.hpp"
#include "brdfbake/reference/fresnel.hpp"
#include "support/tolerances.hpp"

namespace brdfbake {
namespace {

TEST(MaterialPresets, TableIsWellFormed) {
  std::set<std::string> names;
  int conductors = 0, dielectrics = 0;
  for (const MaterialPreset& p : material_presets()) {
    EXPECT_TRUE(names.insert(p.name).second) << "duplicate " << p.name;
    EXPECT_EQ(find_material_preset(p.name), &p);
    EXPECT_FALSE(p.nk_source.empty()) << p.name;
    EXPECT_EQ(p.common_f0.has_value(), !p.common_f0_source.empty()) << p.name;
    for (double n : {p.n.r, p.n.g, p.n.b}) EXPECT_GT(n, 0.0) << p.name;
    if (p.kind == MaterialKind::Conductor) {
      ++conductors;
      for (double k : {p.k.r, p.k.g, p.k.b}) EXPECT_GT(k, 1.0) << p.name;
    } else {
      ++dielectrics;
      EXPECT_EQ(p.k.r + p.k.g + p.k.b, 0.0) << p.name;
      for (double n : {p.n.r, p.n.g, p.n.b}) EXPECT_GT(n, 1.0) << p.name;
      EXPECT_GE(p.n.b, p.n.r) << p.name << ": normal dispersion, n falls with wavelength";
    }
  }
  for (const char* required : {"gold", "silver", "copper", "aluminium", "iron", "chromium", "titanium", "nickel",
                               "platinum", "water", "glass", "diamond", "skin", "ice", "pmma", "polycarbonate"})
    EXPECT_NE(find_material_preset(required), nullptr) << required;
  EXPECT_EQ(find_material_preset("unobtainium"), nullptr);
  EXPECT_GE(conductors, 9);
  EXPECT_GE(dielectrics, 8);
}

// exact_f0 (the product's closed form) against the reference's exact conductor at normal incidence.
TEST(MaterialPresets, ExactF0IsAReflectanceAndMatchesTheExactModel) {
  for (const MaterialPreset& p : material_presets()) {
    const Rgb f = exact_f0(p);
    const Rgb g = reference::fresnel_conductor(1.0, p.n, p.k);
    for (const auto& [a, b] : {std::pair{f.r, g.r}, std::pair{f.g, g.g}, std::pair{f.b, g.b}}) {
      EXPECT_GE(a, 0.0) << p.name;
      EXPECT_LE(a, 1.0) << p.name;
      EXPECT_NEAR(a, b, test::kFresnelReferenceRounding) << p.name;
    }
  }
}

TEST(MaterialPresets, GoldIsYellowAndWaterIsTwoPercent) {
  const Rgb gold = exact_f0(*find_material_preset("gold"));
  EXPECT_GT(gold.r, gold.b);
  EXPECT_GT(gold.r, 0.9);   // Johnson & Christy 1972 at 630 nm: 0.942
  EXPECT_LT(gold.b, 0.45);  // at 465 nm, above the interband edge: 0.404
  const Rgb water = exact_f0(*find_material_preset("water"));
  for (double f : {water.r, water.g, water.b}) EXPECT_NEAR(f, 0.0204, test::kWaterF0Spread);
  // At the sodium D line, n = 1.333: ((0.333) / (2.333))^2 = 0.020373.
  EXPECT_NEAR(reference::f0_from_ior(1.0, 1.333), 0.020373, test::kFresnelSpotValue);
}

TEST(MaterialPresets, HardCodedF0AgreesWithTheMeasuredIndices) {
  int dielectrics = 0;
  for (const MaterialPreset& p : material_presets()) {
    if (!p.common_f0) continue;
    const Rgb f = exact_f0(p);
    const bool conductor = p.kind == MaterialKind::Conductor;
    dielectrics += !conductor;
    const double gap = conductor ? test::kCommonF0GapConductor : test::kCommonF0GapDielectric;
    EXPECT_NEAR(f.r, p.common_f0->r, gap) << p.name;
    EXPECT_NEAR(f.g, p.common_f0->g, gap) << p.name;
    EXPECT_NEAR(f.b, p.common_f0->b, gap) << p.name;
  }
  EXPECT_GE(dielectrics, 7) << "the dielectric bound checked nothing";
}

// The reference's F82-tint fit on every preset metal and channel: exact at its pin, and within a few
// hundredths of the exact conductor everywhere; fit_conductor (the product's) reports the same.
TEST(MaterialPresets, FittedF82TracksTheExactConductor) {
  for (const MaterialPreset& p : material_presets()) {
    if (p.kind != MaterialKind::Conductor) continue;
    const ConductorFit fit = fit_conductor(p.n, p.k);
    for (int c = 0; c < 3; ++c) {
      const double n = c == 0 ? p.n.r : c == 1 ? p.n.g : p.n.b, k = c == 0 ? p.k.r : c == 1 ? p.k.g : p.k.b;
      const double f0 = reference::schlick_f0_from_conductor(n, k), tint = reference::fit_f82_tint(n, k);
      EXPECT_NEAR(reference::fresnel_f82_tint(reference::kF82Cos, f0, tint),
                  reference::fresnel_conductor(reference::kF82Cos, n, k), test::kFresnelReferenceRounding)
          << p.name << " channel " << c;
      const reference::FresnelFitError e =
          reference::fresnel_fit_error([&](double x) { return reference::fresnel_f82_tint(x, f0, tint); },
                                       [&](double x) { return reference::fresnel_conductor(x, n, k); });
      EXPECT_LE(e.max_abs, test::kF82FitMaxError) << p.name << " channel " << c << " worst at cos " << e.cos_at_max;
      const double reported = c == 0 ? fit.f82_max_error.r : c == 1 ? fit.f82_max_error.g : fit.f82_max_error.b;
      EXPECT_NEAR(reported, e.max_abs, test::kRounding) << p.name << " channel " << c;
    }
  }
}

}  // namespace
}  // namespace brdfbake
