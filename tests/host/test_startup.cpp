// Start-up costs only what the job uses (issue 11): the program links no OpenImageIO; commands
// that compute nothing load no library at run time (no OpenCL implementation, no image module);
// the hot formats (EXR, PNG, HDR) need no OpenImageIO module; other formats load it on demand and
// fail with one clear line when it is missing. Checked through the dynamic loader's own reports
// (LD_TRACE_LOADED_OBJECTS, LD_DEBUG=files), never through timings.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "support/cli_runner.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;

using brdfbake::test::CliRun;
using brdfbake::test::count_lines;
using brdfbake::test::run_cli;

constexpr const char* kNoModule = "BRDFBAKE_OIIO_MODULE=/nonexistent/brdfbake_oiio.so";

// The test's temporary folder, removed when the test ends.
fs::path temp_root() { return brdfbake::test::test_temp_root(); }

fs::path temp_dir(const std::string& name) {
  const fs::path d = temp_root() / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// The libraries the dynamic loader opened at run time (dlopen), from LD_DEBUG=files on stderr.
std::vector<std::string> dynamically_loaded(const std::string& err) {
  std::vector<std::string> out;
  size_t at = 0;
  while ((at = err.find("dynamically loaded by", at)) != std::string::npos) {
    const size_t line = err.rfind('\n', at) + 1;
    out.push_back(err.substr(line, at - line));
    at += 10;
  }
  return out;
}

// An 8-bit equirect in a format only OpenImageIO reads (TIFF; PNG is read with libpng since issue 24).
void write_tiff_equirect(const fs::path& p) {
  auto out = OIIO::ImageOutput::create(p.string());
  ASSERT_TRUE(out);
  OIIO::ImageSpec spec(16, 8, 3, OIIO::TypeDesc::UINT8);
  std::vector<unsigned char> px(16 * 8 * 3, 128);
  ASSERT_TRUE(out->open(p.string(), spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
  out->close();
}

TEST(Startup, TheProgramDoesNotLinkOpenImageIo) {
  const CliRun r = run_cli("", "", "LD_TRACE_LOADED_OBJECTS=1");
  ASSERT_TRUE(contains(r.out, "libc.so")) << r.out;  // the loader did list the libraries
  EXPECT_FALSE(contains(r.out, "OpenImageIO")) << r.out;
}

TEST(Startup, CommandsThatComputeNothingLoadNothing) {
  const fs::path dir = temp_dir("nothing");
  const std::vector<std::string> commands = {"--help", "lut --help", "irradiance --help",
                                             "lut --size 0 --quiet -o " + (dir / "t.exr").string()};
  for (const std::string& args : commands) {
    const CliRun r = run_cli(args, "", "LD_DEBUG=files");
    ASSERT_TRUE(contains(r.err, "needed by")) << "LD_DEBUG=files reported nothing: " << r.err;
    EXPECT_EQ(dynamically_loaded(r.err), std::vector<std::string>{}) << args;
  }
}

// 3-band SH alone is a host computation: no OpenCL implementation is loaded.
TEST(Startup, ShAloneOpensNoOpenClPlatform) {
  const fs::path dir = temp_dir("sh");
  const fs::path hdr = dir / "env.hdr";
  ASSERT_EQ(run_cli("lut --kind ggx --size 16 --height 8 --quiet -o " + hdr.string()).code, 0);
  const CliRun r = run_cli("irradiance --env " + hdr.string() + " --sh 3 --quiet -o " + (dir / "sh.json").string(), "",
                           "LD_DEBUG=files");
  EXPECT_EQ(r.code, 0) << r.err;
  ASSERT_TRUE(contains(r.err, "needed by")) << "LD_DEBUG=files reported nothing";
  EXPECT_EQ(dynamically_loaded(r.err), std::vector<std::string>{});
  EXPECT_TRUE(fs::exists(dir / "sh.json"));
}

TEST(Startup, HotFormatsNeedNoOpenImageIoModule) {
  const fs::path dir = temp_dir("hot");
  for (const char* ext : {".exr", ".png", ".hdr"}) {
    const fs::path out = dir / (std::string("dfg") + ext);
    const CliRun r = run_cli("lut --kind ggx --size 8 --png-range scale --quiet -o " + out.string(), "", kNoModule);
    EXPECT_EQ(r.code, 0) << ext << ": " << r.err;
    EXPECT_TRUE(fs::exists(out)) << ext;
  }
  // the outputs read back as environments (.exr and .hdr at 2:1) without the module either
  const fs::path hdr = dir / "env.hdr";
  ASSERT_EQ(run_cli("lut --kind ggx --size 16 --height 8 --quiet -o " + hdr.string()).code, 0);
  const CliRun r =
      run_cli("irradiance --env " + hdr.string() + " --source-size 8 --quiet -o " + (dir / "sh.json").string(), "",
              std::string(kNoModule) + " LD_DEBUG=files");
  EXPECT_EQ(r.code, 0) << r.err;
  for (const std::string& lib : dynamically_loaded(r.err))
    EXPECT_FALSE(contains(lib, "brdfbake_oiio") || contains(lib, "OpenImageIO")) << lib;
}

TEST(Startup, OtherFormatsLoadTheModuleOnDemand) {
  const fs::path dir = temp_dir("other");
  const fs::path tif = dir / "env.tif";
  write_tiff_equirect(tif);
  const std::string args = "irradiance --env " + tif.string() + " --source-size 8 --quiet -o ";
  // with the module (found beside the executable): it is loaded, and the job runs
  const CliRun ok = run_cli(args + (dir / "sh.json").string(), "", "LD_DEBUG=files");
  EXPECT_EQ(ok.code, 0) << ok.err;
  bool loaded = false;
  for (const std::string& lib : dynamically_loaded(ok.err)) loaded |= contains(lib, "brdfbake_oiio.so");
  EXPECT_TRUE(loaded);
  // without it: one line that names the module and how to point at it, and no output
  const CliRun missing = run_cli(args + (dir / "sh2.json").string(), "", kNoModule);
  EXPECT_EQ(missing.code, 2) << missing.err;
  EXPECT_EQ(count_lines(missing.err), 1) << missing.err;
  EXPECT_TRUE(contains(missing.err, "env.tif")) << missing.err;
  EXPECT_TRUE(contains(missing.err, "brdfbake_oiio.so")) << missing.err;
  EXPECT_TRUE(contains(missing.err, "BRDFBAKE_OIIO_MODULE")) << missing.err;
  EXPECT_FALSE(fs::exists(dir / "sh2.json"));
}

// The command line's module search (issue 24): an installed copy of the program, outside the build
// tree, looks beside itself and in ../lib/brdfbake/ only, never at the build tree's path compiled
// into it (for a package built in a temporary folder, a path anyone could create again). Before,
// the moved program loaded the build tree's module.
TEST(Startup, AMovedProgramDoesNotLoadTheBuildTreesModule) {
  const fs::path dir = temp_dir("moved");
  const fs::path bin = dir / "bin", program = bin / "brdfbake";
  fs::create_directories(bin);
  const char* under_test = std::getenv("BRDFBAKE_CLI_UNDER_TEST");
  fs::copy_file(under_test ? under_test : BRDFBAKE_CLI, program);
  const fs::path tif = dir / "env.tif";
  write_tiff_equirect(tif);
  auto run = [&](const std::string& out) {
    const fs::path err = dir / "err.txt";
    const std::string cmd = "env -u BRDFBAKE_OIIO_MODULE " + program.string() + " irradiance --env " + tif.string() +
                            " --source-size 8 --quiet -o " + (dir / out).string() + " 2>" + err.string();
    const int status = std::system(cmd.c_str());
    std::ifstream in(err);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return std::make_pair(WIFEXITED(status) ? WEXITSTATUS(status) : -1, text);
  };
  const auto [code, err] = run("sh.json");
  EXPECT_EQ(code, 2) << err;
  EXPECT_TRUE(contains(err, "is not installed (looked for " + (bin / "brdfbake_oiio.so").string() + ", " +
                                (dir / "lib" / "brdfbake" / "brdfbake_oiio.so").string() + ";"))
      << err;
  EXPECT_FALSE(contains(err, fs::path(BRDFBAKE_CLI).parent_path().string())) << err;
  EXPECT_FALSE(fs::exists(dir / "sh.json"));
  // Installed beside it, the module is found there.
  fs::copy_file(fs::path(BRDFBAKE_CLI).parent_path() / "brdfbake_oiio.so", bin / "brdfbake_oiio.so");
  const auto [code2, err2] = run("sh2.json");
  EXPECT_EQ(code2, 0) << err2;
  EXPECT_TRUE(fs::exists(dir / "sh2.json"));
}

}  // namespace
