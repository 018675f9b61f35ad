// The temporary folders of the C++ tests (issue 34): each folder a test makes is owned by something
// that removes it when the test ends, passed or failed, so that the test command leaves nothing in
// $TMPDIR (scripts/test.sh lists what is left and fails).
//
//   TempDir d("label")   a fresh folder of its own ($TMPDIR/brdfbake-test-label-XXXXXX, mkdtemp),
//                        removed with its contents when `d` goes: a test's local, or a suite's
//                        (deleted in TearDownTestSuite, after the server that writes in it stops).
//   test_temp_root()     the running test's folder ($TMPDIR/brdfbake-test-SUITE.NAME-XXXXXX),
//                        made on first use and removed when the test ends (a GoogleTest listener,
//                        after the fixture and its locals are gone), whatever the test did with it;
//                        outside a test (a suite's set-up) the test program's, removed at its end.
//   test_temp_dir("n")   a fresh, empty folder `n` inside test_temp_root().
//
// BRDFBAKE_TEST_KEEP=1 keeps every folder, and says on stderr which it kept, to look at afterwards.
#pragma once

#include <gtest/gtest.h>
#include <stdlib.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <system_error>

namespace brdfbake::test {

// BRDFBAKE_TEST_KEEP=1: the tests' temporary folders are kept, not removed.
inline bool keep_temp_folders() {
  const char* keep = std::getenv("BRDFBAKE_TEST_KEEP");
  return keep != nullptr && std::string(keep) == "1";
}

// A fresh folder of its own under the temporary folder, removed (with what it holds) when the
// object goes. `path` is the folder.
struct TempDir {
  std::filesystem::path path;

  explicit TempDir(const std::string& label) {
    std::string name;  // a file name from the label: letters, digits, '.', '-', '_' only
    for (char c : label.substr(0, 80))
      name += (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_') ? c : '_';
    std::string pattern = (std::filesystem::temp_directory_path() / ("brdfbake-test-" + name + "-XXXXXX")).string();
    if (::mkdtemp(pattern.data()) == nullptr)
      throw std::runtime_error("cannot make a temporary folder " + pattern + ": " +
                               std::generic_category().message(errno));
    path = pattern;
  }
  ~TempDir() {
    if (keep_temp_folders()) {
      std::fprintf(stderr, "BRDFBAKE_TEST_KEEP=1: kept %s\n", path.c_str());
      return;
    }
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  std::filesystem::path operator/(const std::filesystem::path& name) const { return path / name; }
};

namespace detail {

// The running test's folder and the test program's. A GoogleTest listener (installed on first use)
// removes the first when each test ends and both when the program's tests end; the program's also
// goes when the process exits (e.g. after --gtest_list_tests, which runs no test).
class TempFolders : public ::testing::EmptyTestEventListener {
 public:
  static std::filesystem::path current() {
    State& s = state();
    std::lock_guard<std::mutex> lock(s.mutex);
    if (!s.listening) {
      ::testing::UnitTest::GetInstance()->listeners().Append(new TempFolders);  // GoogleTest owns it
      s.listening = true;
    }
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::unique_ptr<TempDir>& dir = info != nullptr ? s.test : s.program;
    if (!dir)
      dir = std::make_unique<TempDir>(info != nullptr ? std::string(info->test_suite_name()) + "." + info->name()
                                                      : std::string("program"));
    return dir->path;
  }

  void OnTestEnd(const ::testing::TestInfo&) override {
    State& s = state();
    std::lock_guard<std::mutex> lock(s.mutex);
    s.test.reset();
  }
  void OnTestProgramEnd(const ::testing::UnitTest&) override {
    State& s = state();
    std::lock_guard<std::mutex> lock(s.mutex);
    s.test.reset();
    s.program.reset();
  }

 private:
  struct State {
    std::mutex mutex;
    bool listening = false;
    std::unique_ptr<TempDir> test, program;
  };
  static State& state() {
    static State s;  // destroyed at exit: what is left goes then
    return s;
  }
};

}  // namespace detail

// The running test's temporary folder (outside a test, the test program's): see above.
inline std::filesystem::path test_temp_root() { return detail::TempFolders::current(); }

// A fresh, empty folder `name` in the running test's temporary folder.
inline std::filesystem::path test_temp_dir(const std::string& name) {
  const std::filesystem::path d = test_temp_root() / name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace brdfbake::test
