// The command-line tool, run as a user runs it: exit codes, one-line errors, no partial files,
// and the shape of its outputs.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "brdfbake/table.hpp"
#include "io/table_read.hpp"
#include "support/cli_runner.hpp"
#include "support/table_readback.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;

using brdfbake::test::CliRun;
using brdfbake::test::count_lines;

CliRun run(const std::string& args) { return brdfbake::test::run_cli(args); }

// The test's temporary folder (removed when the test ends).
fs::path temp_dir() { return brdfbake::test::test_temp_root(); }

// Each bad input: exit 2 (bad input; 1 is a runtime failure, -1 a crash), exactly one line on
// stderr naming the problem, no file.
void expect_clean_failure(const std::string& args, const fs::path& out, const std::string& needle) {
  const CliRun r = run(args + " --quiet -o " + out.string());
  EXPECT_EQ(r.code, 2) << args << " -> " << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << args << " -> " << r.err;
  EXPECT_NE(r.err.find(needle), std::string::npos) << args << " -> " << r.err;
  EXPECT_FALSE(fs::exists(out)) << args;
  for (const auto& e : fs::directory_iterator(out.parent_path()))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << "left behind: " << e.path();
}

TEST(Cli, BadInputGivesOneLineAndNoFile) {
  const fs::path dir = temp_dir() / "bad";
  fs::create_directories(dir);
  const fs::path out = dir / "t.exr";
  expect_clean_failure("lut --kind ggx --size 0", out, "size");
  expect_clean_failure("lut --kind ggx --size -4", out, "size");
  expect_clean_failure("lut --kind ggx --size 8 --samples nan", out, "samples");
  expect_clean_failure("lut --kind ggx --size 8 --samples -5", out, "samples");
  expect_clean_failure("lut --kind ggx --size 8 --max-error nan", out, "max-error");
  expect_clean_failure("lut --kind phong --size 8", out, "unknown table kind 'phong'");
  expect_clean_failure("lut --kind ggx --size 8 --estimator magic", out,
                       "--estimator: must be one of quadrature, vndf, ndf, uniform (got 'magic')");
  expect_clean_failure("lut --kind ggx --size 8 --precision fp16", out, "unknown precision 'fp16'");
  expect_clean_failure("lut --kind ggx --size 8 --device no-such-device", out, "no-such-device");
  expect_clean_failure("lut --kind ggx --size 8 --no-such-option", out, "no-such-option");
  const fs::path bad_ext = dir / "t.xyz";
  expect_clean_failure("lut --kind ggx --size 8", bad_ext, "unknown output format");
  // unwritable: a path through a regular file (fails for root too)
  std::ofstream(dir / "plain") << "x";
  const CliRun r = run("lut --kind ggx --size 4 --quiet -o " + (dir / "plain" / "t.exr").string());
  EXPECT_EQ(r.code, 1) << "an output that cannot be written is a runtime failure: " << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("plain/t.exr"), std::string::npos) << r.err;
  fs::remove_all(dir);
}

TEST(Cli, CsvToStandardOutput) {
  const CliRun r = run("lut --kind ggx --size 4 --height 3 --quiet -o - --format csv");
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream in(r.out);
  std::string line, header;
  int comments = 0, rows = 0;
  while (std::getline(in, line)) {
    if (line.rfind("#", 0) == 0) {
      ++comments;
    } else if (header.empty()) {
      header = line;
    } else {
      ++rows;
    }
  }
  EXPECT_EQ(header, "n_dot_v,roughness,scale,bias,diffuse");
  EXPECT_EQ(rows, 12);
  EXPECT_GT(comments, 5) << "the metadata lines";
  EXPECT_NE(r.out.find("# kind: ggx"), std::string::npos);
  EXPECT_NE(r.out.find("# error_bound_mixed: "), std::string::npos);
  EXPECT_NE(r.out.find("0.125,0.166666"), std::string::npos) << "first cell centre (0.5/4, 0.5/3)";
}

// The one-table prefilter records its error bound without --max-error (every output does): in the
// summary line and in the file's metadata, with its parts.
TEST(Cli, PrefilterRecordsItsBoundWithoutMaxError) {
  const fs::path out = temp_dir() / "bound.ktx2";
  const CliRun r = run("prefilter --env builtin:sun --size 16 --min-size 4 -o " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE((r.out + r.err).find("stored values: error_bound_rel "), std::string::npos) << r.out << r.err;
  std::ifstream in(out, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const char* key :
       {"brdfbake:error_bound_rel", "brdfbake:error_name", "brdfbake:integration_error_bound_per_level",
        "brdfbake:integration_error_bound_definition", "brdfbake:storage_error"})
    EXPECT_NE(bytes.find(std::string(key) + '\0'), std::string::npos) << key;
  fs::remove(out);
}

// Every format holds the table the CSV holds (read back: values within the format's step, the
// shape, the channels and the metadata).
TEST(Cli, ReferenceDeviceAndEveryFormat) {
  const fs::path dir = temp_dir() / "formats";
  fs::create_directories(dir);
  brdfbake::Table want;
  for (const char* ext : {"csv", "exr", "png", "hdr", "ktx2", "h"}) {
    const fs::path out = dir / (std::string("lut.") + ext);
    const CliRun r = run("lut --kind charlie --size 4 --quiet -o " + out.string());
    ASSERT_EQ(r.code, 0) << ext << ": " << r.err;
    if (std::string(ext) == "csv") {
      want = brdfbake::io::read_table(out.string());
      ASSERT_EQ(want.width, 4);
      ASSERT_EQ(want.height, 4);
      continue;
    }
    brdfbake::test::expect_table_file(out.string(), want, {"kind", "device", "precision", "x_axis", "y_axis"});
  }
  const CliRun r = run("lut --kind ggx --size 2 --device reference -o - --format csv --quiet");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("# device: reference"), std::string::npos);
  fs::remove_all(dir);
}

