// `brdfbake report`: a reduced report (tiny tables, a few counts) run as a user runs it, its JSON
// checked against the reference where it can be (the reference against itself is 0, a point
// recomputed here from the device and the scalar reference gives the same error, the quadrature's
// error falls with its samples, the exact Fresnel model is 0 against itself), and a page that needs
// no network.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "brdfbake/accuracy.hpp"
#include "brdfbake/dfg_lut.hpp"
#include "brdfbake/reference/dfg_lut.hpp"
#include "support/cli_runner.hpp"
#include "support/device_fixture.hpp"
#include "support/tolerances.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::CliRun;
using test::run_cli;

fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("brdfbake-report-" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(CliReport, ReducedReportNumbersAgreeWithTheReference) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  const fs::path dir = temp_dir("reduced");
  const CliRun r = run_cli(
      "report --kinds ggx,charlie,fresnel,prefilter --size 8 --counts 16,64,256,1024 "
      "--estimators quadrature,ndf --materials gold --cube-size 8 -o " +
      (dir / "sub/r.html").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("measurements on"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("load average"), std::string::npos) << r.err;
  const json j = json::parse(read(dir / "sub/r.json"));
  EXPECT_EQ(j["cores"].get<int>() > 0, true);
  EXPECT_EQ(j["load_average_before"].size(), 3u);
  ASSERT_EQ(j["dfg"].size(), 2u);
  for (const json& k : j["dfg"]) {
    SCOPED_TRACE(k["kind"].get<std::string>());
    EXPECT_EQ(k["size"], 8);
    // The measure's own check: the reference against itself.
    EXPECT_EQ(k["reference"]["error"]["max"].get<double>(), 0.0);
    EXPECT_GT(k["reference"]["seconds"].get<double>(), 0.0);
    std::vector<double> quadrature;
    for (const json& p : k["points"]) {
      EXPECT_GT(p["device_seconds"].get<double>(), 0.0);
      EXPECT_GT(p["evaluations_per_texel"].get<int>(), 0);
      const double e = p["error"]["max"].get<double>();
      EXPECT_TRUE(std::isfinite(e) && e >= 0);
      EXPECT_LE(p["error"]["rms"].get<double>(), e);
      if (p["estimator"] == "quadrature") quadrature.push_back(e);
    }
    // The deterministic quadrature converges: each count at least as good as the one before (up to
    // fp32 rounding), and 1024 samples far better than 16.
    ASSERT_EQ(quadrature.size(), 4u);
    for (size_t n = 1; n < quadrature.size(); ++n) EXPECT_LE(quadrature[n], quadrature[n - 1] + test::kLutFp32Rounding);
    EXPECT_LT(quadrature.back(), 1e-2 * quadrature.front());
    EXPECT_LT(quadrature.back(), test::kLutDefaultBound);
  }
  // One point recomputed here: ggx, quadrature, 16 samples, against the scalar reference directly.
  LutSpec s;
  s.kind = LutKind::Ggx;
  s.width = 8;
  s.samples = 16;
  const Table got = bake_lut(*dev, s);
  const std::vector<double> want = reference::lut_table(reference::LutKind::Ggx, 8, 8);
  double max = 0;
  for (size_t k = 0; k < want.size(); ++k)
    max = std::max(max, std::fabs(double(got.data[k]) - want[k]) / std::max(1.0, std::fabs(want[k])));
  const json& first = j["dfg"][0]["points"][0];
  ASSERT_EQ(first["samples"], 16);
  ASSERT_EQ(first["estimator"], "quadrature");
  // The report's reference is the same converged integral stored as float: the two measures differ
  // by that storage rounding at most.
  EXPECT_NEAR(first["error"]["max"].get<double>(), max, test::kLutFp32Rounding);

  // Fresnel: the exact model against itself is 0; every approximation is off by something.
  ASSERT_EQ(j["fresnel"].size(), 1u);
  const json& gold = j["fresnel"][0];
  EXPECT_EQ(gold["exact_model"], "conductor");
  for (const json& m : gold["models"]) {
    if (m["model"] == "conductor") {
      EXPECT_EQ(m["worst"].get<double>(), 0.0);
    } else {
      EXPECT_GT(m["worst"].get<double>(), 0.0) << m["model"];
    }
    EXPECT_GT(m["cells_per_second"].get<double>(), 0.0) << m["model"];
  }
  // Prefilter: both estimators, every level after the source, finite errors; the quadrature within
  // 5% RMS even at 8^2 (docs/BENCHMARKS.md: < 1% at the default sizes).
  ASSERT_EQ(j["prefilter"].size(), 2u);
  for (const json& p : j["prefilter"]) {
    ASSERT_FALSE(p["levels"].empty());
    for (const json& l : p["levels"]) {
      EXPECT_TRUE(std::isfinite(l["rms_error"].get<double>()));
      if (p["estimator"] == "quadrature") {
        EXPECT_LT(l["rms_error"].get<double>(), test::kEnvPrefilterReportRms) << l.dump();
      }
    }
  }
  // A page that stands alone: inline SVG, no scripts, nothing fetched.
  const std::string html = read(dir / "sub/r.html");
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_EQ(html.find("src="), std::string::npos);
  EXPECT_EQ(html.find("url("), std::string::npos);
  EXPECT_NE(html.find("load average"), std::string::npos);
}

TEST(CliReport, BadUsageIsOneLineAndExitTwo) {
  const fs::path dir = temp_dir("bad");
  for (const std::string args :
       {"--kinds nope", "--device reference", "--counts 0", "--precisions fp16", "--materials unobtainium"}) {
    const CliRun r = run_cli("report " + args + " --size 4 -o " + (dir / "r.html").string());
    EXPECT_EQ(r.code, 2) << args << ": " << r.err;
    EXPECT_EQ(test::count_lines(r.err), 1) << args << ": " << r.err;
  }
  EXPECT_EQ(run_cli("report -o " + (dir / "r.txt").string()).code, 2);
  EXPECT_FALSE(fs::exists(dir / "r.html"));
  EXPECT_FALSE(fs::exists(dir / "r.json"));
}

}  // namespace
}  // namespace brdfbake
