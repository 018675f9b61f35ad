// `brdfbake fresnel`, run as a user runs it: the table's CSV shape and cell rules, the error
// columns of --vs exact, 2-D tables, every format, the listing, comparison and fit modes, and one
// clear line with a non-zero exit and no file for every bad input.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "brdfbake/reference/fresnel.hpp"
#include "brdfbake/table.hpp"
#include "io/table_read.hpp"
#include "support/cli_runner.hpp"
#include "support/table_readback.hpp"
#include "support/temp_dir.hpp"
#include "support/tolerances.hpp"

namespace {

namespace fs = std::filesystem;

using brdfbake::test::CliRun;
using brdfbake::test::count_lines;

CliRun run(const std::string& args) { return brdfbake::test::run_cli(args); }

// A folder `name` in the test's temporary folder (removed when the test ends).
fs::path temp_dir(const std::string& name) {
  const fs::path d = brdfbake::test::test_temp_root() / name;
  fs::create_directories(d);
  return d;
}

// A CSV from standard output: the '#' metadata lines, the header, the rows split into fields.
struct Csv {
  std::vector<std::string> meta;
  std::string header;
  std::vector<std::vector<double>> rows;
};
Csv parse_csv(const std::string& text) {
  Csv c;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("#", 0) == 0) {
      c.meta.push_back(line);
    } else if (c.header.empty()) {
      c.header = line;
    } else {
      std::vector<double> row;
      std::istringstream fields(line);
      std::string f;
      while (std::getline(fields, f, ',')) row.push_back(std::strtod(f.c_str(), nullptr));
      c.rows.push_back(row);
    }
  }
  return c;
}

bool has_meta(const Csv& c, const std::string& prefix) {
  for (const std::string& m : c.meta)
    if (m.rfind(prefix, 0) == 0) return true;
  return false;
}

TEST(CliFresnel, CsvHeaderAndCellCentres) {
  const CliRun r = run("fresnel --model schlick --f0 0.04 --size 4 --quiet -o - --format csv");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  const Csv c = parse_csv(r.out);
  EXPECT_EQ(c.header, "cos_theta,r,g,b");
  ASSERT_EQ(c.rows.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    ASSERT_EQ(c.rows[i].size(), 4u);
    EXPECT_DOUBLE_EQ(c.rows[i][0], (static_cast<double>(i) + 0.5) / 4.0);
    EXPECT_NEAR(c.rows[i][1], brdfbake::reference::fresnel_schlick(c.rows[i][0], 0.04), brdfbake::test::kFresnelFp32);
  }
  for (const char* key :
       {"# generator: brdfbake", "# model: schlick", "# parameters: f0 = 0.04, f90 = 1", "# material: none",
        "# x_axis: cos_theta = (i + 0.5) / width", "# precision: fp32", "# device: ", "# channels: r,g,b"})
    EXPECT_TRUE(has_meta(c, key)) << key << "\n" << r.out;
}

TEST(CliFresnel, EndpointsIncludeGrazingAndNormalIncidence) {
  const CliRun r = run("fresnel --model conductor --material gold --size 5 --endpoints --quiet -o - --format csv");
  ASSERT_EQ(r.code, 0) << r.err;
  const Csv c = parse_csv(r.out);
  ASSERT_EQ(c.rows.size(), 5u);
  EXPECT_EQ(c.rows.front()[0], 0.0);
  EXPECT_EQ(c.rows.back()[0], 1.0);
  for (int ch = 1; ch <= 3; ++ch)
    EXPECT_NEAR(c.rows.front()[size_t(ch)], 1.0, brdfbake::test::kFresnelGrazingOne) << "grazing";
  // Normal incidence: ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2), gold red n = 0.188, k = 3.403.
  EXPECT_NEAR(c.rows.back()[1], brdfbake::reference::schlick_f0_from_conductor(0.188, 3.403),
              brdfbake::test::kFresnelFp32);
  EXPECT_TRUE(has_meta(c, "# x_axis: cos_theta = i / (width - 1)"));
  EXPECT_TRUE(has_meta(c, "# material: gold"));
  EXPECT_TRUE(has_meta(c, "# material_source: Johnson & Christy 1972"));
}

