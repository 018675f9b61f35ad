// The program binary cache: a second build of the same program comes from disk, a corrupt entry
// falls back to building from source, and kernel source expansion resolves includes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "brdfbake/dfg_lut.hpp"
#include "runtime/program.hpp"
#include "support/device_fixture.hpp"
#include "support/temp_dir.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;

// A fresh, empty folder `name` in the test's temporary folder (removed when the test ends).
fs::path fresh_dir(const std::string& name) { return brdfbake::test::test_temp_dir(name); }

std::vector<fs::path> entries(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path());
  return out;
}

TEST(ProgramCache, SecondOpenLoadsTheBinaryAndCorruptionFallsBack) {
  BRDFBAKE_REQUIRE_DEVICE(unused);
  const fs::path dir = fresh_dir("cache");
  detail::set_program_cache_dir(dir.string());
  LutSpec spec;
  spec.width = 4;
  spec.kind = LutKind::Charlie;
  spec.estimator = Estimator::Uniform;  // a program no other test of this process builds
  spec.samples = 64;

  const auto s0 = detail::program_cache_stats();
  Table first;
  {
    Device d = Device::open();
    first = bake_lut(d, spec);
  }
  const auto s1 = detail::program_cache_stats();
  EXPECT_EQ(s1.source_builds, s0.source_builds + 1);
  const auto files = entries(dir);
  ASSERT_EQ(files.size(), 1u) << "one cache entry per program";

  {
    Device d = Device::open();  // a fresh context: its in-memory program map is empty
    const Table again = bake_lut(d, spec);
    EXPECT_EQ(again.data, first.data);
  }
  const auto s2 = detail::program_cache_stats();
  EXPECT_EQ(s2.disk_hits, s1.disk_hits + 1);
  EXPECT_EQ(s2.source_builds, s1.source_builds);

  {  // corrupt the entry: keep its header, garble the binary
    std::fstream f(files[0], std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(-64, std::ios::end);
    const std::string junk(64, '\x5a');
    f.write(junk.data(), 64);
  }
  {
    Device d = Device::open();
    const Table third = bake_lut(d, spec);
    EXPECT_EQ(third.data, first.data);
  }
  const auto s3 = detail::program_cache_stats();
  // The checksum catches the garbled binary before the driver sees it: rebuilt from source.
  EXPECT_EQ(s3.source_builds, s2.source_builds + 1);
  EXPECT_EQ(s3.disk_hits, s2.disk_hits);
  EXPECT_GT(s3.bad_entries, s2.bad_entries);

  {  // truncate to a few bytes: not a valid entry at all
    std::ofstream f(files[0], std::ios::binary | std::ios::trunc);
    f << "BRD";
  }
  {
    Device d = Device::open();
    EXPECT_EQ(bake_lut(d, spec).data, first.data);
  }
  const auto s4 = detail::program_cache_stats();
  EXPECT_EQ(s4.source_builds, s3.source_builds + 1);
  EXPECT_GT(s4.bad_entries, s3.bad_entries);
  detail::set_program_cache_dir(detail::program_cache_dir());
  fs::remove_all(dir);
}

TEST(ProgramCache, UnwritableCacheOnlyCostsTime) {
  BRDFBAKE_REQUIRE_DEVICE(unused);
  const fs::path dir = fresh_dir("nocache");
  std::ofstream(dir / "file") << "x";
  detail::set_program_cache_dir((dir / "file" / "sub").string());  // under a regular file
  LutSpec spec;
  spec.width = 2;
  spec.kind = LutKind::Charlie;
  spec.estimator = Estimator::Ndf;
  spec.samples = 32;
  const auto s0 = detail::program_cache_stats();
  Device d = Device::open();
  const Table t = bake_lut(d, spec);
  EXPECT_EQ(t.width, 2);
  EXPECT_GT(detail::program_cache_stats().write_failures, s0.write_failures);
  fs::remove_all(dir);
}

// The developer switch: kernels from disk. A broken kernel reports the build log, naming the file.
TEST(KernelSource, BuildFailureCarriesTheLog) {
  BRDFBAKE_REQUIRE_DEVICE(unused);
  const fs::path dir = fresh_dir("kernels");
  fs::create_directories(dir / "common");
  for (const char* f : {"common/real.clh", "common/microfacet.clh", "common/sampling.clh"})
    std::ofstream(dir / f) << detail::kernel_source(f);
  std::ofstream(dir / "dfg_lut.cl")
      << "#include \"common/real.clh\"\nkernel void dfg_lut(global float* o) { o[0] = undefined_thing; }\n";
  ::setenv("BRDFBAKE_KERNEL_DIR", dir.string().c_str(), 1);
  detail::set_program_cache_dir("");
  LutSpec spec;
  spec.width = 2;
  Device d = Device::open();
  try {
    bake_lut(d, spec);
    ADD_FAILURE() << "a broken kernel built";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("building kernels/dfg_lut.cl failed"), std::string::npos) << m;
    EXPECT_NE(m.find("undefined_thing"), std::string::npos) << "the build log is missing: " << m;
  }
  ::unsetenv("BRDFBAKE_KERNEL_DIR");
  fs::remove_all(dir);
}

