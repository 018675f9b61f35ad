// The tests' temporary folders (tests/support/temp_dir.hpp, issue 34): a test's folder is gone when the
// test ends, failed as much as passed, and a TempDir's when it goes; BRDFBAKE_TEST_KEEP=1 keeps them.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;

// Run by TempDirs.* below in a child process of this program (skipped otherwise): writes the paths of
// its folders into $BRDFBAKE_TEMP_PROBE, then fails.
TEST(TempDirProbe, FailsWithFolders) {
  const char* probe = std::getenv("BRDFBAKE_TEMP_PROBE");
  if (probe == nullptr) GTEST_SKIP() << "run by TempDirs.* in a child process";
  const fs::path dir = brdfbake::test::test_temp_dir("made");
  std::ofstream(dir / "file") << "x";
  std::ofstream(probe) << brdfbake::test::test_temp_root().string() << "\n";
  ADD_FAILURE() << "a failing test (planted)";
}

// Runs this program's TempDirProbe in a child with `env` set; its exit status and the folder it made.
struct Probe {
  int status = -1;
  fs::path folder;
};
Probe run_probe(const fs::path& record, const std::string& env) {
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  const std::string cmd = env + " BRDFBAKE_TEMP_PROBE='" + record.string() + "' '" + self +
                          "' --gtest_filter=TempDirProbe.FailsWithFolders > /dev/null 2>&1";
  Probe p;
  const int s = std::system(cmd.c_str());
  p.status = WIFEXITED(s) ? WEXITSTATUS(s) : -1;
  std::ifstream in(record);
  std::string folder;
  std::getline(in, folder);
  p.folder = folder;
  return p;
}

TEST(TempDirs, AFailedTestsFolderIsRemovedWhenItEnds) {
  const brdfbake::test::TempDir here("temp-dirs");
  const Probe p = run_probe(here / "record", "env -u BRDFBAKE_TEST_KEEP");
  EXPECT_EQ(p.status, 1) << "the probe fails";
  ASSERT_FALSE(p.folder.empty());
  EXPECT_EQ(p.folder.filename().string().rfind("brdfbake-test-TempDirProbe.FailsWithFolders-", 0), 0u) << p.folder;
  EXPECT_FALSE(fs::exists(p.folder)) << "left: " << p.folder;
}

TEST(TempDirs, KeptWhenAsked) {
  const brdfbake::test::TempDir here("temp-dirs");
  const Probe p = run_probe(here / "record", "BRDFBAKE_TEST_KEEP=1");
  ASSERT_FALSE(p.folder.empty());
  EXPECT_TRUE(fs::exists(p.folder / "made" / "file")) << p.folder;
  std::error_code ec;
  fs::remove_all(p.folder, ec);
}

TEST(TempDirs, ATempDirIsRemovedWhenItGoes) {
  fs::path path;
  {
    const brdfbake::test::TempDir d("scoped");
    path = d.path;
    std::ofstream(d / "file") << "x";
    EXPECT_TRUE(fs::is_directory(path));
    EXPECT_EQ(path.filename().string().rfind("brdfbake-test-scoped-", 0), 0u) << path;
  }
  EXPECT_FALSE(fs::exists(path)) << path;
}

}  // namespace