// The conventions line states what the model computes: eta only where an index enters (issue 10:
// the empirical rim term's CSV carried the dielectric's eta line).
TEST(CliFresnel, ConventionsNameEtaOnlyForModelsWithAnIndex) {
  auto conventions = [](const std::string& args) {
    const CliRun r = run("fresnel " + args + " --size 2 --quiet -o - --format csv");
    EXPECT_EQ(r.code, 0) << r.err;
    for (const std::string& m : parse_csv(r.out).meta)
      if (m.rfind("# conventions: ", 0) == 0) return m;
    return std::string();
  };
  const std::string empirical = conventions("--model empirical --bias 0.1 --scale 0.9 --power 5");
  EXPECT_EQ(empirical.find("eta ="), std::string::npos) << empirical;
  EXPECT_NE(empirical.find("empirical rim term"), std::string::npos) << empirical;
  EXPECT_EQ(conventions("--model schlick --f0 0.04").find("eta ="), std::string::npos);
  EXPECT_NE(conventions("--model dielectric --ior 1.5").find("eta = n_t / n_i"), std::string::npos);
  EXPECT_NE(conventions("--model conductor --material gold").find("unpolarised reflectance"), std::string::npos);
}

// --vs exact: err_<c> = value - exact, the exact model being the conductor for a metal preset.
TEST(CliFresnel, VsExactAddsSignedErrorColumns) {
  const CliRun r =
      run("fresnel --model schlick --material gold --size 64 --endpoints --vs exact --quiet -o - --format csv");
  ASSERT_EQ(r.code, 0) << r.err;
  const Csv c = parse_csv(r.out);
  EXPECT_EQ(c.header, "cos_theta,r,g,b,err_r,err_g,err_b");
  ASSERT_EQ(c.rows.size(), 64u);
  const double n[3] = {0.188, 0.544, 1.332}, k[3] = {3.403, 2.231, 1.869};
  double worst = 0.0;
  for (const auto& row : c.rows)
    for (int ch = 0; ch < 3; ++ch) {
      const double exact = brdfbake::reference::fresnel_conductor(row[0], n[ch], k[ch]);
      EXPECT_NEAR(row[size_t(4 + ch)], row[size_t(1 + ch)] - exact, brdfbake::test::kFresnelFp32) << "cos " << row[0];
      worst = std::max(worst, std::fabs(row[size_t(4 + ch)]));
    }
  EXPECT_GT(worst, 0.01) << "Schlick misses gold by ~0.02";
  EXPECT_EQ(c.rows.back()[4], 0.0) << "Schlick from the exact F0 is exact at normal incidence";
  EXPECT_TRUE(has_meta(c, "# error_columns: err_<c> = <c> - exact_<c>"));
  EXPECT_TRUE(has_meta(c, "# error_max_abs: "));

  // For an IOR the exact model is the dielectric with the same pair.
  const CliRun d = run("fresnel --model schlick-ior --ior 1.5 --size 8 --vs exact --quiet -o - --format csv");
  ASSERT_EQ(d.code, 0) << d.err;
  EXPECT_NE(d.out.find("exact is the dielectric model"), std::string::npos) << d.out;
}

