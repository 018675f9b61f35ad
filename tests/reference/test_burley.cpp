// Spot values of the reference's Burley diffuse terms (host/reference/src/burley.cpp); their
// albedos' closed forms are in test_dfg_reference.cpp (BurleyAlbedo) and tests/identities.
#include <gtest/gtest.h>

#include <cmath>

#include "brdfbake/math/conventions.hpp"
#include "brdfbake/reference/burley.hpp"
#include "support/tolerances.hpp"

namespace ref = brdfbake::reference;
namespace test = brdfbake::test;

namespace {

using brdfbake::math::kPi;

}  // namespace

TEST(BurleyReference, RetroReflectionSpotValues) {
  // F_D90 = 1 is Lambert: 1/pi everywhere.
  for (double c : {0.0, 0.3, 1.0}) EXPECT_NEAR(ref::Fd_BurleyF90(c, 0.7, 1.0), 1.0 / kPi, test::kRounding);
  // Grazing light, normal view: f = F_D90 / pi with F_D90 = 0.5 + 2 r (l.h)^2; r = 0.5, l.h = 0.5.
  EXPECT_NEAR(ref::Fd_Burley(1.0, 0.0, 0.5, 0.5), 0.75 / kPi, test::kRounding);
  // Both grazing: F_D90^2 / pi; r = 1, l.h = 1 gives 2.5^2.
  EXPECT_NEAR(ref::Fd_Burley(0.0, 0.0, 1.0, 1.0), 6.25 / kPi, test::kRounding);
  // n.l = 0.5, n.v = 1, r = 0.25, l.h = sqrt(0.75): F_D90 = 0.875, f = (1 - 0.125 / 32) / pi.
  EXPECT_NEAR(ref::Fd_Burley(1.0, 0.5, std::sqrt(0.75), 0.25), (1.0 - 0.125 / 32.0) / kPi, test::kRounding);
}

TEST(BurleyReference, DisneySubsurfaceSpotValues) {
  // F_ss90 = r (l.h)^2 = 1 at r = 1, l.h = 1: F_ss = 1, f = (1.25/pi) (1 / (n.l + n.v) - 0.5 + 0.5).
  EXPECT_NEAR(ref::Fd_DisneySubsurface(0.5, 0.5, 1.0, 1.0), 1.25 / kPi, test::kRounding);
  // Normal view and light: F_ss = 1 (the Schlick weights vanish), f = (1.25/pi)(1/2 - 1/2 + 1/2).
  EXPECT_NEAR(ref::Fd_DisneySubsurface(1.0, 1.0, 1.0, 0.3), 0.625 / kPi, test::kRounding);
}

TEST(BurleyReference, EveryTermIsFiniteAtTheCorners) {
  for (double r : {0.0, 1e-6, 1.0})
    for (double a : {0.0, 1e-6, 1.0})
      for (double b : {0.0, 1e-6, 1.0}) {
        EXPECT_TRUE(std::isfinite(ref::Fd_Burley(a, b, a, r)));
        EXPECT_TRUE(std::isfinite(ref::Fd_DisneySubsurface(a + 1e-7, b + 1e-7, a, r)));
      }
}
