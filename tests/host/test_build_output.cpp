// The OpenCL compiler's output never reaches the user's stderr (issue 18): what an implementation
// prints during clBuildProgram is contained, a cold build with --quiet leaves stderr empty, and
// --verbose shows each build.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "brdfbake/diagnostics.hpp"
#include "runtime/program.hpp"
#include "runtime/stderr_capture.hpp"
#include "support/cli_runner.hpp"
#include "support/device_fixture.hpp"
#include "support/temp_dir.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;

// Points fd 2 at a file for the test's duration, to see what would have reached the terminal.
class StderrToFile {
 public:
  explicit StderrToFile(const fs::path& p) : path_(p) {
    std::fflush(stderr);
    saved_ = ::dup(2);
    file_ = std::fopen(p.c_str(), "w");
    ::dup2(::fileno(file_), 2);
  }
  ~StderrToFile() { restore(); }
  void restore() {
    if (saved_ < 0) return;
    std::fflush(stderr);
    ::dup2(saved_, 2);
    ::close(saved_);
    std::fclose(file_);
    saved_ = -1;
  }
  std::string text() {
    restore();
    std::ifstream in(path_);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }

 private:
  fs::path path_;
  std::FILE* file_ = nullptr;
  int saved_ = -1;
};

TEST(BuildOutput, WhatIsPrintedDuringABuildIsContained) {
  const fs::path outer = brdfbake::test::test_temp_root() / "stderr.txt";
  StderrToFile terminal(outer);
  // Both ways an implementation can write: the C stream and the raw descriptor.
  const std::string captured = detail::run_with_stderr_captured([] {
    std::fprintf(stderr, "3 warnings generated.\n");
    const char raw[] = "raw write\n";
    EXPECT_EQ(::write(2, raw, sizeof raw - 1), static_cast<ssize_t>(sizeof raw - 1));
  });
  std::fprintf(stderr, "after\n");
  const std::string seen = terminal.text();
  fs::remove(outer);
  EXPECT_EQ(captured, "3 warnings generated.\nraw write\n");
  EXPECT_EQ(seen, "after\n");  // stderr is restored, and nothing of the build reached it
}

TEST(BuildOutput, StderrIsRestoredWhenTheBuildThrows) {
  const fs::path outer = brdfbake::test::test_temp_root() / "stderr.txt";
  StderrToFile terminal(outer);
  EXPECT_THROW(detail::run_with_stderr_captured([] {
                 std::fprintf(stderr, "noise\n");
                 throw std::runtime_error("build failed");
               }),
               std::runtime_error);
  std::fprintf(stderr, "after\n");
  const std::string seen = terminal.text();
  fs::remove(outer);
  EXPECT_EQ(seen, "after\n");
}

// PoCL 3.1 prints clang's "N warnings generated." to the process's stderr when it compiles a program
// with warnings (its cache cold), besides the build log. A kernel with a #warning, built by the
// product's build path: nothing reaches stderr, and the observer receives the log and that text.
TEST(BuildOutput, CompilerWarningsGoToTheObserverNotStderr) {
  BRDFBAKE_REQUIRE_DEVICE(device);
  const fs::path dir = brdfbake::test::test_temp_dir("warn");
  // a source no cache has seen (PoCL keys its cache by the source)
  const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
  std::ofstream(dir / "warn.cl") << "// " << stamp << "\n#warning a deliberate warning\n"
                                 << "kernel void k(global float* a) { a[0] = 1.0f; }\n";
  ::setenv("BRDFBAKE_KERNEL_DIR", dir.c_str(), 1);
  std::string log;
  set_program_build_observers({}, [&](const ProgramBuild& b) {
    if (b.program.find("warn.cl") != std::string::npos) log = b.log;
  });
  detail::set_program_cache_dir("");
  const fs::path outer = dir / "stderr.txt";
  StderrToFile terminal(outer);
  detail::ProgramSpec spec;
  spec.file = "warn.cl";
  std::string failure;
  try {
    detail::build_program(device->impl(), spec);
  } catch (const std::exception& e) {
    failure = e.what();
  }
  const std::string seen = terminal.text();
  ::unsetenv("BRDFBAKE_KERNEL_DIR");
  set_program_build_observers({}, {});
  fs::remove_all(dir);
  ASSERT_EQ(failure, "");
  EXPECT_EQ(seen, "");
  EXPECT_NE(log.find("a deliberate warning"), std::string::npos) << log;
  // what PoCL printed on its own is in the log too
  if (device->info().platform_name.find("Portable Computing Language") != std::string::npos) {
    EXPECT_NE(log.find("warning generated."), std::string::npos) << log;
  }
}

// A first run from cold caches (ours and PoCL's): nothing on stderr with --quiet; one line a
// program with --verbose.
TEST(BuildOutput, ColdBuildIsSilentAndVerboseShowsIt) {
  const fs::path dir = brdfbake::test::test_temp_dir("cold");
  const std::string env =
      "BRDFBAKE_CACHE_DIR=" + (dir / "ours").string() + " POCL_CACHE_DIR=" + (dir / "pocl").string();
  const std::string out = (dir / "t.exr").string();
  const test::CliRun quiet = test::run_cli("lut --kind ggx --size 8 --quiet -o " + out, {}, env);
  ASSERT_EQ(quiet.code, 0) << quiet.err;
  EXPECT_EQ(quiet.err, "");
  fs::remove_all(dir / "ours");
  const test::CliRun verbose = test::run_cli("lut --kind ggx --size 8 --quiet --verbose -o " + out, {}, env);
  ASSERT_EQ(verbose.code, 0) << verbose.err;
  EXPECT_NE(verbose.err.find("brdfbake: built kernels/dfg_lut.cl fp32 for "), std::string::npos) << verbose.err;
  const test::CliRun warm = test::run_cli("lut --kind ggx --size 8 --quiet --verbose -o " + out, {}, env);
  ASSERT_EQ(warm.code, 0) << warm.err;
  EXPECT_NE(warm.err.find("brdfbake: loaded kernels/dfg_lut.cl fp32 for "), std::string::npos) << warm.err;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace brdfbake