TEST(CliFresnel, TwoDimensionalTableHasAYColumn) {
  const CliRun r = run("fresnel --model dielectric --table 2d --size 4 --height 3 --quiet -o - --format csv");
  ASSERT_EQ(r.code, 0) << r.err;
  const Csv c = parse_csv(r.out);
  EXPECT_EQ(c.header, "cos_theta,ior,f");
  ASSERT_EQ(c.rows.size(), 12u);
  // cell centres of the default [1, 3]; CSV keeps 9 significant digits
  EXPECT_NEAR(c.rows[0][1], 1.0 + 2.0 * 0.5 / 3.0, brdfbake::test::kTextNineDigits);
  EXPECT_NEAR(c.rows[11][1], 1.0 + 2.0 * 2.5 / 3.0, brdfbake::test::kTextNineDigits);
  EXPECT_TRUE(has_meta(c, "# y_range: 1,3"));
  const CliRun f =
      run("fresnel --model schlick --table 2d --size 3 --height 5 --range 0,0.5 --endpoints --quiet "
          "-o - --format csv");
  ASSERT_EQ(f.code, 0) << f.err;
  const Csv g = parse_csv(f.out);
  EXPECT_EQ(g.header, "cos_theta,f0,f");
  ASSERT_EQ(g.rows.size(), 15u);
  EXPECT_EQ(g.rows.front()[1], 0.0);
  EXPECT_EQ(g.rows.back()[1], 0.5);
  EXPECT_NEAR(g.rows.back()[2], 0.5, brdfbake::test::kFresnelFp32Exact) << "cos 1, F0 0.5";
}

// Every format holds the table the CSV holds (read back: values within the format's step, the
// shape, the channels and the metadata); so do a 2-D table and the error columns of --vs exact.
TEST(CliFresnel, EveryFormatAndTheReferenceDevice) {
  const fs::path dir = temp_dir("formats");
  const std::vector<std::string> keys = {"model", "material", "device", "precision", "x_axis"};
  brdfbake::Table want;
  for (const char* ext : {"csv", "exr", "png", "hdr", "ktx2", "h"}) {
    const fs::path out = dir / (std::string("gold.") + ext);
    const CliRun r = run("fresnel --model conductor --material gold --size 16 --quiet -o " + out.string());
    ASSERT_EQ(r.code, 0) << ext << ": " << r.err;
    if (std::string(ext) == "csv") {
      want = brdfbake::io::read_table(out.string());
      ASSERT_EQ(want.width, 16);
      ASSERT_EQ(want.channels.size(), 3u);
      continue;
    }
    brdfbake::test::expect_table_file(out.string(), want, keys);
  }
  const std::string two_d = "fresnel --model f82-tint --f82 0.9 --table 2d --size 8 --quiet -o ";
  ASSERT_EQ(run(two_d + (dir / "f0.csv").string()).code, 0);
  ASSERT_EQ(run(two_d + (dir / "f0.exr").string()).code, 0);
  const brdfbake::Table want_2d = brdfbake::io::read_table((dir / "f0.csv").string());
  EXPECT_EQ(want_2d.width, 8);
  EXPECT_GT(want_2d.height, 1);
  brdfbake::test::expect_table_file((dir / "f0.exr").string(), want_2d, {"model", "table", "x_axis", "y_axis"});
  const std::string vs = "fresnel --model f82-tint --material iron --size 8 --vs exact --quiet -o ";
  ASSERT_EQ(run(vs + (dir / "err.csv").string()).code, 0);
  ASSERT_EQ(run(vs + (dir / "err.h").string()).code, 0);
  const brdfbake::Table want_vs = brdfbake::io::read_table((dir / "err.csv").string());
  EXPECT_EQ(want_vs.channels.size(), 6u) << "F and its error against the exact conductor, per channel";
  brdfbake::test::expect_table_file((dir / "err.h").string(), want_vs, {"model", "material", "error_columns"});
  const CliRun ref =
      run("fresnel --model dielectric --material water --size 4 --device reference --quiet -o - --format csv");
  EXPECT_EQ(ref.code, 0) << ref.err;
  EXPECT_NE(ref.out.find("# device: reference"), std::string::npos);
  const CliRun fp64 = run("fresnel --model conductor --material silver --size 4 --precision fp64 -o - --format csv");
  EXPECT_EQ(fp64.code, 0) << fp64.err;
  EXPECT_EQ(count_lines(fp64.err), 1) << "one summary line: " << fp64.err;
  fs::remove_all(dir.parent_path());
}

