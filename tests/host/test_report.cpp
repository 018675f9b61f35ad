// `brdfbake report`: a reduced report (tiny tables, a few counts) run as a user runs it, its JSON
// checked against the reference where it can be (the reference against itself is 0, a point
// recomputed here from the device and the scalar reference gives the same error, the quadrature's
// error falls with its samples, the exact Fresnel model is 0 against itself), and a page that needs
// no network.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "brdfbake/accuracy.hpp"
#include "brdfbake/dfg_lut.hpp"
#include "brdfbake/reference/dfg_lut.hpp"
#include "brdfbake/report.hpp"
#include "support/cli_runner.hpp"
#include "support/device_fixture.hpp"
#include "support/temp_dir.hpp"
#include "support/tolerances.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::CliRun;
using test::run_cli;

// A fresh, empty folder `name` in the test's temporary folder (removed when the test ends).
fs::path temp_dir(const std::string& name) { return brdfbake::test::test_temp_dir(name); }

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
    EXPECT_EQ(p["chain_size"], 8) << "--cube-size, its alias, named canonically";
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

// A point of the bake sweep is on the Pareto front when no other point is at most as costly and at
// most as wrong, one strictly: checked here by brute force over every pair.
bool on_front(const json& points, size_t i, const char* cost) {
  for (size_t j = 0; j < points.size(); ++j) {
    if (j == i) continue;
    const double ci = points[i][cost].get<double>(), cj = points[j][cost].get<double>();
    const double ei = points[i]["error"].get<double>(), ej = points[j]["error"].get<double>();
    if (cj <= ci && ej <= ei && (cj < ci || ej < ei)) return false;
  }
  return true;
}

