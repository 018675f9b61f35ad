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

}  // namespace
}  // namespace brdfbake
