// The DFG lookup-table kernels against the scalar double reference, every kind, fp32 and fp64, and
// the DFG identities (tests/identities/dfg_identities.hpp) on the outputs of both backends (the
// device in fp32 and fp64, and the product's reference backend).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include "brdfbake/backend.hpp"
#include "brdfbake/dfg_lut.hpp"
#include "brdfbake/error.hpp"
#include "identities/dfg_identities.hpp"
#include "support/device_fixture.hpp"
#include "support/tolerances.hpp"

namespace brdfbake {
namespace test {
namespace {

// bake_lut at explicit points, default sample count, on a brdfbake::Backend: the OpenCL device or the
// product's reference backend (the family's two kernels, host/src/families/dfg_lut/).
class BackendDfg : public DfgBackend {
 public:
  BackendDfg(std::shared_ptr<brdfbake::Backend> backend, Precision precision)
      : backend_(std::move(backend)), precision_(precision) {}
  std::vector<DfgTexel> ggx(const std::vector<double>& n_dot_v, double roughness) override {
    const Table t = bake(LutKind::Ggx, n_dot_v, roughness, SheenVisibility::EstevezKulla);
    std::vector<DfgTexel> out;
    for (int i = 0; i < t.width; ++i) out.push_back({t.at(i, 0, 0), t.at(i, 0, 1), t.at(i, 0, 2)});
    return out;
  }
  std::vector<double> charlie(const std::vector<double>& n_dot_v, double sheen_roughness, bool neubelt) override {
    const Table t = bake(LutKind::Charlie, n_dot_v, sheen_roughness,
                         neubelt ? SheenVisibility::Neubelt : SheenVisibility::EstevezKulla);
    std::vector<double> out;
    for (int i = 0; i < t.width; ++i) out.push_back(t.at(i, 0, 0));
    return out;
  }

