// Every kernel family on a second OpenCL implementation (issue 17, docs/RELIABILITY.md "Devices"):
// Oclgrind, an interpreter that checks every memory access and API call (--check-api) and, with
// --data-races, every access that work-items share. Each case bakes a small table of one family on
// Oclgrind and on the first other device (PoCL on the development machines): the hand-written cases
// below (estimators and layouts), and every kind's example request (table_kind_example), so that a
// new family is covered without a new case. Each case asserts
//   - Oclgrind reported nothing (no invalid access, API error or race: its words on stderr), and
//   - the two results agree within the family's stated tolerance: the bound the result records
//     where the family measures one, else the fp32 tolerance of its device tests
//     (tests/support/tolerances.hpp), absolute below 1 and relative above, as the bounds are.
// Both devices are in one process: ctest registers Oclgrind's ICD beside the machine's
// (OCL_ICD_VENDORS, tests/CMakeLists.txt, test "Oclgrind.EveryKernelFamily"). Run otherwise, where
// Oclgrind is not among the platforms, the cases skip with a message. Sizes are tiny: Oclgrind
// interprets every work-item (a 4^2 table takes a second).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "brdfbake/backend.hpp"
#include "brdfbake/device.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/job.hpp"
#include "brdfbake/tables.hpp"
#include "support/family_cases.hpp"
#include "support/result_values.hpp"

namespace brdfbake {
namespace {

bool is_oclgrind(const DeviceInfo& d) { return d.platform_name.find("Oclgrind") != std::string::npos; }

// The two backends, opened once and never destroyed (see tests/support/device_fixture.hpp: an
// implementation may tear its state down before static destructors run).
struct Pair {
  std::shared_ptr<Backend> oclgrind, other;
  Device* oclgrind_device = nullptr;  // held here, so that they stay reachable (LeakSanitizer)
  Device* other_device = nullptr;
  std::string other_name, why_not;
};

const Pair& backends() {
  static Pair* pair = [] {
    auto* p = new Pair;
    const std::vector<DeviceInfo> all = list_devices();
    const auto og = std::find_if(all.begin(), all.end(), is_oclgrind);
    const auto other = std::find_if(all.begin(), all.end(), [](const DeviceInfo& d) { return !is_oclgrind(d); });
    if (og == all.end()) {
      p->why_not =
          "Oclgrind is not among the OpenCL platforms: install oclgrind and run the ctest test "
          "Oclgrind.EveryKernelFamily, which registers its ICD";
    } else if (other == all.end()) {
      p->why_not = "no OpenCL device besides Oclgrind to compare with (install pocl-opencl-icd)";
    } else {
      p->oclgrind_device = new Device(Device::open(*og));
      p->other_device = new Device(Device::open(*other));
      p->oclgrind = Backend::open(*p->oclgrind_device);
      p->other = Backend::open(*p->other_device);
      p->other_name = other->name;
    }
    return p;
  }();
  return *pair;
}

// Standard error (fd 2) into a temporary file while it lives: what Oclgrind reports.
class StderrCapture {
 public:
  StderrCapture() {
    std::fflush(stderr);
    file_ = std::tmpfile();
    saved_ = ::dup(2);
    if (file_ && saved_ >= 0) ::dup2(::fileno(file_), 2);
  }
  ~StderrCapture() { restore(); }
  StderrCapture(const StderrCapture&) = delete;
  StderrCapture& operator=(const StderrCapture&) = delete;
  std::string text() {
    restore();
    std::string out;
    if (!file_) return out;
    std::rewind(file_);
    char buf[4096];
    size_t n = 0;
    while ((n = std::fread(buf, 1, sizeof buf, file_)) > 0 && out.size() < (1u << 16)) out.append(buf, n);
    std::fclose(file_);
    file_ = nullptr;
    return out;
  }

 private:
  void restore() {
    if (saved_ < 0) return;
    std::fflush(stderr);
    ::dup2(saved_, 2);
    ::close(saved_);
    saved_ = -1;
  }
  std::FILE* file_ = nullptr;
  int saved_ = -1;
};

using test::values_of;

using test::FamilyCase;

class SecondDevice : public ::testing::TestWithParam<FamilyCase> {};

TEST_P(SecondDevice, AgreesWithTheFirstAndOclgrindReportsNothing) {
  const Pair& b = backends();
  if (!b.oclgrind) GTEST_SKIP() << b.why_not;
  const FamilyCase& c = GetParam();
  const std::unique_ptr<test::PreparedCase> prepared = test::prepare_case(c);
  const TableRequest& t = prepared->request();
  const BakeInputs& inputs = prepared->inputs;
  const BakeResult first = bake_table(t, *b.other, inputs);
  BakeResult second;
  std::string reports;
  {
    StderrCapture capture;
    second = bake_table(t, *b.oclgrind, inputs);
    reports = capture.text();
  }
  EXPECT_EQ(reports.find("Oclgrind"), std::string::npos) << "Oclgrind reported:\n" << reports.substr(0, 4000);
  EXPECT_EQ(reports.find("Invalid"), std::string::npos) << "Oclgrind reported:\n" << reports.substr(0, 4000);
  EXPECT_EQ(reports.find("data race"), std::string::npos) << "Oclgrind reported:\n" << reports.substr(0, 4000);
  EXPECT_EQ(reports.find("Uninitialized"), std::string::npos) << "Oclgrind reported:\n" << reports.substr(0, 4000);

  const std::vector<double> a = values_of(first), o = values_of(second);
  ASSERT_EQ(a.size(), o.size());
  ASSERT_FALSE(a.empty());
  // The bound the result states (abs below 1, relative above), else the family's fp32 tolerance.
  const double bound = first.error_bound ? *first.error_bound : c.tolerance;
  ASSERT_GT(bound, 0.0) << c.name << ": no bound and no tolerance";
  size_t worst = 0;
  double worst_excess = -1.0;
  for (size_t k = 0; k < a.size(); ++k) {
    ASSERT_TRUE(std::isfinite(o[k])) << c.name << ": value " << k << " on Oclgrind is " << o[k];
    const double excess = std::fabs(o[k] - a[k]) / std::max(1.0, std::fabs(a[k])) / bound;
    if (excess > worst_excess) worst_excess = excess, worst = k;
  }
  EXPECT_LE(worst_excess, 1.0) << c.name << ": value " << worst << " is " << o[worst] << " on Oclgrind and " << a[worst]
                               << " on " << b.other_name << " (bound " << bound << ")";
}

INSTANTIATE_TEST_SUITE_P(Family, SecondDevice, ::testing::ValuesIn(test::family_cases()), test::case_test_name);

}  // namespace
}  // namespace brdfbake
