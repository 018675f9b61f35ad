// The Filament target against Filament itself: a real Filament program (tests/engines/
// filament_ktx_check, linked against Debian's libfilament-dev) loads our NAME_ibl.ktx with
// image::KtxBundle, reads the 9 SH coefficients with getSphericalHarmonics() and every blob of every
// level; the coefficients must match those cmgen (Debian libfilament-tools) writes for the same
// input with the same windowing choice within 1%: the target's default (cmgen's default, its automatic
// deringing window) and none (cmgen --sh-window=no). Skips with a message
// when Filament's package or cmgen is missing.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "brdfbake/engines.hpp"
#include "brdfbake/environment.hpp"
#include "support/device_fixture.hpp"
#include "support/temp_dir.hpp"
#include "support/tolerances.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;

// Runs a command, returns its standard output; *rc its exit status.
std::string run(const std::string& command, int* rc) {
  std::string out;
  FILE* p = ::popen(command.c_str(), "r");
  if (!p) {
    *rc = -1;
    return out;
  }
  char buf[4096];
  for (size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
  const int status = ::pclose(p);
  *rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

bool cmgen_available() {
  int rc = 0;
  run("command -v cmgen >/dev/null 2>&1", &rc);
  return rc == 0;
}

nlohmann::json filament_check(const fs::path& ktx) {
  int rc = 0;
  const std::string out = run(std::string(BRDFBAKE_FILAMENT_CHECK) + " '" + ktx.string() + "'", &rc);
  EXPECT_EQ(rc, 0) << "filament_ktx_check failed on " << ktx;
  return nlohmann::json::parse(out);
}

// builtin:studio (soft area lights, asymmetric: every SH coefficient matters, and the lights
// tell the mirror image apart) at 2048 x 1024, written as a float OpenEXR that both tools read.
// The size matters: cmgen's equirect-to-cube conversion point-samples the image without area
// weights and maps longitude onto [0, W - 1], which overstates this environment's mean radiance
// (its SH band 0) by 1.0% from a 1024 x 512 image and by 0.27% from 2048 x 1024 (measured against
// the image's exact solid-angle-weighted mean). builtin:sun is no test of conventions: 80% of its
// energy is a 0.5 degree disc, whose share cmgen's conversion misses by 10%.
fs::path write_input(const fs::path& dir) {
  const EnvImage env = builtin_environment("studio", 2048);
  const fs::path path = dir / "studio.exr";
  OIIO::ImageSpec spec(env.width, env.height, 3, OIIO::TypeDesc::FLOAT);
  auto out = OIIO::ImageOutput::create("openexr");
  EXPECT_TRUE(out && out->open(path.string(), spec) && out->write_image(OIIO::TypeDesc::FLOAT, env.rgb.data()) &&
              out->close());
  return path;
}

TEST(FilamentTarget, KtxBundleReadsOurFileAndShMatchesCmgen) {
  if (std::string(BRDFBAKE_FILAMENT_CHECK).empty())
    GTEST_SKIP() << "libfilament-dev is not installed: the Filament KTX1 check was not built "
                    "(apt-get install libfilament-dev libfilament-tools)";
  if (!cmgen_available()) GTEST_SKIP() << "cmgen (libfilament-tools) is not installed";
  BRDFBAKE_REQUIRE_DEVICE(dev);
  const fs::path dir = brdfbake::test::test_temp_dir("filament");
  const fs::path input = write_input(dir);

  // cmgen: 64^2 (levels 64, 32, 16), its default SH window (auto)
  int rc = 0;
  const fs::path cm = dir / "cm";
  run("cmgen -q -x '" + cm.string() + "' -f ktx -s 64 '" + input.string() + "' 2>&1", &rc);
  ASSERT_EQ(rc, 0) << "cmgen failed";
  ASSERT_TRUE(fs::exists(cm / "cm_ibl.ktx"));

  // ours, through the library as a bake would: the same file, a Filament-schedule chain, SH
  const EnvImage env = load_environment(input.string());
  const EngineSettings fs_ = engine_settings(EngineTarget::Filament);
  PrefilterSpec ps;
  ps.size = 64;
  ps.min_size = fs_.min_size;
  ps.schedule = fs_.schedule;
  const CubeLevels chain = prefilter_environment(*dev, env, ps);
  IrradianceSpec is;
  is.window = fs_.sh_window;
  is.cube_size = 0;
  const IrradianceResult irr = compute_irradiance(*dev, env, is);
  EngineBake bake;
  bake.prefiltered = &chain;
  bake.sh = &irr.sh;
  const fs::path ours = dir / "ours";
  write_engine_files(EngineTarget::Filament, bake, ours.string());
  for (const char* f : {"ours_ibl.ktx", "ours_skybox.ktx", "sh.txt"}) EXPECT_TRUE(fs::exists(ours / f)) << f;

  const nlohmann::json a = filament_check(ours / "ours_ibl.ktx");
  const nlohmann::json b = filament_check(cm / "cm_ibl.ktx");
  EXPECT_TRUE(a.at("cubemap").get<bool>());
  EXPECT_EQ(a.at("levels"), b.at("levels"));  // 64, 32, 16 both
  EXPECT_EQ(a.at("width"), 64);
  EXPECT_EQ(a.at("blob_bytes"), b.at("blob_bytes"));  // every face of every level, R11F_G11F_B10F
  // Filament maps the header to the same texture and pixel types as cmgen's own file
  EXPECT_EQ(a.at("texture_format"), b.at("texture_format"));
  EXPECT_EQ(a.at("pixel_data_type"), b.at("pixel_data_type"));
  EXPECT_EQ(a.at("pixel_data_format"), b.at("pixel_data_format"));
  ASSERT_TRUE(a.at("sh").is_array()) << "KtxBundle::getSphericalHarmonics() found no sh key";
  ASSERT_EQ(a.at("sh").size(), 27u);
  EXPECT_EQ(fs_.sh_window, ShWindow::Auto);  // the target's default is cmgen's default

  // Within 1%: of each coefficient's own magnitude, or, for a coefficient that is itself near zero,
  // of the channel's band-0 term (the SH's scale; 1% of it is a 1% change of the lit result).
  auto compare_sh = [](const nlohmann::json& sa, const nlohmann::json& sb, const char* what) {
    double worst = 0.0;
    for (size_t k = 0; k < 9; ++k)
      for (size_t c = 0; c < 3; ++c) {
        const double x = sa[3 * k + c], y = sb[3 * k + c], scale = sb[c];
        worst = std::max(worst, std::fabs(x - y) / std::max(std::fabs(y), std::fabs(scale)));
        EXPECT_NEAR(x, y, test::kCmgenSh * std::max(std::fabs(y), std::fabs(scale)))
            << what << ": coefficient " << k << " channel " << c << " (ours " << x << ", cmgen " << y << ")";
      }
    std::printf("largest SH difference from cmgen (%s): %.3g%%\n", what, 100.0 * worst);
    return worst;
  };
  // The default: ours (auto) against cmgen's default (auto).
  compare_sh(a.at("sh"), b.at("sh"), "window auto");
  // No window on both sides.
  run("cmgen -q -x '" + (dir / "cm_no").string() + "' -f ktx --sh-window=no -s 64 '" + input.string() + "' 2>&1", &rc);
  ASSERT_EQ(rc, 0) << "cmgen --sh-window=no failed";
  is.window = ShWindow::None;
  const IrradianceResult raw = compute_irradiance(*dev, env, is);
  bake.sh = &raw.sh;
  write_engine_files(EngineTarget::Filament, bake, (dir / "ours_no").string());
  const nlohmann::json ours_no = filament_check(dir / "ours_no" / "ours_no_ibl.ktx").at("sh");
  compare_sh(ours_no, filament_check(dir / "cm_no" / "cm_no_ibl.ktx").at("sh"), "window none");
  // and the window matters here: auto and none differ by more than the comparison's tolerance
  double apart = 0.0;
  for (size_t i = 3; i < 27; ++i)
    apart = std::max(apart, std::fabs(double(a.at("sh")[i]) - double(ours_no[i])) / std::fabs(double(ours_no[i % 3])));
  EXPECT_GT(apart, test::kCmgenSh) << "the auto window changed nothing: the comparison above would not see it";
}

}  // namespace
}  // namespace brdfbake
