// The thin-film table on the device against the scalar double reference.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "brdfbake/reference/thin_film.hpp"
#include "brdfbake/tables.hpp"
#include "brdfbake/thin_film.hpp"
#include "support/device_fixture.hpp"
#include "support/tolerances.hpp"

namespace {

using namespace brdfbake;

using test::kThinFilmFp32;
using test::kThinFilmFp64;

std::string detail_format(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

void compare(Device& dev, Precision p, double tolerance) {
  ThinFilmSpec r;
  r.film_ior = 1.8;
  r.base_f0 = Rgb{0.9, 0.5, 0.04};
  r.thickness_min = 0.0;
  r.thickness_max = 1200.0;
  r.width = 33;
  r.height = 17;
  r.precision = p;
  const Table t = bake_thin_film(dev, r);
  ASSERT_EQ(t.width, 33);
  ASSERT_EQ(t.height, 17);
  reference::ThinFilm f;
  f.film_ior = 1.8;
  f.base_f0 = *r.base_f0;
  double worst = 0.0;
  for (int j = 0; j < t.height; ++j)
    for (int i = 0; i < t.width; ++i) {
      const Rgb v = reference::thin_film_fresnel(t.x[size_t(i)], t.y[size_t(j)], f);
      worst = std::max({worst, std::fabs(double(t.at(i, j, 0)) - v.r), std::fabs(double(t.at(i, j, 1)) - v.g),
                        std::fabs(double(t.at(i, j, 2)) - v.b)});
    }
  // fp64 results are stored as float: allow the storage rounding on top.
  EXPECT_LT(worst, tolerance + (p == Precision::Fp64 ? 1.2e-7 : 0.0));
  // The same table as the family bakes it: the measured bound it records.
  TableRequest q;
  q.kind = TableKind::ThinFilm;
  q.params = {{"film_ior", 1.8},      {"base_f0", std::vector<double>{0.9, 0.5, 0.04}},
              {"thickness_min", 0.0}, {"thickness_max", 1200.0},
              {"size", 33.0},         {"height", 17.0}};
  q.precision = p;
  validate_table(q);
  const BakeResult res = bake_table(q, *Backend::open(dev));
  ASSERT_TRUE(res.error_bound.has_value());
  EXPECT_LE(*res.error_bound, tolerance + 1.2e-7) << "the measured bound";
  // Both tables are stored as float32: the bound misses at most their rounding (1.2e-7 below 1).
  EXPECT_GE(*res.error_bound + 1.2e-7, worst) << "the bound is the measured max difference";
  EXPECT_EQ(res.table()->meta("error_bound"), detail_format(*res.error_bound)) << "and the file records it";
}

TEST(ThinFilmDevice, MatchesTheReferenceFp32) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  compare(*dev, Precision::Fp32, kThinFilmFp32);
}

TEST(ThinFilmDevice, MatchesTheReferenceFp64) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  BRDFBAKE_REQUIRE_FP64(dev);
  compare(*dev, Precision::Fp64, kThinFilmFp64);
}

TEST(ThinFilmDevice, DielectricBaseAndOneThickness) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  ThinFilmSpec r;
  r.base_ior = 1.5;
  r.thickness_min = r.thickness_max = 400.0;
  r.width = 8;
  const Table t = bake_thin_film(*dev, r);
  EXPECT_EQ(t.y.size(), 1u);
  EXPECT_DOUBLE_EQ(t.y[0], 400.0);
  EXPECT_EQ(t.meta("base_ior"), "1.5");
  const Rgb v = reference::thin_film_fresnel(t.x[3], 400.0, reference::ThinFilm{1.0, 1.3, {0.04, 0.04, 0.04}});
  EXPECT_NEAR(double(t.at(3, 0, 1)), v.g, kThinFilmFp32);
}

}  // namespace