TEST(CliFresnel, ListMaterialsShowsExactAndHardCodedF0) {
  const CliRun r = run("fresnel --list-materials");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* needle : {"gold", "silver", "copper", "aluminium", "iron", "chromium", "titanium", "nickel",
                             "platinum", "water", "glass", "diamond", "skin",
                             "0.942 0.704 0.403",     // gold's exact F0 (Johnson & Christy 1972)
                             "1.000 0.710 0.290",     // gold as hard-coded from Hoffman 2010
                             "0.950 0.640 0.540",     // copper, the same table
                             "+0.058 +0.006 -0.113",  // their difference for gold
                             "Johnson & Christy 1972", "Real-Time Rendering 4th ed."})
    EXPECT_NE(r.out.find(needle), std::string::npos) << needle;
}

TEST(CliFresnel, CompareListsEveryModelWithErrorAndRate) {
  const CliRun r = run("fresnel --compare --material copper --rate-cells 4096");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* needle : {"exact conductor", "schlick ", "schlick-metallic", "conductor ", "f82-tint", "empirical",
                             "Mcells/s", "rate: RGB cells per second"})
    EXPECT_NE(r.out.find(needle), std::string::npos) << needle << "\n" << r.out;
  EXPECT_EQ(r.out.find("schlick-ior"), std::string::npos) << "a metal has no real index";
  const CliRun w = run("fresnel --compare --material water --device reference");
  ASSERT_EQ(w.code, 0) << w.err;
  for (const char* needle : {"exact dielectric", "schlick-ior", "dielectric "})
    EXPECT_NE(w.out.find(needle), std::string::npos) << needle;
}

TEST(CliFresnel, FitGivesSchlickF0AndF82Tint) {
  const CliRun r = run("fresnel --fit --material chromium");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("Schlick F0"), std::string::npos);
  EXPECT_NE(r.out.find("F82 tint"), std::string::npos);
  EXPECT_NE(r.out.find("0.553 0.556 0.558"), std::string::npos) << r.out;
  const CliRun i = run("fresnel --fit --ior 1.5");
  ASSERT_EQ(i.code, 0) << i.err;
  EXPECT_NE(i.out.find("0.040 0.040 0.040"), std::string::npos) << i.out;
}

// Each bad input: non-zero exit, exactly one line on stderr naming the problem, no file.
void expect_clean_failure(const std::string& args, const fs::path& out, const std::string& needle) {
  const CliRun r = run("fresnel " + args + " --quiet -o " + out.string());
  EXPECT_EQ(r.code, 2) << args;
  EXPECT_EQ(count_lines(r.err), 1) << args << " -> " << r.err;
  EXPECT_NE(r.err.find(needle), std::string::npos) << args << " -> " << r.err;
  EXPECT_FALSE(fs::exists(out)) << args;
  for (const auto& e : fs::directory_iterator(out.parent_path()))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << "left behind: " << e.path();
}