 private:
  Table bake(LutKind kind, const std::vector<double>& n_dot_v, double roughness, SheenVisibility visibility) {
    LutSpec s;
    s.kind = kind;
    s.n_dot_v = n_dot_v;
    s.roughness = {roughness};
    s.precision = precision_;
    s.sheen_visibility = visibility;
    return bake_lut(*backend_, s);
  }
  std::shared_ptr<brdfbake::Backend> backend_;
  Precision precision_;
};

}  // namespace

void make_dfg_backend(Backend b, std::unique_ptr<DfgBackend>& out) {
  if (b == Backend::ReferenceBackend) {
    out = std::make_unique<BackendDfg>(brdfbake::Backend::open("reference"), Precision::Fp64);
    return;
  }
  Device* dev = test_device();
  if (!dev) {
    if (allow_no_device()) GTEST_SKIP() << "no OpenCL device (allowed)";
    FAIL() << "this test needs an OpenCL device and found none";
  }
  if (b == Backend::Fp64 && !dev->info().fp64) GTEST_SKIP() << "device '" << dev->info().name << "' has no fp64";
  out = std::make_unique<BackendDfg>(brdfbake::Backend::open(*dev),
                                     b == Backend::Fp64 ? Precision::Fp64 : Precision::Fp32);
}

INSTANTIATE_TEST_SUITE_P(Device, DfgIdentities, ::testing::Values(Backend::Fp32, Backend::Fp64), BackendName());
INSTANTIATE_TEST_SUITE_P(ReferenceBackend, DfgIdentities, ::testing::Values(Backend::ReferenceBackend), BackendName());

}  // namespace test

namespace {

using test::kLutDefaultBound;
using test::kLutFp32Rounding;
using test::kLutQuadratureFp64;

struct Diff {
  double max_abs = 0;
  int at_i = -1, at_j = -1, at_c = -1;
};

Diff compare(const Table& a, const Table& b) {
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(a.channels, b.channels);
  Diff d;
  for (int j = 0; j < a.height; ++j)
    for (int i = 0; i < a.width; ++i)
      for (int c = 0; c < a.channel_count(); ++c) {
        // absolute below 1, relative above (Charlie's albedo reaches ~1e3 at grazing and sheen
        // roughness 0, where fp32 keeps 7 significant digits, not 1e-4 absolute)
        const double want = double(b.at(i, j, c));
        const double e = std::fabs(double(a.at(i, j, c)) - want) / std::max(1.0, std::fabs(want));
        if (e > d.max_abs) d = {e, i, j, c};
      }
  return d;
}

void expect_finite_and_bounded(const Table& t) {
  for (int j = 0; j < t.height; ++j)
    for (int i = 0; i < t.width; ++i) {
      for (int c = 0; c < t.channel_count(); ++c) {
        const float v = t.at(i, j, c);
        ASSERT_TRUE(std::isfinite(v)) << t.channels[size_t(c)] << " at " << i << "," << j;
        ASSERT_GE(v, 0.0f) << t.channels[size_t(c)] << " at " << i << "," << j;
      }
      const std::string kind = t.meta("kind");
      if (kind == "ggx") {  // scale + bias is the albedo of a white (F = 1) GGX lobe: <= 1
        EXPECT_LE(t.at(i, j, 0) + t.at(i, j, 1), 1.0f + 1e-6f) << i << "," << j;
      } else if (kind == "ggx-multiscatter") {  // bias <= albedo <= 1
        EXPECT_LE(t.at(i, j, 0), t.at(i, j, 1) + 1e-6f);
        EXPECT_LE(t.at(i, j, 1), 1.0f + 1e-6f);
      }
      // Charlie with either visibility is not energy conserving: its albedo exceeds 1 at low sheen
      // roughness and grazing view (1.7172 at n.v = 1/32, sheen roughness 1/24, by three independent
      // quadratures), so only finiteness and sign bound it.
    }
}

class LutVsReference : public ::testing::TestWithParam<std::tuple<LutKind, Precision>> {};

// The default sample count promises kLutDefaultBound over the 128x128 table; a 16x12 table at
// its own cell centres (non-square) is held to the same bound.
TEST_P(LutVsReference, DefaultSamplesMeetTheBound) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  const auto [kind, precision] = GetParam();
  if (precision == Precision::Fp64) {
    BRDFBAKE_REQUIRE_FP64(dev);
  }
  LutSpec spec;
  spec.kind = kind;
  spec.width = 16;
  spec.height = 12;
  spec.precision = precision;
  const Table got = bake_lut(*dev, spec);
  const Table want = bake_lut_reference(spec);
  expect_finite_and_bounded(got);
  const Diff d = compare(got, want);
  EXPECT_LE(d.max_abs, kLutDefaultBound + kLutFp32Rounding)
      << "channel " << d.at_c << " at (" << d.at_i << ", " << d.at_j << ")";
}

// The hard corners: grazing (down to n_dot_v = 1e-6 and exactly 0), normal incidence, mirror
// (roughness 0) and roughest (1).
TEST_P(LutVsReference, Corners) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  const auto [kind, precision] = GetParam();
  if (precision == Precision::Fp64) {
    BRDFBAKE_REQUIRE_FP64(dev);
  }
  LutSpec spec;
  spec.kind = kind;
  spec.precision = precision;
  spec.n_dot_v = {0.0, 1e-6, 1e-3, 0.02, 0.5, 0.999, 1.0};
  spec.roughness = {0.0, 1e-3, 0.02, 0.5, 0.98, 1.0};
  const Table got = bake_lut(*dev, spec);
  expect_finite_and_bounded(got);
  LutSpec ref = spec;
  ref.n_dot_v.front() = 1e-7;  // n.v = 0 stands for its limit, as the kernel documents
  const Table want = bake_lut_reference(ref);
  for (int j = 0; j < got.height; ++j)
    for (int i = 0; i < got.width; ++i)
      for (int c = 0; c < got.channel_count(); ++c) {
        const double w = want.at(i, j, c);
        const double e = std::fabs(double(got.at(i, j, c)) - w) / std::max(1.0, std::fabs(w));
        const bool degenerate = kind == LutKind::Charlie && precision == Precision::Fp32 &&
                                spec.n_dot_v[size_t(i)] <= 1e-6 && spec.roughness[size_t(j)] <= 1e-3;
        EXPECT_LE(e, degenerate ? test::kCharlieDegenerateFp32 : kLutDefaultBound + kLutFp32Rounding)
            << "channel " << c << " at n.v = " << spec.n_dot_v[size_t(i)]
            << ", roughness = " << spec.roughness[size_t(j)] << ": " << got.at(i, j, c) << " vs " << w;
      }
}

INSTANTIATE_TEST_SUITE_P(AllKinds, LutVsReference,
                         ::testing::Combine(::testing::Values(LutKind::Ggx, LutKind::GgxMultiscatter, LutKind::Charlie),
                                            ::testing::Values(Precision::Fp32, Precision::Fp64)),
                         [](const auto& param_info) {
                           std::string n = lut_kind_name(std::get<0>(param_info.param));
                           std::replace(n.begin(), n.end(), '-', '_');
                           return n + "_" + precision_name(std::get<1>(param_info.param));
                         });