TEST(CliReport, BakeSweepTimesBytesAndTheErrorsOfADirectPreview) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  const fs::path dir = temp_dir("bake");
  const std::string env = "builtin:sun";
  const CliRun r = run_cli("report --kinds bake --env " + env +
                           " --targets generic --vary 'cube_size=32;lut_size=16' --preview-width 96 --runs 2 "
                           "--keep-bakes " +
                           (dir / "bakes").string() + " -o " + (dir / "r.html").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const json j = json::parse(read(dir / "r.json"));
  ASSERT_TRUE(j.contains("bake")) << j.dump();
  const json& b = j["bake"];
  EXPECT_EQ(b["environment"], env);
  ASSERT_EQ(b["targets"].size(), 1u);
  const json& t = b["targets"][0];
  EXPECT_EQ(t["target"], "generic");
  const json& pts = t["points"];
  ASSERT_EQ(pts.size(), 3u) << t.dump();
  EXPECT_EQ(pts[0]["label"], "default");
  EXPECT_EQ(pts[1]["label"], "chain_size=32");  // --vary by the old name: reported canonically
  EXPECT_EQ(pts[2]["label"], "lut_size=16");
  for (size_t i = 0; i < pts.size(); ++i) {
    const json& p = pts[i];
    SCOPED_TRACE(p["label"].get<std::string>());
    // Time: every run measured; the median of two is their mean.
    ASSERT_GE(p["wall_seconds"].size(), 1u);
    for (const json& w : p["wall_seconds"]) EXPECT_GT(w.get<double>(), 0.0);
    EXPECT_GT(p["seconds"].get<double>(), 0.0);
    // Bytes: the files of the kept bake, as the file system counts them.
    const fs::path folder = p["folder"].get<std::string>();
    std::uintmax_t bytes = 0;
    int files = 0;
    for (const auto& e : fs::recursive_directory_iterator(folder))
      if (e.is_regular_file()) {
        bytes += e.file_size();
        ++files;
      }
    EXPECT_EQ(p["bytes"].get<std::uintmax_t>(), bytes);
    EXPECT_EQ(p["files"].get<int>(), files);
    EXPECT_TRUE(fs::exists(folder / "manifest.json"));
    // Errors: a direct `brdfbake preview` of the same bake renders its own reference; the sweep
    // rendered one reference for the target and compared every setting with it. The reference does
    // not depend on the bake and both compare alike: the same numbers, to the last bit (the JSON
    // round-trips doubles).
    const fs::path out = dir / ("preview_" + std::to_string(i) + ".png");
    const CliRun pr = run_cli("preview --env " + env + " --target generic --bake " + folder.string() +
                              " --width 96 --height 48 -o " + out.string());
    ASSERT_EQ(pr.code, 0) << pr.err;
    const json pj = json::parse(read(fs::path(out).replace_extension(".json")));
    const json& spheres = pj["spheres"];
    ASSERT_EQ(spheres.size(), 72u);
    ASSERT_EQ(p["sphere_rms"].size(), 72u);
    std::vector<double> rms;
    for (size_t s = 0; s < spheres.size(); ++s) {
      const json& e = spheres[s]["error"]["linear"];
      EXPECT_EQ(p["sphere_rms"][s].get<double>(), e["rms"].get<double>()) << s;
      EXPECT_EQ(p["sphere_p99"][s].get<double>(), e["p99"].get<double>()) << s;
      EXPECT_EQ(p["sphere_max"][s].get<double>(), e["max"].get<double>()) << s;
      rms.push_back(e["rms"].get<double>());
    }
    std::sort(rms.begin(), rms.end());
    EXPECT_DOUBLE_EQ(p["error"].get<double>(), 0.5 * (rms[35] + rms[36]));  // the median of 72
    EXPECT_EQ(p["groups"].size(), 6u);
    EXPECT_TRUE(p["groups"].contains("gold"));
  }
  // The 16^2 DFG table and the 32^2 chain change the render: not the default's numbers.
  EXPECT_NE(pts[1]["error"].get<double>(), pts[0]["error"].get<double>());
  EXPECT_NE(pts[2]["error"].get<double>(), pts[0]["error"].get<double>());
  // The Pareto flags, checked by brute force; the recommendation by its rule.
  double best = HUGE_VAL;
  for (const json& p : pts) best = std::min(best, p["error"].get<double>());
  std::string fastest;
  double fastest_seconds = HUGE_VAL;
  for (size_t i = 0; i < pts.size(); ++i) {
    EXPECT_EQ(pts[i]["pareto_time"].get<bool>(), on_front(pts, i, "seconds")) << i;
    EXPECT_EQ(pts[i]["pareto_bytes"].get<bool>(), on_front(pts, i, "bytes")) << i;
    if (pts[i]["error"].get<double>() <= kBakeRecommendWithin * best &&
        pts[i]["seconds"].get<double>() < fastest_seconds) {
      fastest_seconds = pts[i]["seconds"].get<double>();
      fastest = pts[i]["label"].get<std::string>();
    }
  }
  EXPECT_EQ(t["recommended"], fastest);
  const std::string html = read(dir / "r.html");
  EXPECT_NE(html.find("What each bake setting costs"), std::string::npos);
  EXPECT_NE(html.find("Pareto front"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
}

// The front and the recommendation on numbers whose answer is known.
TEST(BakeSweep, ParetoFrontAndRecommendation) {
  BakeSweepTarget t;
  const double at[][3] = {{1.0, 0.5, 10}, {2.0, 0.3, 30}, {3.0, 0.3, 20}, {0.5, 0.9, 40}, {4.0, 0.29, 50}};
  for (const auto& a : at) {
    BakeSweepPoint p;
    p.seconds = a[0];
    p.error = a[1];
    p.bytes = std::uint64_t(a[2]);
    t.points.push_back(p);
  }
  mark_bake_sweep(t);
  // time: (3 s, 0.3) is dominated by (2 s, 0.3); every other point is best at something.
  const bool time_front[] = {true, true, false, true, true};
  // bytes: (30, 0.3) is dominated by (20, 0.3); (40, 0.9) by (10, 0.5).
  const bool bytes_front[] = {true, false, true, false, true};
  for (size_t i = 0; i < t.points.size(); ++i) {
    EXPECT_EQ(t.points[i].pareto_time, time_front[i]) << i;
    EXPECT_EQ(t.points[i].pareto_bytes, bytes_front[i]) << i;
  }
  // Within 10% of the best 0.29 (<= 0.319): 0.3 at 2 s and 3 s, 0.29 at 4 s; the fastest is 2 s.
  EXPECT_EQ(t.recommended, 1);
}

// The page of `report --kinds bake` alone says what it answers (not the DFG report's intro), and
// its plots' labels do not overlap: a sweep whose settings tie (the same error at nearly the same
// time and bytes, as lut_size and the chain's max error do on a real sweep) drew their labels on top
// of each other. Each label's box is estimated as the page places them (9-pixel font, 5.2 pixels a
// character, a 10-pixel line); every Pareto point's setting is written.
TEST(BakeSweep, PageSaysWhatItAnswersAndItsLabelsDoNotOverlap) {
  Report r;
  BakeSweep sweep;
  sweep.environment = "builtin:studio";
  sweep.preview_width = 96;
  BakeSweepTarget t;
  t.target = "generic";
  const char* const labels[] = {"default",     "cube_size=64", "cube_size=128", "lut_size=16", "lut_size=32",
                                "lut_size=64", "pixel=f32",    "sh_order=5",    "min_size=4",  "n_dot_v_axis=sqrt"};
  for (size_t i = 0; i < std::size(labels); ++i) {
    BakeSweepPoint p;
    p.label = labels[i];
    const bool tied = i >= 3 && i <= 7;  // five settings at the default's error, 1.00-1.04 s, 4.4 MB
    p.seconds = tied ? 1.0 + 0.01 * double(i - 3) : i == 0 ? 1.05 : 0.2 * double(i);
    p.error = tied || i == 0 ? 0.109 : 0.13 - 0.004 * double(i);
    p.bytes = tied || i == 0 ? 4400000 + 1000 * i : 500000 * i;
    p.wall_seconds = {p.seconds};
    t.points.push_back(p);
  }
  mark_bake_sweep(t);
  sweep.targets.push_back(t);
  r.bake.push_back(sweep);
  const std::string html = report_html(r);
  EXPECT_NE(html.find("<h1>brdfbake: what each bake setting costs</h1>"), std::string::npos);
  EXPECT_NE(html.find("Which bake settings to use for each target engine"), std::string::npos);
  EXPECT_EQ(html.find("DFG errors are"), std::string::npos) << "the DFG report's intro on the bake page";

  struct Box {
    double x0, y0, x1, y1;
    std::string text;
  };
  size_t at = 0;
  int plots = 0;
  while ((at = html.find("<svg", at)) != std::string::npos) {
    const size_t end = html.find("</svg>", at);
    const std::string svg = html.substr(at, end - at);
    at = end;
    ++plots;
    std::vector<Box> boxes;
    size_t k = 0;
    while ((k = svg.find("<text x=\"", k)) != std::string::npos) {
      const size_t close = svg.find('>', k), stop = svg.find("</text>", close);
      const std::string tag = svg.substr(k, close - k), text = svg.substr(close + 1, stop - close - 1);
      k = stop;
      if (tag.find("font-size=\"9\"") == std::string::npos) continue;  // axis ticks and titles
      const double x = std::stod(tag.substr(tag.find("x=\"") + 3)), y = std::stod(tag.substr(tag.find(" y=\"") + 4));
      const double w = 5.2 * double(text.size());
      const bool end_anchor = tag.find("text-anchor=\"end\"") != std::string::npos;
      boxes.push_back({end_anchor ? x - w : x, y - 8, end_anchor ? x : x + w, y + 2, text});
    }
    ASSERT_FALSE(boxes.empty()) << svg;
    for (size_t a = 0; a < boxes.size(); ++a)
      for (size_t b = a + 1; b < boxes.size(); ++b) {
        const bool apart = boxes[a].x1 <= boxes[b].x0 || boxes[b].x1 <= boxes[a].x0 || boxes[a].y1 <= boxes[b].y0 ||
                           boxes[b].y1 <= boxes[a].y0;
        EXPECT_TRUE(apart) << "plot " << plots << ": '" << boxes[a].text << "' over '" << boxes[b].text << "'";
      }
    const bool bytes_plot = svg.find("against bytes") != std::string::npos;
    for (const BakeSweepPoint& p : r.bake[0].targets[0].points) {
      if (!(bytes_plot ? p.pareto_bytes : p.pareto_time)) continue;
      EXPECT_TRUE(std::any_of(boxes.begin(), boxes.end(), [&](const Box& b) { return b.text == p.label; }))
          << "plot " << plots << ": the Pareto point " << p.label << " is not labelled";
    }
  }
  EXPECT_EQ(plots, 2);
}

TEST(CliReport, BadUsageIsOneLineAndExitTwo) {
  const fs::path dir = temp_dir("bad");
  for (const std::string args :
       {"--kinds nope", "--device reference", "--counts 0", "--precisions fp16", "--materials unobtainium",
        "--kinds bake --targets nope", "--kinds bake --vary cube_size",
        "--kinds bake --vary 'chain_size=32;cube_size=64'", "--kinds bake --vary colour=red",
        "--kinds bake --preview-width 8", "--kinds bake --runs 0",
        "--lut-size 4" /* with the --size 4 below: an option and its alias together */}) {
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