TEST(KernelSource, IncludesAreExpandedOnce) {
  const std::string src = detail::kernel_source("dfg_lut.cl");
  EXPECT_NE(src.find("inline real D_GGX"), std::string::npos);
  EXPECT_EQ(src.find("#include"), std::string::npos);
  // real.clh is included by three files but appears once
  const auto first = src.find("typedef float real;");
  ASSERT_NE(first, std::string::npos);
  EXPECT_EQ(src.find("typedef float real;", first + 1), std::string::npos);
  EXPECT_THROW(detail::kernel_source("no_such.cl"), Error);
}

TEST(DeviceSelection, SelectorsAndErrors) {
  const auto all = list_devices();
  if (all.empty()) {
    EXPECT_THROW(select_device(""), Error);
    return;
  }
  EXPECT_EQ(std::count_if(all.begin(), all.end(), [](const DeviceInfo& d) { return d.is_default; }), 1);
  const DeviceInfo& first = all.front();
  const DeviceInfo by_index =
      select_device(std::to_string(first.platform_index) + ":" + std::to_string(first.device_index));
  EXPECT_EQ(by_index.name, first.name);
  EXPECT_EQ(select_device(first.type).type, first.type);
  EXPECT_EQ(select_device(first.name.substr(0, 6)).name.substr(0, 6), first.name.substr(0, 6));
  EXPECT_THROW(select_device("99:99"), Error);
  EXPECT_THROW(select_device("no-such-device-name"), Error);
  try {
    select_device("no-such-device-name");
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("available:"), std::string::npos) << e.what();
  }
}

TEST(ClErrors, NameTheCallAndTheError) {
  const ClError e("clEnqueueNDRangeKernel", -5, "kernel dfg_lut");
  // the call, the error's name, and for the errors that end a run on a working driver, what to do
  EXPECT_STREQ(e.what(),
               "OpenCL error in kernel dfg_lut: clEnqueueNDRangeKernel (-5 CL_OUT_OF_RESOURCES); the device ran out of "
               "resources, or its driver stopped a launch (a display watchdog): try a smaller size or another device");
  const ClError build("clBuildProgram", -11, "program dfg_lut.cl");
  EXPECT_STREQ(build.what(), "OpenCL error in program dfg_lut.cl: clBuildProgram (-11 CL_BUILD_PROGRAM_FAILURE)");
  EXPECT_NE(std::string(ClError("clCreateBuffer", -4).what()).find("ran out of memory"), std::string::npos);
  EXPECT_NE(std::string(ClError("clFinish", -36).what()).find("device was lost"), std::string::npos);
  // a runtime failure (exit 1), not bad input
  EXPECT_NE(dynamic_cast<const RuntimeFailure*>(&e), nullptr);
  EXPECT_STREQ(cl_error_name(-11), "CL_BUILD_PROGRAM_FAILURE");
}

}  // namespace
}  // namespace brdfbake
