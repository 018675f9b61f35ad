// One test body for every table family (issue 25, item 5): each kind's example request
// (table_kind_example, the family's own small valid request) baked through `Backend` on the
// reference (Backend::open("reference"), the families' reference adapters) and on the device under
// test in fp32 and in fp64, the device's values held to the reference's. A new family is covered
// by its example without a new case here; its tolerance is the one line of `device_tolerance`.
//
// The bound of a kind, absolute below 1 and relative above (as the recorded bounds are):
//   - DFG kinds: the bound the device's result records (calibrated against the converged values),
//     plus the reference's own convergence and, in fp32, the kernel's rounding;
//   - the others: the fp32 / fp64 tolerance of the family's device-against-reference tests
//     (tests/support/tolerances.hpp, where each says why).
//   - the environment families (prefilter, irradiance): per level (and for the SH coefficients), the
//     relative RMS and the largest difference relative to the level's largest value, held to the
//     tolerances of their device-against-reference tests (EnvTolerance), at the sizes those were
//     measured at (test_example); test_prefilter.cpp and test_irradiance.cpp add the other estimators,
//     lobes and sources.
// The preview is not here: its renders against the reference are tests/device/test_preview.cpp's
// (its reference's brute force takes minutes even at the example's size).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "brdfbake/backend.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/tables.hpp"
#include "support/device_fixture.hpp"
#include "support/result_values.hpp"
#include "support/tolerances.hpp"

