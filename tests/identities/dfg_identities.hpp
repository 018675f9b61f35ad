// One body of DFG identities, run on every backend: the mirror limit, closed forms of the albedos
// (Burley at normal view, the white GGX lobe and Neubelt's sheen at roughness 1) and the bounds of
// the split sum.
//
// tests/reference/test_dfg_reference.cpp instantiates it on the scalar double reference
// (host/reference/src/dfg_lut.cpp), tests/device/test_dfg_lut.cpp through brdfbake::Backend on the
// OpenCL kernels (kernels/dfg_lut.cl, default sample counts) in fp32 and fp64 and on the reference
// backend, each with its tolerances (tests/support/tolerances.hpp). Each executable defines
// make_dfg_backend for its backends.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "identities/backend.hpp"
#include "support/tolerances.hpp"

namespace brdfbake::test {

// The split-sum integrals at one texel (docs/CONVENTIONS.md): GGX with height-correlated Smith V,
// scale = int (1 - Fc) D V n.l, bias = int Fc D V n.l (Fc = (1 - v.h)^5); Burley's diffuse albedo.
struct DfgTexel {
  double scale, bias, diffuse;
};

class DfgBackend {
 public:
  virtual ~DfgBackend() = default;
  // GGX scale, bias and Burley's albedo at each n_dot_v, one roughness.
  virtual std::vector<DfgTexel> ggx(const std::vector<double>& n_dot_v, double roughness) = 0;
  // The Charlie sheen albedo with Neubelt's visibility (Estevez-Kulla's when false).
  virtual std::vector<double> charlie(const std::vector<double>& n_dot_v, double sheen_roughness, bool neubelt) = 0;
};

// Defined by each test executable for the backends it instantiates (sets `out`, or skips or fails).
void make_dfg_backend(Backend backend, std::unique_ptr<DfgBackend>& out);

struct DfgTolerances {
  double mirror;       // the mirror limit at roughness 0 and 1e-3
  double burley;       // Burley's albedo at normal view (a polynomial integrand)
  double closed_form;  // the GGX and Charlie closed forms at roughness 1
  double rounding;     // bounds: scale, bias >= -rounding, scale + bias <= 1 + rounding
};
inline DfgTolerances dfg_tolerances(Backend b) {
  switch (b) {
    case Backend::Reference:
      return {kMirrorLimit, kRounding, kAnalytic, kRounding};
    case Backend::Fp32:
      return {kLutMirrorDevice, kLutFp32Rounding, kLutDefaultBound, kLutFp32Rounding};
    case Backend::Fp64:
      return {kLutMirrorDevice, kLutFp32Rounding, kLutDefaultBound, kLutFp32Rounding};
    // the reference's own, plus float32 storage of values up to ~1 (kLutFp32Rounding)
    case Backend::ReferenceBackend:
      return {kMirrorLimit + kLutFp32Rounding, kLutFp32Rounding, kLutFp32Rounding, kLutFp32Rounding};
  }
  return {};
}

class DfgIdentities : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override { make_dfg_backend(GetParam(), backend_); }
  DfgTolerances tol() const { return dfg_tolerances(GetParam()); }
  std::unique_ptr<DfgBackend> backend_;
};

// As alpha -> 0, D becomes a Dirac delta at h = n and G2 -> 1: scale + bias -> 1 and
// bias -> Fc(v.h = n.v) = (1 - n.v)^5 (Karis 2013).
TEST_P(DfgIdentities, MirrorLimitAtSmallRoughness) {
  const std::vector<double> nv = {1e-3, 0.05, 0.2, 0.3, 0.5, 0.7, 0.8, 1.0};
  for (double roughness : {0.0, 1e-3}) {
    const std::vector<DfgTexel> t = backend_->ggx(nv, roughness);
    for (size_t i = 0; i < nv.size(); ++i) {
      EXPECT_NEAR(t[i].scale + t[i].bias, 1.0, tol().mirror) << nv[i] << " " << roughness;
      EXPECT_NEAR(t[i].bias, std::pow(1.0 - nv[i], 5.0), tol().mirror) << nv[i] << " " << roughness;
    }
  }
}

// Burley's albedo at n.v = 1: l.v = mu, F_D90 = 0.5 + r (1 + mu), albedo = 2 int mu (1 + (F_D90 - 1)
// (1 - mu)^5) dmu = 1 - 1/42 + 2 r (B(2,6) + B(3,6)) = 41/42 + 5 r / 84.
TEST_P(DfgIdentities, BurleyAlbedoAtNormalView) {
  for (double r : {0.0, 0.25, 0.5, 1.0})
    EXPECT_NEAR(backend_->ggx({1.0}, r)[0].diffuse, 41.0 / 42.0 + 5.0 * r / 84.0, tol().burley) << r;
}

// alpha = 1: D = 1/pi for every h, S(c) = 1, V = 1 / (2 (n.l + n.v)), so
// scale + bias = 2 int_0^1 mu / (2 (mu + n.v)) dmu = 1 - n.v ln(1 + 1/n.v).
TEST_P(DfgIdentities, WhiteGgxLobeAtRoughnessOne) {
  const std::vector<double> nv = {1e-3, 0.1, 0.5, 0.9, 1.0};
  const std::vector<DfgTexel> t = backend_->ggx(nv, 1.0);
  for (size_t i = 0; i < nv.size(); ++i)
    EXPECT_NEAR(t[i].scale + t[i].bias, 1.0 - nv[i] * std::log1p(1.0 / nv[i]), tol().closed_form) << nv[i];
}

// alpha = 1, n.v = 1: V = 1/4, D = 3 sin th_h / (2 pi) with sin th_h = sqrt((1 - mu) / 2), so the
// Neubelt sheen albedo is (3/4) (1/sqrt 2) int_0^1 mu sqrt(1 - mu) dmu = (3/4) (1/sqrt 2) (4/15)
// = sqrt(2) / 10.
TEST_P(DfgIdentities, NeubeltSheenAtRoughnessOne) {
  EXPECT_NEAR(backend_->charlie({1.0}, 1.0, true)[0], std::sqrt(2.0) / 10.0, tol().closed_form);
}

// Both parts are integrals of non-negative terms; their sum is the single-scattering albedo, at
// most 1 since G2 <= G1(v) and the visible normals are normalised.
TEST_P(DfgIdentities, ScaleAndBiasAreBounded) {
  const std::vector<double> nv = {0.0, 1e-6, 1e-3, 0.02, 0.2, 0.5, 0.8, 1.0};
  for (double r : {0.0, 1e-3, 0.05, 0.2, 0.5, 0.8, 1.0}) {
    const std::vector<DfgTexel> t = backend_->ggx(nv, r);
    for (size_t i = 0; i < nv.size(); ++i) {
      EXPECT_GE(t[i].scale, -tol().rounding) << nv[i] << " " << r;
      EXPECT_GE(t[i].bias, -tol().rounding) << nv[i] << " " << r;
      EXPECT_LE(t[i].scale + t[i].bias, 1.0 + tol().rounding) << nv[i] << " " << r;
      EXPECT_TRUE(std::isfinite(t[i].diffuse)) << nv[i] << " " << r;
    }
  }
}

}  // namespace brdfbake::test
