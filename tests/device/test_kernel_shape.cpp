// The kernels' work shapes (issue 36, docs/DEVICES.md "Kernel shapes"): every hot kernel has a CPU
// shape (blocks of texels a work-item, float16 vectors: what PoCL's vectoriser fills) and a GPU shape
// (a work-item a texel, pixel or pair), chosen from the device's type, or forced with
// --kernel-shape / BRDFBAKE_KERNEL_SHAPE. Here:
//   - the CPU shape's outputs are those the kernels gave before the GPU shapes existed: a digest of
//     every value of each family's cases (tests/support/family_cases.hpp and a few larger ones),
//     recorded on this project's CI device (tests/device/cpu_shape_digests.json: PoCL's CPU device
//     and driver version; on another device or driver the test skips, saying which), and
//   - the GPU shape on the same device agrees with the CPU shape within each family's bound (the
//     bound the result records, else its fp32 tolerance), so that the GPU shape is tested on every
//     machine, not only on a GPU; ctest also runs the families' own reference tests in the GPU shape
//     (KernelShape.GpuShapeFamilyTests) and Oclgrind runs it by default (a GPU-type device).
// BRDFBAKE_RECORD_SHAPE_DIGESTS=FILE writes the digests of this device to FILE instead of checking.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "brdfbake/backend.hpp"
#include "brdfbake/device.hpp"
#include "brdfbake/error.hpp"
#include "families/brdf_eval/model.hpp"
#include "support/family_cases.hpp"
#include "support/result_values.hpp"

namespace brdfbake {
namespace {

using test::FamilyCase;

// The cases of every family, and larger ones where a shape has more than one block to walk: a 32^2
// chain (4 x 4 blocks of 8 x 8 texels a face in the CPU shape), a 32^2 DFG table, Charlie at 16^2.
std::vector<FamilyCase> shape_cases() {
  std::vector<FamilyCase> list = test::family_cases();
  list.push_back({"shape_prefilter_ggx_32", R"({"kind": "prefilter", "environment": "builtin:sun", "size": 32,
                                               "min_size": 8})",
                  test::kEnvFp32VsFp64});
  list.push_back({"shape_prefilter_charlie_16", R"({"kind": "prefilter", "environment": "builtin:sun",
                                                   "distribution": "charlie", "size": 16, "min_size": 8})",
                  test::kEnvFp32VsFp64});
  list.push_back({"shape_lut_ggx_32", R"({"kind": "ggx", "size": 32, "samples": 512})", 0});
  return list;
}

// FNV-1a, 64 bits, over the bit patterns of the values.
uint64_t digest(const std::vector<double>& values) {
  uint64_t h = 1469598103934665603ull;
  for (double v : values) {
    uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    for (int b = 0; b < 8; ++b) {
      h ^= (bits >> (8 * b)) & 0xffu;
      h *= 1099511628211ull;
    }
  }
  return h;
}

std::string hex(uint64_t h) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

std::vector<double> bake_values(const FamilyCase& c, Backend& backend) {
  const std::unique_ptr<test::PreparedCase> p = test::prepare_case(c);
  return test::values_of(bake_table(p->request(), backend, p->inputs));
}

std::string digest_file() { return std::string(BRDFBAKE_SOURCE_DIR) + "/tests/device/cpu_shape_digests.json"; }

TEST(KernelShape, CpuShapeOutputsAreThoseRecordedBeforeTheGpuShapes) {
  DeviceInfo info;
  try {
    info = select_device("cpu");
  } catch (const std::exception& e) {
    GTEST_SKIP() << "no OpenCL CPU device: " << e.what();
  }
  info.kernel_shape = "cpu";
  const std::shared_ptr<Backend> backend = Backend::open(Device::open(info));
  if (const char* out = std::getenv("BRDFBAKE_RECORD_SHAPE_DIGESTS")) {
    nlohmann::json j;
    j["device"] = info.name;
    j["driver_version"] = info.driver_version;
    j["platform_version"] = info.platform_version;
    for (const FamilyCase& c : shape_cases()) j["digests"][c.name] = hex(digest(bake_values(c, *backend)));
    std::ofstream(out) << j.dump(2) << "\n";
    GTEST_SKIP() << "recorded the digests in " << out;
  }
  std::ifstream in(digest_file());
  ASSERT_TRUE(in) << "cannot read " << digest_file();
  const nlohmann::json j = nlohmann::json::parse(in);
  const std::string device = j.at("device"), driver = j.at("driver_version"), platform = j.at("platform_version");
  if (device != info.name || driver != info.driver_version || platform != info.platform_version)
    GTEST_SKIP() << "the digests were recorded on '" << device << "' (" << platform << ", driver " << driver
                 << "), this device is '" << info.name << "' (" << info.platform_version << ", driver "
                 << info.driver_version << "): a compiler's rounding differs between them";
  size_t checked = 0;
  for (const FamilyCase& c : shape_cases()) {
    ASSERT_TRUE(j.at("digests").contains(c.name)) << c.name << " has no recorded digest";
    EXPECT_EQ(hex(digest(bake_values(c, *backend))), j.at("digests").at(c.name).get<std::string>()) << c.name;
    ++checked;
  }
  EXPECT_EQ(checked, j.at("digests").size()) << "a recorded case is no longer baked";
}