namespace brdfbake {
namespace {

struct Case {
  TableKind kind;
  Precision precision;
};

// The fp32 or fp64 tolerance of a kind against the reference, for results that record no bound;
// 0 where the device's recorded bound is used, -1 where the kind is not covered yet.
double device_tolerance(TableKind kind, Precision p) {
  const bool fp32 = p == Precision::Fp32;
  switch (kind) {
    case TableKind::Ggx:
    case TableKind::GgxMultiscatter:
    case TableKind::Charlie:
      return 0;
    case TableKind::Fresnel:
      return fp32 ? test::kFresnelFp32 : test::kFresnelFp64;
    case TableKind::ThinFilm:
      return fp32 ? test::kThinFilmFp32 : test::kThinFilmFp64;
    // the reference is fed the example's double directions, the fp32 device their float roundings:
    // kBrdfTableFp32 covers the lobes' response to that (~1e-7 rad)
    case TableKind::Eval:
      return fp32 ? test::kBrdfTableFp32 : test::kBrdfFp64;
    // directional albedo: the device's fixed quadrature against the reference's adaptive one
    case TableKind::Tabulate:
      return test::kBrdfAlbedoQuadrature;
    case TableKind::Prefilter:
    case TableKind::Irradiance:
      return 0;               // per level: env_tolerance
    case TableKind::Preview:  // its renders against the reference: tests/device/test_preview.cpp
      return -1;
  }
  return -1;
}

// The environment families' examples (a 32^2 GGX chain of builtin:studio; its SH and an 8^2
// irradiance cube from a 64^2 source) against the reference, per level.
struct EnvTolerance {
  double rms, max;
};
EnvTolerance env_tolerance(TableKind kind) {
  // The device's pyramid sums texels as boxes, the reference interpolates the source bilinearly
  // (kEnvPrefilterRms / kEnvPrefilterMax, measured on 16^2 - 32^2 cubes; here worst level 0.36 % RMS).
  if (kind == TableKind::Prefilter) return {test::kEnvPrefilterRms, test::kEnvPrefilterMax};
  // The same box-against-tent difference in the cosine convolution (here 4e-4 of the SH, 2e-4 of the cube).
  return {test::kEnvIrradianceDeviceRms, test::kEnvIrradianceDevice};
}

// The lists of values compared level by level: each cube level, or the SH coefficients and each
// level of the irradiance cube.
std::vector<std::vector<double>> env_levels(const BakeResult& r) {
  std::vector<std::vector<double>> out;
  auto add = [&](const auto& list) { out.emplace_back(list.begin(), list.end()); };
  if (const CubeLevels* c = r.cube())
    for (const auto& level : c->levels) add(level);
  if (const IrradianceResult* i = r.irradiance()) {
    add(i->sh.radiance);
    for (const auto& level : i->cube.levels) add(level);
  }
  return out;
}

void expect_env_levels_agree(const BakeResult& got, const BakeResult& want, const std::string& what) {
  const EnvTolerance tol = env_tolerance(got.kind);
  const auto a = env_levels(got), r = env_levels(want);
  ASSERT_EQ(a.size(), r.size());
  ASSERT_FALSE(a.empty());
  for (size_t l = 0; l < a.size(); ++l) {
    ASSERT_EQ(a[l].size(), r[l].size()) << what << " level " << l;
    double sum2 = 0, ref2 = 0, worst = 0, largest = 0;
    for (size_t k = 0; k < a[l].size(); ++k) {
      ASSERT_TRUE(std::isfinite(a[l][k])) << what << " level " << l << " value " << k << " is " << a[l][k];
      const double d = a[l][k] - r[l][k];
      sum2 += d * d, ref2 += r[l][k] * r[l][k];
      worst = std::max(worst, std::fabs(d)), largest = std::max(largest, std::fabs(r[l][k]));
    }
    ASSERT_GT(largest, 0.0) << what << " level " << l << ": the reference is all zero";
    EXPECT_LE(std::sqrt(sum2 / ref2), tol.rms) << what << " level " << l << ": relative RMS";
    EXPECT_LE(worst / largest, tol.max) << what << " level " << l << ": largest difference / largest value";
  }
}

void PrintTo(const Case& c, std::ostream* os) { *os << table_kind_name(c.kind) << " " << precision_name(c.precision); }

std::vector<Case> cases() {
  std::vector<Case> list;
  for (TableKind kind : table_kinds())
    for (Precision p : {Precision::Fp32, Precision::Fp64}) list.push_back({kind, p});
  return list;
}

std::string case_name(const ::testing::TestParamInfo<Case>& i) {
  std::string name = std::string(table_kind_name(i.param.kind)) + "_" + precision_name(i.param.precision);
  std::replace(name.begin(), name.end(), '-', '_');
  return name;
}

// A kind's example as this test bakes it: the environment families' at the sizes their tolerances
// were measured at (8^2 from a sun is below them: the sun's few texels are one conversion apart).
TableExample test_example(TableKind kind) {
  TableExample e = table_kind_example(kind);
  if (kind == TableKind::Prefilter) e.request.params = {{"chain_size", 32.0}, {"min_size", 4.0}};
  if (kind == TableKind::Irradiance) e.request.params = {{"irradiance_size", 8.0}, {"source_size", 64.0}};
  if (table_kind_uses_environment(kind)) e.request.environment = "builtin:studio";
  return e;
}

// The inputs of a kind's example: its pairs, and its environment loaded into `env`.
BakeInputs example_inputs(const TableExample& e, EnvImage& env) {
  BakeInputs inputs;
  if (!e.pairs.empty()) {
    inputs.pairs = e.pairs.data();
    inputs.pair_count = e.pairs.size() / 6;
  }
  if (table_kind_uses_environment(e.request.kind)) {
    env = load_environment(e.request.environment);
    inputs.environment = &env;
  }
  return inputs;
}

// The reference's result of each kind's example, baked once.
const BakeResult& reference_result(TableKind kind) {
  static std::shared_ptr<Backend> reference = Backend::open(std::string("reference"));
  static std::map<TableKind, BakeResult> results;
  auto it = results.find(kind);
  if (it == results.end()) {
    const TableExample e = test_example(kind);
    EnvImage env;
    it = results.emplace(kind, bake_table(e.request, *reference, example_inputs(e, env))).first;
  }
  return it->second;
}

class EveryBackend : public ::testing::TestWithParam<Case> {};

TEST_P(EveryBackend, DeviceAgreesWithTheReference) {
  const Case& c = GetParam();
  const double tolerance = device_tolerance(c.kind, c.precision);
  if (tolerance < 0) GTEST_SKIP() << table_kind_name(c.kind) << ": not covered yet (see the file's header)";
  BRDFBAKE_REQUIRE_DEVICE(dev);
  if (c.precision == Precision::Fp64) BRDFBAKE_REQUIRE_FP64(dev);
  const std::shared_ptr<Backend> device = Backend::open(*dev);

  TableExample e = test_example(c.kind);
  e.request.precision = c.precision;
  EnvImage env;
  const BakeResult got = bake_table(e.request, *device, example_inputs(e, env));
  const BakeResult& want = reference_result(c.kind);
  EXPECT_EQ(got.device.find("reference"), std::string::npos) << got.device;

  if (c.kind == TableKind::Prefilter || c.kind == TableKind::Irradiance) {
    expect_env_levels_agree(got, want, std::string(table_kind_name(c.kind)) + " " + precision_name(c.precision));
    return;
  }
  double bound = tolerance;
  if (bound == 0) {
    ASSERT_TRUE(got.error_bound.has_value()) << table_kind_name(c.kind) << ": the device's result records no bound";
    bound =
        *got.error_bound + test::kReferenceConverged + (c.precision == Precision::Fp32 ? test::kLutFp32Rounding : 0);
  }
  const std::vector<double> a = test::values_of(got), r = test::values_of(want);
  ASSERT_EQ(a.size(), r.size());
  ASSERT_FALSE(a.empty());
  size_t worst = 0;
  double worst_error = -1.0;
  for (size_t k = 0; k < a.size(); ++k) {
    ASSERT_TRUE(std::isfinite(a[k])) << "value " << k << " is " << a[k];
    const double error = std::fabs(a[k] - r[k]) / std::max(1.0, std::fabs(r[k]));
    if (error > worst_error) worst_error = error, worst = k;
  }
  EXPECT_LE(worst_error, bound) << table_kind_name(c.kind) << " " << precision_name(c.precision) << ": value " << worst
                                << " is " << a[worst] << " on the device and " << r[worst] << " on the reference";
}

INSTANTIATE_TEST_SUITE_P(Family, EveryBackend, ::testing::ValuesIn(cases()), case_name);

}  // namespace
}  // namespace brdfbake