// The mirror limit and Burley's closed form at normal incidence are in the identity body
// (tests/identities/dfg_identities.hpp), with the reference's.

// Every texel is computed on its own: a 1x1 table equals the same cell of a larger table
// (different launch shapes and work-group sizes) bit for bit.
TEST(LutDevice, IndependentOfLaunchShape) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  LutSpec big;
  big.width = 24;
  big.height = 20;
  const Table all = bake_lut(*dev, big);
  for (auto [i, j] : {std::pair{0, 0}, std::pair{23, 19}, std::pair{7, 13}}) {
    LutSpec one;
    one.n_dot_v = {(i + 0.5) / 24};
    one.roughness = {(j + 0.5) / 20};
    const Table t = bake_lut(*dev, one);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(t.at(0, 0, c), all.at(i, j, c)) << i << "," << j;
  }
}

TEST(LutDevice, OneByOneTable) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  LutSpec spec;
  spec.width = 1;
  spec.height = 1;
  const Table t = bake_lut(*dev, spec);
  const Table r = bake_lut_reference(spec);
  ASSERT_EQ(t.width, 1);
  ASSERT_EQ(t.height, 1);
  EXPECT_LE(compare(t, r).max_abs, kLutDefaultBound + kLutFp32Rounding);
}

// At a high count, fp64 quadrature converges to the reference far below the default bound.
TEST(LutDevice, QuadratureConvergesInFp64) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  BRDFBAKE_REQUIRE_FP64(dev);
  LutSpec spec;
  spec.width = 8;
  spec.height = 8;
  spec.samples = 8192;
  spec.precision = Precision::Fp64;
  for (LutKind k : {LutKind::Ggx, LutKind::Charlie}) {
    spec.kind = k;
    const Diff d = compare(bake_lut(*dev, spec), bake_lut_reference(spec));
    EXPECT_LE(d.max_abs, kLutQuadratureFp64)
        << lut_kind_name(k) << " channel " << d.at_c << " at (" << d.at_i << ", " << d.at_j << ")";
  }
}

// The Monte Carlo estimators agree with the reference within their own calibrated error.
TEST(LutDevice, MonteCarloEstimators) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  struct Case {
    LutKind kind;
    Estimator est;
    int samples;
  };
  for (const Case c :
       {Case{LutKind::Ggx, Estimator::Vndf, 4096}, Case{LutKind::Ggx, Estimator::Ndf, 4096},
        Case{LutKind::Charlie, Estimator::Ndf, 4096}, Case{LutKind::Charlie, Estimator::Uniform, 4096}}) {
    LutSpec spec;
    spec.kind = c.kind;
    spec.estimator = c.est;
    spec.samples = c.samples;
    spec.width = 8;
    spec.height = 8;
    const double bound = lut_error_bound(c.kind, c.est, Precision::Fp32, c.samples);
    ASSERT_GT(bound, 0) << "no calibration for " << estimator_name(c.est);
    const Diff d = compare(bake_lut(*dev, spec), bake_lut_reference(spec));
    // The calibration is the max over 128x128 cells; an 8x8 subset of coarser cells stays below it.
    EXPECT_LE(d.max_abs, bound + kLutFp32Rounding) << lut_kind_name(c.kind) << "/" << estimator_name(c.est);
  }
}

TEST(LutSpecErrors, RejectsBadInput) {
  LutSpec s;
  s.width = 0;
  EXPECT_THROW(resolve_lut_spec(s), Error);
  s.width = 4;
  s.samples = -3;
  EXPECT_THROW(resolve_lut_spec(s), Error);
  s.samples = 0;
  s.max_error = std::nan("");
  EXPECT_THROW(resolve_lut_spec(s), Error);
  s.max_error = 0;
  s.kind = LutKind::Charlie;
  s.estimator = Estimator::Vndf;
  EXPECT_THROW(resolve_lut_spec(s), Error);
  EXPECT_THROW(lut_kind_from_name("ggx2"), Error);
  EXPECT_THROW(estimator_from_name("mc"), Error);
  s.estimator = Estimator::Quadrature;
  s.max_error = 1e-30;
  EXPECT_THROW(resolve_lut_spec(s), Error);
}

TEST(LutSpecErrors, MaxErrorPicksACalibratedCount) {
  LutSpec s;
  s.max_error = 1e-4;
  const LutSpec r = resolve_lut_spec(s);
  EXPECT_GT(r.samples, 0);
  EXPECT_LE(lut_error_bound(LutKind::Ggx, Estimator::Quadrature, Precision::Fp32, r.samples), 1e-4);
}

}  // namespace
}  // namespace brdfbake