// The GPU shape on the first CPU device (PoCL here) against the CPU shape on the same device: each
// value within the bound the result records (absolute below 1, relative above, as the bounds are),
// else the family's fp32 tolerance (tests/support/tolerances.hpp). The two shapes sum in different
// orders (lanes, blocks against texels), so they agree to rounding, not to the bit.
class GpuShape : public ::testing::TestWithParam<FamilyCase> {};

TEST_P(GpuShape, AgreesWithTheCpuShapeOnTheSameDevice) {
  DeviceInfo info;
  try {
    info = select_device("cpu");
  } catch (const std::exception& e) {
    GTEST_SKIP() << "no OpenCL CPU device: " << e.what();
  }
  static std::shared_ptr<Backend>* cpu = nullptr;  // opened once for every case, never destroyed
  static std::shared_ptr<Backend>* gpu = nullptr;
  if (!cpu) {
    info.kernel_shape = "cpu";
    cpu = new std::shared_ptr<Backend>(Backend::open(Device::open(info)));
    info.kernel_shape = "gpu";
    gpu = new std::shared_ptr<Backend>(Backend::open(Device::open(info)));
  }
  ASSERT_EQ((*cpu)->device()->info().kernel_shape, "cpu");
  ASSERT_EQ((*gpu)->device()->info().kernel_shape, "gpu");
  const FamilyCase& c = GetParam();
  const std::unique_ptr<test::PreparedCase> p = test::prepare_case(c);
  const BakeResult a = bake_table(p->request(), **cpu, p->inputs);
  const BakeResult g = bake_table(p->request(), **gpu, p->inputs);
  const std::vector<double> va = test::values_of(a), vg = test::values_of(g);
  ASSERT_EQ(va.size(), vg.size());
  ASSERT_FALSE(va.empty());
  const double bound = a.error_bound ? *a.error_bound : c.tolerance;
  ASSERT_GT(bound, 0.0) << c.name << ": no bound and no tolerance";
  size_t worst = 0;
  double worst_excess = -1.0;
  for (size_t k = 0; k < va.size(); ++k) {
    ASSERT_TRUE(std::isfinite(vg[k])) << c.name << ": value " << k << " in the GPU shape is " << vg[k];
    const double excess = std::fabs(vg[k] - va[k]) / std::max(1.0, std::fabs(va[k])) / bound;
    if (excess > worst_excess) worst_excess = excess, worst = k;
  }
  EXPECT_LE(worst_excess, 1.0) << c.name << ": value " << worst << " is " << vg[worst] << " in the GPU shape and "
                               << va[worst] << " in the CPU shape (bound " << bound << ")";
}

INSTANTIATE_TEST_SUITE_P(Family, GpuShape, ::testing::ValuesIn(shape_cases()), test::case_test_name);

// The shape a device takes: auto follows its type; a name in any case; anything else refused, naming
// the choices and where the name came from.
TEST(KernelShape, AutoFollowsTheDeviceTypeAndOtherNamesAreRefused) {
  EXPECT_EQ(resolve_kernel_shape("auto", "cpu"), "cpu");
  EXPECT_EQ(resolve_kernel_shape("auto", "gpu"), "gpu");
  EXPECT_EQ(resolve_kernel_shape("auto", "accelerator"), "gpu");
  EXPECT_EQ(resolve_kernel_shape("GPU", "cpu"), "gpu");
  EXPECT_EQ(resolve_kernel_shape("cpu", "gpu"), "cpu");
  try {
    resolve_kernel_shape("warp", "cpu");
    ADD_FAILURE() << "'warp' was taken";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("auto, cpu or gpu"), std::string::npos) << e.what();
  }
}

// eval's batches and lanes follow the shape: the CPU shape's 65,536 pairs and 16 / 8 lanes as
// measured on PoCL; the GPU shape's 16,384 pairs a compute unit, at least the CPU's and at most 2^21
// (an H200's 132 SMs: 2.16M, capped to 2.10M, where 2M pairs a launch measured 15.4 G/s against 1.67
// at 65,536), and 4 lanes.
TEST(KernelShape, EvalBatchesAndLanesFollowTheShape) {
  DeviceInfo d;
  d.kernel_shape = "cpu";
  d.compute_units = 132;
  EXPECT_EQ(detail::eval_chunk_pairs(d), size_t(65536));
  EXPECT_EQ(detail::resolve_lanes(EvalOptions{}, d), 16);
  EvalOptions fp64;
  fp64.precision = Precision::Fp64;
  EXPECT_EQ(detail::resolve_lanes(fp64, d), 8);
  d.kernel_shape = "gpu";
  EXPECT_EQ(detail::eval_chunk_pairs(d), size_t(1) << 21);
  d.compute_units = 100;
  EXPECT_EQ(detail::eval_chunk_pairs(d), size_t(100) * 16384);
  EXPECT_EQ(detail::resolve_lanes(EvalOptions{}, d), 4);
  EXPECT_EQ(detail::resolve_lanes(fp64, d), 4);
  d.compute_units = 2;
  EXPECT_EQ(detail::eval_chunk_pairs(d), size_t(65536));
  EvalOptions eight;
  eight.lanes = 8;
  EXPECT_EQ(detail::resolve_lanes(eight, d), 8);  // asked for: kept
}

}  // namespace
}  // namespace brdfbake