TEST(Cli, DevicesListsTheDefaultAndJson) {
  const CliRun r = run("devices --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"default\": true"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"fp64\""), std::string::npos);
  EXPECT_NE(r.out.find("\"id\": \"reference\""), std::string::npos);
  const CliRun plain = run("devices");
  EXPECT_EQ(plain.code, 0);
  EXPECT_NE(plain.out.find(" * "), std::string::npos) << plain.out;
}

// --kernel-shape is taken by every command (docs/DEVICES.md, "Kernel shapes"): the device is opened
// in that shape (devices prints it), BRDFBAKE_KERNEL_SHAPE does the same, and a name other than auto,
// cpu or gpu is a one-line usage error (exit 2), before any work.
TEST(Cli, KernelShapeIsAnOptionOfEveryCommand) {
  const CliRun gpu = run("devices --json --kernel-shape gpu");
  ASSERT_EQ(gpu.code, 0) << gpu.err;
  EXPECT_NE(gpu.out.find("\"kernel_shape\": \"gpu\""), std::string::npos) << gpu.out;
  EXPECT_EQ(gpu.out.find("\"kernel_shape\": \"cpu\""), std::string::npos) << gpu.out;
  const CliRun cpu = run("devices --kernel-shape=cpu");
  ASSERT_EQ(cpu.code, 0) << cpu.err;
  EXPECT_NE(cpu.out.find("kernel shape cpu"), std::string::npos) << cpu.out;
  const CliRun lut = run("lut --kind ggx --size 4 --samples 64 -o - --format csv --quiet --kernel-shape gpu");
  EXPECT_EQ(lut.code, 0) << lut.err;
  EXPECT_NE(lut.out.find("n_dot_v"), std::string::npos) << lut.out.substr(0, 400);
  for (const char* bad : {"lut --kind ggx --size 4 -o - --format csv --kernel-shape warp", "devices --kernel-shape",
                          "devices --kernel-shape="}) {
    const CliRun r = run(bad);
    EXPECT_EQ(r.code, 2) << bad << ": " << r.err;
    EXPECT_NE(r.err.find("--kernel-shape"), std::string::npos) << bad << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << bad << ": " << r.err;
  }
  const CliRun env = brdfbake::test::run_cli("devices --json", "", "BRDFBAKE_KERNEL_SHAPE=gpu");
  ASSERT_EQ(env.code, 0) << env.err;
  EXPECT_NE(env.out.find("\"kernel_shape\": \"gpu\""), std::string::npos) << env.out;
  const CliRun bad_env = brdfbake::test::run_cli("devices --json", "", "BRDFBAKE_KERNEL_SHAPE=simd");
  EXPECT_NE(bad_env.code, 0);
  EXPECT_NE(bad_env.err.find("BRDFBAKE_KERNEL_SHAPE"), std::string::npos) << bad_env.err;
}

// Every command's help gives each option one default at most, says none is an empty string, and
// shows an example (issue 10: "(default: standard input) (default: -)", `--device (default: "")`,
// eval's input called required though it defaults to standard input).
TEST(Cli, HelpShowsOneDefaultAndAnExample) {
  for (const char* command : {"lut", "fresnel", "thin-film", "prefilter", "irradiance", "eval", "tabulate", "bake",
                              "run", "view", "report"}) {
    const CliRun r = run(std::string(command) + " --help");
    ASSERT_EQ(r.code, 0) << command << ": " << r.err;
    // One entry per option: its first line starts with '-', cxxopts wraps the rest.
    std::vector<std::string> entries;
    std::istringstream in(r.out);
    std::string line;
    while (std::getline(in, line)) {
      const size_t at = line.find_first_not_of(' ');
      if (at == std::string::npos) continue;
      if (line[at] == '-')
        entries.push_back(line.substr(at));
      else if (!entries.empty() && at > 2)
        entries.back() += " " + line.substr(at);
    }
    EXPECT_GT(entries.size(), 2u) << command;
    for (const std::string& e : entries) {
      const size_t first = e.find("(default:");
      EXPECT_TRUE(first == std::string::npos || e.find("(default:", first + 1) == std::string::npos)
          << command << ": " << e;
      EXPECT_EQ(e.find("(default: \"\")"), std::string::npos) << command << ": " << e;
      if (std::string(command) == "eval" && e.rfind("-i, --input", 0) == 0) {
        EXPECT_EQ(e.find("(required)"), std::string::npos) << "eval reads standard input by default: " << e;
      }
    }
    EXPECT_NE(r.out.find("example"), std::string::npos) << command;
  }
}

TEST(Cli, UnknownCommand) {
  const CliRun r = run("frobnicate");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(count_lines(r.err), 1);
}

}  // namespace