TEST(CliFresnel, BadInputGivesOneLineAndNoFile) {
  const fs::path dir = temp_dir("bad");
  const fs::path out = dir / "t.csv";
  expect_clean_failure(
      "--model dielectric --ior -1.5", out,
      "--ior: must be a number or three numbers r,g,b, each greater than 0 and at most 1000 (got -1.5)");
  expect_clean_failure("--model dielectric --ior 1.5 --ior-outside 0", out,
                       "--ior-outside: must be a number greater than 0");
  expect_clean_failure("--model dielectric --ior nan", out, "--ior: must be a number or three numbers");
  expect_clean_failure("--model schlick --f0 nan,0.5,0.5", out,
                       "--f0: must be a number or three numbers r,g,b, each in 0..1 (got [nan, 0.5, 0.5])");
  expect_clean_failure("--model schlick --f0 1,2", out, "got '1,2'");
  expect_clean_failure("--model schlick --f0 0.04,", out, "--f0: must be");
  expect_clean_failure("--model schlick --f0 1.5", out,
                       "--f0: must be a number or three numbers r,g,b, each in 0..1 (got 1.5)");
  expect_clean_failure("--model conductor --n 0.2,0.5,1.3 --k 3,2,-1", out,
                       "--k: must be a number or three numbers r,g,b, each in 0..1000 (got [3, 2, -1])");
  expect_clean_failure("--model conductor --material unobtainium", out, "unknown material 'unobtainium'");
  expect_clean_failure("--model phong --f0 0.04", out,
                       "--model: must be one of schlick, schlick-metallic, schlick-ior, dielectric, conductor, "
                       "f82-tint, empirical (got 'phong')");
  expect_clean_failure("--model schlick", out, "model 'schlick' needs f0");
  expect_clean_failure("--model conductor --n 1,1,1", out, "needs n and k");
  expect_clean_failure("--model schlick-metallic --base-color 0.9,0.6,0.3", out, "needs base-color and metallic");
  expect_clean_failure("--model empirical --bias 0.1 --scale 0.9", out, "needs bias, scale and power");
  expect_clean_failure("--model schlick --f0 0.04 --k 1", out, "k does not apply to model 'schlick'");
  expect_clean_failure("--model conductor --material gold --n 0.2", out, "either a material or");
  expect_clean_failure("--model dielectric --material gold", out, "'gold' is a conductor");
  expect_clean_failure("--model empirical --material gold", out, "takes bias, scale and power, not a material");
  expect_clean_failure("--model schlick --f0 0.04 --vs exact", out, "names no exact model");
  expect_clean_failure("--model schlick --material gold --vs approx", out, "--vs takes 'exact'");
  expect_clean_failure("--model conductor --material gold --table 2d", out, "give no material");
  expect_clean_failure("--model conductor --n 1 --k 1 --table 2d", out, "has neither");
  expect_clean_failure("--model schlick --table 2d --range 0.5,0.2", out,
                       "--range: must be two numbers lo,hi with lo <= hi (got [0.5, 0.2])");
  expect_clean_failure("--model schlick --table 2d --range 0,2", out, "[0, 1]");
  expect_clean_failure("--model schlick --table 2d --range 1", out, "--range: must be two numbers lo,hi");
  expect_clean_failure("--model schlick --f0 0.04 --range 0,1", out, "range is for 2-D tables");
  expect_clean_failure("--model schlick --f0 0.04 --table 3d", out, "--table: must be one of 1d, 2d (got '3d')");
  expect_clean_failure("--model schlick --f0 0.04 --size 0", out, "--size: must be an integer in 1..16777216 (got 0)");
  expect_clean_failure("--model schlick --f0 0.04 --size 1 --endpoints", out, "at least 2");
  expect_clean_failure("--model schlick --f0 0.04 --size 1x", out, "--size: must be an integer");
  expect_clean_failure("--model schlick --f0 0.04 --precision fp16", out, "unknown precision 'fp16'");
  expect_clean_failure("--model schlick --f0 0.04 --device no-such-device", out, "no-such-device");
  expect_clean_failure("--model schlick --f0 0.04 --rate-cells 5", out, "--rate-cells is for --compare");
  expect_clean_failure("--list-materials", out, "--output does not apply to --list-materials");
  expect_clean_failure("--compare --material gold", out, "--output does not apply to --compare");
  expect_clean_failure("--compare --fit --material gold", out, "give one of");
  const fs::path exr = dir / "t.exr";
  expect_clean_failure("--model schlick --material gold --vs exact", exr, "write .csv or .h");
  // Without -o the table goes to the name a job would give it, in the current folder.
  const CliRun no_output =
      brdfbake::test::run_cli("fresnel --model schlick --f0 0.04 --size 4 --quiet", {}, "cd " + dir.string() + " &&");
  EXPECT_EQ(no_output.code, 0) << no_output.err;
  EXPECT_TRUE(fs::exists(dir / "fresnel_schlick_f0_0.04.exr"));
  const CliRun no_format = run("fresnel --model schlick --f0 0.04 -o -");
  EXPECT_EQ(no_format.code, 2);
  EXPECT_NE(no_format.err.find("needs --format csv"), std::string::npos) << no_format.err;
  const CliRun no_material = run("fresnel --compare");
  EXPECT_EQ(no_material.code, 2);
  EXPECT_NE(no_material.err.find("--compare needs --material"), std::string::npos) << no_material.err;
  const CliRun unknown = run("fresnel --compare --material unobtainium");
  EXPECT_EQ(unknown.code, 2);
  EXPECT_EQ(count_lines(unknown.err), 1) << unknown.err;
  fs::remove_all(dir.parent_path());
}

}  // namespace

