// `brdfbake report`: a reduced report (tiny tables, a few counts) run as a user runs it, its JSON
// checked against the reference where it can be (the reference against itself is 0, a point
// recomputed here from the device and the scalar reference gives the same error, the quadrature's
// error falls with its samples, the exact Fresnel model is 0 against itself), and a page that needs
// no network.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
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
    const double ei = points[i]["bake_error"].get<double>(), ej = points[j]["bake_error"].get<double>();
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
    // The shares: the sweep's ideal bake (shared between settings of one chain shape) and the
    // preview's own (made for these files alone) are the same computation: the same numbers.
    for (size_t s = 0; s < spheres.size(); ++s) {
      EXPECT_EQ(p["sphere_bake"][s].get<double>(), spheres[s]["bake_share"]["rms"].get<double>()) << s;
      EXPECT_EQ(p["sphere_engine"][s].get<double>(), spheres[s]["engine_share"]["rms"].get<double>()) << s;
      // the probe: the spheres below roughness 0.1 (r0, r0.05 of each row), -1 for the others
      const double roughness = spheres[s]["material"]["roughness"].get<double>();
      EXPECT_EQ(p["sphere_sharp"][s].get<double>() >= 0.0, roughness < 0.1) << s;
    }
    for (const auto& [name, g] : p["groups"].items()) {
      double worst = 0.0, sharp = -1.0;
      for (size_t s = 0; s < spheres.size(); ++s)
        if (spheres[s]["name"].get<std::string>().rfind(name + " ", 0) == 0) {
          worst = std::max(worst, spheres[s]["bake_share"]["rms"].get<double>());
          sharp = std::max(sharp, p["sphere_sharp"][s].get<double>());
        }
      EXPECT_EQ(g["bake_worst"].get<double>(), worst) << name;
      EXPECT_EQ(g["sharp"].get<double>(), sharp) << name;
    }
  }
  // The 32^2 chain (against 256^2) and the 16^2 DFG table (against 128^2) add to the bake's share:
  // the chain on the mirrors' probe above all, the table on the spheres.
  EXPECT_GT(pts[1]["groups"]["gold"]["sharp"].get<double>(), 2.0 * pts[0]["groups"]["gold"]["sharp"].get<double>());
  EXPECT_GT(pts[1]["bake_error"].get<double>(), pts[0]["bake_error"].get<double>());
  EXPECT_GT(pts[2]["bake_error"].get<double>(), pts[0]["bake_error"].get<double>());
  // The Pareto flags, checked by brute force; the recommendation by its rule (the BakeSweep tests
  // below hold the rule to numbers whose answer is known).
  for (size_t i = 0; i < pts.size(); ++i) {
    EXPECT_EQ(pts[i]["pareto_time"].get<bool>(), on_front(pts, i, "seconds")) << i;
    EXPECT_EQ(pts[i]["pareto_bytes"].get<bool>(), on_front(pts, i, "bytes")) << i;
  }
  // no blurrier than the default on any group's probe; within 10 % of the best of those on every
  // group's worst sphere
  std::vector<bool> sharp_ok(pts.size(), true), ok(pts.size(), true);
  for (size_t i = 0; i < pts.size(); ++i)
    for (const auto& [name, g] : pts[i]["groups"].items()) {
      const json& d = pts[0]["groups"][name]["sharp"];
      if (!d.is_null() && !g["sharp"].is_null())
        sharp_ok[i] = sharp_ok[i] && g["sharp"].get<double>() <= kBakeSharpWithin * d.get<double>();
      sharp_ok[i] = sharp_ok[i] && g["engine_median"].get<double>() <=
                                       kBakeSharpWithin * pts[0]["groups"][name]["engine_median"].get<double>();
    }
  std::map<std::string, double> best;
  for (size_t i = 0; i < pts.size(); ++i)
    for (const auto& [name, g] : pts[i]["groups"].items())
      if (sharp_ok[i])
        best[name] =
            best.count(name) ? std::min(best[name], g["bake_worst"].get<double>()) : g["bake_worst"].get<double>();
  for (size_t i = 0; i < pts.size(); ++i) {
    ok[i] = sharp_ok[i];
    for (const auto& [name, g] : pts[i]["groups"].items())
      ok[i] = ok[i] && g["bake_worst"].get<double>() <= kBakeRecommendWithin * best[name];
    EXPECT_EQ(pts[i]["eligible"].get<bool>(), ok[i]) << pts[i]["label"];
  }
  const auto eligible = std::count(ok.begin(), ok.end(), true);
  // the settings the recommendation may take were timed --runs (2) times when more than one may; the
  // others once
  for (size_t i = 0; i < pts.size(); ++i)
    EXPECT_EQ(pts[i]["wall_seconds"].size(), ok[i] && eligible > 1 ? 2u : 1u) << pts[i]["label"];
  const std::string recommended = t["recommended"].get<std::string>();
  for (const json& p : pts) {
    if (p["label"] == recommended && eligible > 0) {
      EXPECT_TRUE(p["eligible"].get<bool>());
    }
  }
  EXPECT_FALSE(t["why"].get<std::string>().empty());
  const std::string html = read(dir / "r.html");
  EXPECT_NE(html.find("What each bake setting costs"), std::string::npos);
  EXPECT_NE(html.find("Pareto front"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
}

// The front and the recommendation on numbers whose answer is known.
namespace {
BakeSweepPoint sweep_point(const std::string& label, double seconds, double spread, double bake_error,
                           std::uint64_t bytes, std::vector<std::array<double, 2>> groups) {
  BakeSweepPoint p;
  p.label = label;
  p.seconds = seconds;
  p.spread = spread;
  p.wall_seconds = {seconds - 0.5 * spread, seconds, seconds + 0.5 * spread};
  p.bake_error = bake_error;
  p.bytes = bytes;
  const char* names[] = {"white", "gold"};
  for (size_t g = 0; g < groups.size(); ++g) {
    BakeSweepGroup bg;
    bg.name = names[g];
    bg.bake_worst = groups[g][0];
    bg.sharp = groups[g][1];
    p.groups.push_back(bg);
  }
  return p;
}
}  // namespace

TEST(BakeSweep, ParetoFrontAndRecommendation) {
  BakeSweepTarget t;
  // label, seconds, spread, bake share (median), bytes, per group {worst sphere's bake share, probe}
  t.points = {
      sweep_point("default", 1.0, 0.05, 0.010, 40, {{0.0085, 0.10}, {0.100, 0.30}}),
      // best on white, 15 % worse than the best on gold: not eligible
      sweep_point("a", 0.5, 0.05, 0.009, 10, {{0.008, 0.10}, {0.115, 0.30}}),
      // within 10 % on both groups but its probe 3 % blurrier than the default's on gold: not eligible
      sweep_point("b", 0.4, 0.05, 0.009, 10, {{0.0085, 0.10}, {0.105, 0.309}}),
      // eligible: within 10 % of the best (white 0.008, gold 0.100), probes no blurrier
      sweep_point("c", 0.9, 0.02, 0.009, 30, {{0.0087, 0.09}, {0.1099, 0.29}}),
      // eligible, ties c in time (|0.95 - 0.9| <= 0.08) with fewer bytes: taken
      sweep_point("d", 0.95, 0.08, 0.011, 20, {{0.0087, 0.10}, {0.104, 0.305}}),
      // eligible but slower than c by more than either spread
      sweep_point("e", 1.5, 0.1, 0.008, 5, {{0.0080, 0.05}, {0.100, 0.20}}),
      // far lower on gold's worst sphere but blurrier than the default: it does not set the bar (else
      // no other setting would be within 10 % of its 0.05 on gold)
      sweep_point("blur", 0.3, 0.01, 0.02, 3, {{0.02, 0.10}, {0.050, 0.40}}),
      // the default's bake shares, fastest of all, but the engine reads it worse (a chain of fewer
      // levels: its LOD from roughness): not eligible
      sweep_point("lod", 0.2, 0.01, 0.010, 40, {{0.0085, 0.10}, {0.100, 0.30}}),
  };
  for (BakeSweepPoint& p : t.points)
    for (BakeSweepGroup& g : p.groups) g.engine_median = 0.2;
  t.points.back().groups[1].engine_median = 0.21;  // 5 % above the default's
  mark_bake_sweep(t);
  const bool eligible[] = {true, false, false, true, true, true, false, false};
  for (size_t i = 0; i < t.points.size(); ++i) EXPECT_EQ(t.points[i].eligible, eligible[i]) << t.points[i].label;
  ASSERT_EQ(t.recommended, 4) << t.why;
  EXPECT_EQ(t.ties, std::vector<std::string>{"c"});
  EXPECT_NE(t.why.find("ties in time with c"), std::string::npos) << t.why;
  // time front over the bake share: b (0.4 s, 0.009) dominates a (0.5 s, 0.009) and c (0.9 s, 0.009);
  // default (1.0, 0.010) and d (0.95, 0.011) are dominated by b; e is the least wrong
  // blur (0.3 s, 0.02) by lod (0.2 s, 0.010)
  const bool time_front[] = {false, false, true, false, false, true, false, true};
  // bytes: e (5, 0.008) dominates every other but blur (3 bytes, the fewest)
  const bool bytes_front[] = {false, false, false, false, false, true, true, false};
  for (size_t i = 0; i < t.points.size(); ++i) {
    EXPECT_EQ(t.points[i].pareto_time, time_front[i]) << t.points[i].label;
    EXPECT_EQ(t.points[i].pareto_bytes, bytes_front[i]) << t.points[i].label;
  }
  // Without the tie (c's spread and d's narrower than their 0.05 s apart), the fastest is taken.
  t.points[3].spread = t.points[4].spread = 0.01;
  mark_bake_sweep(t);
  EXPECT_EQ(t.recommended, 3) << t.why;
  EXPECT_TRUE(t.ties.empty());
  // Settings that trade one group against another, none within 10 % on both: the one closest to the
  // best on its worst group (x: 20 % above on gold; y: 50 % above on white).
  BakeSweepTarget trade;
  trade.points = {sweep_point("default", 1.0, 0.0, 0.02, 40, {{0.015, 0.3}, {0.12, 0.3}}),
                  sweep_point("x", 1.0, 0.0, 0.02, 40, {{0.010, 0.3}, {0.12, 0.3}}),
                  sweep_point("y", 1.0, 0.0, 0.02, 40, {{0.015, 0.3}, {0.10, 0.3}})};
  mark_bake_sweep(trade);
  for (const BakeSweepPoint& p : trade.points) EXPECT_FALSE(p.eligible) << p.label;
  EXPECT_EQ(trade.recommended, 1) << trade.why;
  EXPECT_NE(trade.why.find("20 %"), std::string::npos) << trade.why;
  // One eligible setting: it is recommended whatever its time.
  BakeSweepTarget one;
  one.points = {sweep_point("default", 1.0, 0.0, 0.02, 40, {{0.02, 0.3}}),
                sweep_point("big", 9.0, 0.0, 0.01, 400, {{0.01, 0.1}})};
  mark_bake_sweep(one);
  EXPECT_FALSE(one.points[0].eligible);
  EXPECT_EQ(one.recommended, 1) << one.why;
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
    p.bake_error = p.error;
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
