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
#include "support/result_values.hpp"
#include "support/tolerances.hpp"

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

struct Case {
  std::string name;
  std::string table;     // the job's table, JSON; empty: the example request of `kind`
  double tolerance = 0;  // when the result records no bound
  TableKind kind = TableKind::Ggx;
};

// The fp32 tolerance of a kind's device tests (tests/support/tolerances.hpp), for results that
// record no bound of their own; 0 for the kinds that record one.
double example_tolerance(TableKind kind) {
  switch (kind) {
    case TableKind::Ggx:
    case TableKind::GgxMultiscatter:
    case TableKind::Charlie:
      return 0;  // the calibrated bound the result records
    case TableKind::Fresnel:
    case TableKind::ThinFilm:
      return test::kFresnelFp32;
    case TableKind::Prefilter:
    case TableKind::Irradiance:
      return test::kEnvFp32VsFp64;
    case TableKind::Eval:
      return test::kBrdfFp32;
    case TableKind::Tabulate:
      return test::kBrdfTableFp32;
    case TableKind::Preview:
      return 0;  // not among the examples here (see cases())
  }
  return 0;
}

std::string source_path(const char* relative) { return std::string(BRDFBAKE_SOURCE_DIR) + "/" + relative; }

std::vector<Case> cases() {
  const std::string mats = source_path("examples/materials.json"), pairs = source_path("examples/pairs.csv");
  using test::kBrdfFp32;
  using test::kBrdfTableFp32;
  using test::kEnvFp32VsFp64;
  using test::kFresnelFp32;
  std::vector<Case> list = {
      {"lut_ggx_quadrature", R"({"kind": "ggx", "size": 4, "samples": 256})", 0},
      {"lut_ggx_vndf", R"({"kind": "ggx", "size": 4, "estimator": "vndf", "samples": 256})", 0},
      {"lut_ggx_ndf_fp64", R"({"kind": "ggx", "size": 4, "estimator": "ndf", "samples": 128, "precision": "fp64"})", 0},
      {"lut_multiscatter", R"({"kind": "ggx-multiscatter", "size": 4, "samples": 256})", 0},
      {"lut_charlie_uniform", R"({"kind": "charlie", "size": 4, "estimator": "uniform", "samples": 256})", 0},
      {"fresnel_conductor",
       R"({"kind": "fresnel", "model": "conductor", "n": [0.2, 0.9, 1.1], "k": [3.9, 2.4, 2.2], "size": 16})",
       kFresnelFp32},
      {"fresnel_dielectric_2d", R"({"kind": "fresnel", "model": "dielectric", "table": "2d", "size": 8})",
       kFresnelFp32},
      {"thin_film", R"({"kind": "thin-film", "base_ior": 1.5, "size": 4})", kFresnelFp32},
      {"prefilter_quadrature", R"({"kind": "prefilter", "environment": "builtin:sun", "size": 8, "min_size": 4})",
       kEnvFp32VsFp64},
      {"prefilter_sampling", R"({"kind": "prefilter", "environment": "builtin:sun", "size": 8, "min_size": 4,
                                 "estimator": "sampling", "samples": 64})",
       kEnvFp32VsFp64},
      {"prefilter_charlie", R"({"kind": "prefilter", "environment": "builtin:studio", "distribution": "charlie",
                                "size": 4, "min_size": 4})",
       kEnvFp32VsFp64},
      {"irradiance_cube", R"({"kind": "irradiance", "environment": "builtin:sun", "cube_size": 4, "source_size": 8})",
       kEnvFp32VsFp64},
      {"eval", R"({"kind": "eval", "material": ")" + mats + R"(", "name": "velvet", "input": ")" + pairs + "\"}",
       kBrdfFp32},
      {"tabulate_grid", R"({"kind": "tabulate", "material": ")" + mats + R"(", "name": "red-plastic", "layout": "grid",
                            "res": [4, 4, 4]})",
       kBrdfTableFp32},
      {"tabulate_slice", R"({"kind": "tabulate", "material": ")" + mats + R"(", "name": "gold", "layout": "slice",
                             "res": [8, 8]})",
       kBrdfTableFp32},
      {"tabulate_albedo", R"({"kind": "tabulate", "material": ")" + mats + R"(", "name": "velvet", "layout": "albedo",
                              "res": [4]})",
       kBrdfTableFp32},
  };
  for (TableKind kind : table_kinds()) {
    // The preview's reference render interpreted by Oclgrind takes minutes even at its example's
    // 96x48; tests/device/test_preview.cpp holds its kernels to the scalar reference.
    if (kind == TableKind::Preview) continue;
    std::string name = std::string("example_") + table_kind_name(kind);
    std::replace(name.begin(), name.end(), '-', '_');
    list.push_back({name, "", example_tolerance(kind), kind});
  }
  return list;
}

class SecondDevice : public ::testing::TestWithParam<Case> {};

TEST_P(SecondDevice, AgreesWithTheFirstAndOclgrindReportsNothing) {
  const Pair& b = backends();
  if (!b.oclgrind) GTEST_SKIP() << b.why_not;
  const Case& c = GetParam();
  TableExample example;
  if (c.table.empty()) {
    example = table_kind_example(c.kind);
  } else {
    const Job job = parse_job(R"({"brdfbake_job": 1, "output_dir": "unused", "tables": [)" + c.table + "]}", c.name);
    ASSERT_EQ(job.tables.size(), 1u);
    example.request = job.tables[0];
    if (example.request.environment.empty()) example.request.environment = job.environment;
  }
  const TableRequest& t = example.request;
  EnvImage env;
  BakeInputs inputs;
  if (table_kind_uses_environment(t.kind)) {
    env = load_environment(t.environment);
    inputs.environment = &env;
  }
  if (!example.pairs.empty()) {
    inputs.pairs = example.pairs.data();
    inputs.pair_count = example.pairs.size() / 6;
  }

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

INSTANTIATE_TEST_SUITE_P(Family, SecondDevice, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& i) { return i.param.name; });

}  // namespace
}  // namespace brdfbake