// Issue 24, item 8: a thin film over a bright base stores the model's reflectance above 1 (the
// KHR_materials_iridescence evaluation clamps only below 0), and says so: a warning line, and the
// file's metadata, naming how many cells, the largest value and where. A dielectric base stays
// below 1 and gets neither.
TEST(CliThinFilm, ReflectanceAboveOneIsSaid) {
  const CliRun bright = run("thin-film --base-f0 0.95,0.64,0.54 --size 32 --format csv -o -");
  ASSERT_EQ(bright.code, 0) << bright.err;
  EXPECT_NE(bright.err.find("warning: thin-film: reflectance above 1 in "), std::string::npos) << bright.err;
  const Csv c = parse_csv(bright.out);
  double worst = 0.0;
  for (const auto& row : c.rows)
    for (size_t k = 2; k < row.size(); ++k) worst = std::max(worst, row[k]);
  EXPECT_GT(worst, 1.05);  // measured 1.0756 (r at cos_theta 0.0156)
  EXPECT_TRUE(has_meta(c, "# reflectance_above_1: reflectance above 1 in ")) << bright.out.substr(0, 2000);
  const CliRun glass = run("thin-film --base-f0 0.04 --size 32 --format csv -o -");
  ASSERT_EQ(glass.code, 0) << glass.err;
  EXPECT_EQ(glass.err.find("reflectance above 1"), std::string::npos) << glass.err;
  EXPECT_FALSE(has_meta(parse_csv(glass.out), "# reflectance_above_1"));
}

// Issue 24, numbers at the edge: parameters beyond the float range are the model's, not infinities
// that meet 0 (inf * 0 = NaN, stored as 0): R = clamp(bias + scale (1 - cos)^power, 0, 1) is 1
// everywhere for 1e308s (the double model: 1e308 + 1e308 w >= 1e308), and 0 for a bias of -1e308
// under a scale of 1e308 with power 1 (-1e308 cos_theta <= 0, 0 at grazing).
TEST(CliFresnel, EmpiricalParametersBeyondTheFloatRange) {
  const CliRun big =
      run("fresnel --model empirical --bias 1e308 --scale 1e308 --power 1e308 --size 16 --format csv -o -");
  ASSERT_EQ(big.code, 0) << big.err;
  const Csv a = parse_csv(big.out);
  ASSERT_EQ(a.rows.size(), 16u);
  for (const auto& row : a.rows) EXPECT_EQ(row.back(), 1.0) << "cos_theta " << row.front();
  const CliRun neg = run("fresnel --model empirical --bias -1e308 --scale 1e308 --power 1 --size 16 --format csv -o -");
  ASSERT_EQ(neg.code, 0) << neg.err;
  for (const auto& row : parse_csv(neg.out).rows) EXPECT_EQ(row.back(), 0.0) << "cos_theta " << row.front();
  // and the bound the file records is the distance from the double model: 0 here, not 1
  EXPECT_NE(big.err.find("stored values: error_bound_mixed 0 "), std::string::npos) << big.err;
}
