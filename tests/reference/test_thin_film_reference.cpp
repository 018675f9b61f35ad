// The thin-film interference Fresnel reference (KHR_materials_iridescence): its identities.
#include <gtest/gtest.h>

#include <cmath>

#include "brdfbake/reference/thin_film.hpp"
#include "support/tolerances.hpp"

namespace {

using namespace brdfbake::reference;
using brdfbake::Rgb;

using brdfbake::test::kSensorWhite;
constexpr double kClosedForm = brdfbake::test::kThinFilmClosedForm;
constexpr double kIncoherent = brdfbake::test::kThinFilmIncoherent;

double max3(const Rgb& c) { return std::max(c.r, std::max(c.g, c.b)); }

TEST(ThinFilmReference, IorAndF0AreInverse) {
  for (double n : {1.0, 1.33, 1.5, 2.42, 3.0}) {
    EXPECT_NEAR(thin_film_f0_to_ior(thin_film_ior_to_f0(n, 1.0)), n, kClosedForm * n) << n;
  }
  EXPECT_NEAR(thin_film_ior_to_f0(1.5, 1.0), 0.04, kClosedForm);
  EXPECT_TRUE(std::isfinite(thin_film_f0_to_ior(1.0))) << "F0 = 1 is guarded (0.9999)";
}

TEST(ThinFilmReference, SensorIsWhiteAtZeroPathDifference) {
  // Y(0) = 1 by the normalisation; x-bar and z-bar integrate to the same within the fits' digits:
  // the sensor sees an equal-energy white, whose linear Rec. 709 value is M (1, 1, 1).
  const Rgb s = thin_film_sensitivity(0.0, Rgb{0, 0, 0});
  EXPECT_NEAR(s.r, 3.2404542 - 1.5371385 - 0.4985314, kSensorWhite * 3.2);
  EXPECT_NEAR(s.g, -0.9692660 + 1.8760108 + 0.0415560, kSensorWhite * 1.9);
  EXPECT_NEAR(s.b, 0.0556434 - 0.2040259 + 1.0572252, kSensorWhite * 1.1);
  // A phase shift of pi flips the sign; large path differences average out.
  const Rgb flipped = thin_film_sensitivity(0.0, Rgb{M_PI, M_PI, M_PI});
  EXPECT_NEAR(flipped.g, -s.g, kClosedForm);
  EXPECT_LT(std::fabs(thin_film_sensitivity(20000.0, Rgb{0, 0, 0}).g), 1e-25);  // exp(-68) of the widest fit
}

TEST(ThinFilmReference, ThickFilmsAreTheIncoherentSum) {
  ThinFilm f;
  f.film_ior = 1.8;
  f.base_f0 = {0.04, 0.04, 0.04};
  for (double c : {0.05, 0.3, 0.7, 1.0}) {
    const Rgb coherent = thin_film_fresnel(c, 20000.0, f);
    const Rgb incoherent = thin_film_incoherent(c, 20000.0, f);
    EXPECT_NEAR(coherent.r, incoherent.r, kIncoherent) << c;
    EXPECT_NEAR(coherent.g, incoherent.g, kIncoherent) << c;
    EXPECT_NEAR(coherent.b, incoherent.b, kIncoherent) << c;
  }
  // The incoherent sum itself: Stokes' two-interface formula at normal incidence.
  const double r12 = std::pow((1.8 - 1.0) / 2.8, 2), r23 = std::pow((1.5 - 1.8) / 3.3, 2);
  const double expected = r12 + (1 - r12) * (1 - r12) * r23 / (1 - r12 * r23);
  EXPECT_NEAR(thin_film_incoherent(1.0, 500.0, f).g, expected, kClosedForm);
}

TEST(ThinFilmReference, QuarterWaveCoatingReducesReflection) {
  // A quarter-wave film of index sqrt(1.5) on glass cancels the reflection at its design
  // wavelength (550 nm); over the visible spectrum the green channel drops far below the bare 4%.
  ThinFilm f;
  f.film_ior = std::sqrt(1.5);
  f.base_f0 = {0.04, 0.04, 0.04};
  const Rgb coated = thin_film_fresnel(1.0, 550.0 / (4.0 * f.film_ior), f);
  EXPECT_LT(coated.g, 0.01);
  // A half-wave film is "absent" at its design wavelength: back near the bare 4%.
  const Rgb half = thin_film_fresnel(1.0, 550.0 / (2.0 * f.film_ior), f);
  EXPECT_GT(half.g, 0.025);
}

TEST(ThinFilmReference, TotalInternalReflectionAndRange) {
  ThinFilm f;
  f.outside_ior = 1.5;
  f.film_ior = 1.2;
  const Rgb tir = thin_film_fresnel(0.1, 300.0, f);  // past asin(1.2 / 1.5)
  EXPECT_EQ(tir.r, 1.0);
  EXPECT_EQ(tir.g, 1.0);
  EXPECT_EQ(tir.b, 1.0);
  // Everywhere finite and non-negative (negatives are out of gamut and clamped), including
  // cosines a hair outside [0, 1] and zero thickness.
  ThinFilm g;
  g.film_ior = 1.8;
  g.base_f0 = {0.9, 0.6, 0.2};
  for (double c : {-1e-9, 0.0, 0.5, 1.0, 1.0 + 1e-9})
    for (double d : {0.0, 0.01, 100.0, 400.0, 1200.0}) {
      const Rgb v = thin_film_fresnel(c, d, g);
      EXPECT_TRUE(std::isfinite(max3(v))) << c << " " << d;
      EXPECT_GE(std::min(v.r, std::min(v.g, v.b)), 0.0) << c << " " << d;
    }
}

}  // namespace
