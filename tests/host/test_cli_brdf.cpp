// Material files (our JSON, glTF documents) and the eval and tabulate commands, run as a user runs
// them: values against the reference, streaming through several chunks, exit codes, one-line errors
// naming the line or field, and no file left behind.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "brdfbake/brdf.hpp"
#include "brdfbake/error.hpp"
#include "support/cli_runner.hpp"
#include "support/temp_dir.hpp"
#include "support/tolerances.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;

using brdfbake::test::kCliFp32;

using test::CliRun;
CliRun run(const std::string& args) { return test::run_cli(args); }

// The test's temporary folder (removed when the test ends).
fs::path temp_dir() { return brdfbake::test::test_temp_root(); }

void write_text(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

using test::count_lines;

// ../shared/scenes beside the repository (BRDFBAKE_SHARED_DIR), or "" when absent.
std::string shared_scenes() {
  const fs::path d = fs::path(BRDFBAKE_SHARED_DIR) / "scenes";
  return fs::is_directory(d) ? d.string() : std::string();
}

const char* kMaterials = R"({"materials": [
  {"name": "plastic", "model": "disney", "baseColor": [0.8, 0.2, 0.1], "roughness": 0.35, "clearcoat": 0.5,
   "sheen": 0.3, "subsurface": 0.2},
  {"name": "gold", "model": "gltf", "baseColorFactor": [1.0, 0.78, 0.34, 1.0], "metallicFactor": 1.0, "roughness": 0.25},
  {"name": "cloth", "model": "gltf-correlated", "baseColor": [0.3, 0.3, 0.6], "roughness": 0.8,
   "sheenColor": [0.9, 0.8, 0.7], "sheenRoughness": 0.4}
]})";

fs::path materials_file() {
  const fs::path p = temp_dir() / "materials.json";
  write_text(p, kMaterials);
  return p;
}

// Random pairs as CSV (header first) and as the doubles they parse back to.
std::string pairs_csv(int n, unsigned seed, std::vector<double>& values) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::string s = "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n";
  char buf[64];
  values.clear();
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < 6; ++c) {
      double v = g(rng);
      if (c == 2 || c == 5) v = i % 4 == 3 ? v : std::fabs(v) + 1e-3;
      std::snprintf(buf, sizeof buf, "%.9g", v);
      values.push_back(std::strtod(buf, nullptr));
      s += buf;
      s += c == 5 ? "\n" : ",";
    }
  }
  return s;
}

std::vector<double> parse_rgb_csv(const std::string& text) {
  std::vector<double> out;
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "r,g,b");
  while (std::getline(in, line)) {
    std::istringstream l(line);
    std::string field;
    while (std::getline(l, field, ',')) out.push_back(std::strtod(field.c_str(), nullptr));
  }
  return out;
}

double error(double got, double want) { return std::fabs(got - want) / std::max(1.0, std::fabs(want)); }

// ---- Material files -----------------------------------------------------------------------------

TEST(BrdfMaterials, JsonNamesAliasesAndDefaults) {
  const auto mats = parse_materials_json(kMaterials, "m.json");
  ASSERT_EQ(mats.size(), 3u);
  EXPECT_EQ(mats[0].name, "plastic");
  EXPECT_EQ(*mats[0].model, BrdfModel::Disney);
  EXPECT_DOUBLE_EQ(mats[0].params.clearcoat, 0.5);
  EXPECT_DOUBLE_EQ(mats[0].params.specular, 0.5);       // Disney's default
  EXPECT_DOUBLE_EQ(mats[1].params.base_color.g, 0.78);  // baseColorFactor alias, alpha ignored
  EXPECT_DOUBLE_EQ(mats[1].params.metallic, 1.0);
  EXPECT_DOUBLE_EQ(mats[2].params.sheen_roughness, 0.4);
  // the metadata dump parses back to the same material
  const auto again = parse_materials_json("{\"materials\": [" + material_to_json(mats[2]) + "]}", "dump");
  EXPECT_EQ(material_to_json(again[0]), material_to_json(mats[2]));
}

TEST(BrdfMaterials, JsonErrorsNameTheField) {
  auto expect_error = [](const std::string& body, const std::string& needle) {
    try {
      parse_materials_json("{\"materials\": [" + body + "]}", "m.json");
      FAIL() << body;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << body << " -> " << e.what();
      EXPECT_NE(std::string(e.what()).find("m.json"), std::string::npos) << e.what();
    }
  };
  expect_error(R"({"name": "a", "roughness": 1.5})", "roughness must be in [0, 1] (got 1.5)");
  expect_error(R"({"name": "a", "rougness": 0.5})", "unknown parameter 'rougness'");
  expect_error(R"({"name": "a", "metallic": "high"})", "metallic must be a number");
  expect_error(R"({"name": "a", "baseColor": [1, 2]})", "baseColor must be an array of 3 numbers");
  expect_error(R"({"name": "a", "baseColor": [1, 0.5, -0.1]})", "baseColor must have every channel in [0, 1]");
  expect_error(R"({"name": "a", "model": "phongg"})", "unknown model 'phongg'");
  expect_error(R"({"name": "a", "ior": 0.5})", "ior must be 0 or a finite number >= 1");
  expect_error(R"({"name": "a", "shininess": -1})", "shininess must be in");
  expect_error(R"({"name": "a", "distribution": "phong"})", "distribution must be");
  expect_error(R"({"name": "a"}, {"name": "a"})", "the name is used twice");
  EXPECT_THROW(parse_materials_json("{\"materials\": 3}", "m.json"), Error);
  EXPECT_THROW(parse_materials_json("{\"materials\": [", "m.json"), Error);
  Material m;
  m.sheen_roughness = std::numeric_limits<double>::quiet_NaN();
  try {
    validate_material(m, "here");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("sheenRoughness"), std::string::npos) << e.what();
  }
}

TEST(BrdfMaterials, GltfDefaultsAndExtensions) {
  const char* doc = R"({"asset": {"version": "2.0"}, "materials": [
    {"name": "plain"},
    {"name": "full", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.4, 0.3, 1], "metallicFactor": 0.0,
       "roughnessFactor": 0.6, "baseColorTexture": {"index": 0}},
     "extensions": {"KHR_materials_sheen": {"sheenColorFactor": [1, 0.5, 0], "sheenRoughnessFactor": 0.3},
                    "KHR_materials_clearcoat": {"clearcoatFactor": 0.7, "clearcoatRoughnessFactor": 0.1},
                    "KHR_materials_specular": {"specularFactor": 0.5, "specularColorFactor": [1.5, 1, 1]},
                    "KHR_materials_ior": {"ior": 1.33},
                    "KHR_materials_transmission": {"transmissionFactor": 1}}}]})";
  const auto mats = parse_gltf_materials(doc, "doc.gltf");
  ASSERT_EQ(mats.size(), 2u);
  // glTF 2.0: baseColorFactor, metallicFactor and roughnessFactor default to 1
  EXPECT_DOUBLE_EQ(mats[0].params.base_color.r, 1.0);
  EXPECT_DOUBLE_EQ(mats[0].params.metallic, 1.0);
  EXPECT_DOUBLE_EQ(mats[0].params.roughness, 1.0);
  EXPECT_DOUBLE_EQ(mats[0].params.ior, 1.5);
  EXPECT_EQ(*mats[0].model, BrdfModel::Gltf);
  const Material& f = mats[1].params;
  EXPECT_DOUBLE_EQ(f.sheen_color.g, 0.5);
  EXPECT_DOUBLE_EQ(f.sheen_roughness, 0.3);
  EXPECT_DOUBLE_EQ(f.clearcoat, 0.7);
  EXPECT_DOUBLE_EQ(f.clearcoat_roughness, 0.1);
  EXPECT_DOUBLE_EQ(f.specular_factor, 0.5);
  EXPECT_DOUBLE_EQ(f.specular_color_factor.r, 1.5);
  EXPECT_DOUBLE_EQ(f.ior, 1.33);
  std::string notes;
  for (const auto& n : mats[1].notes) notes += n + ";";
  EXPECT_NE(notes.find("baseColorTexture"), std::string::npos) << notes;
  EXPECT_NE(notes.find("KHR_materials_transmission"), std::string::npos) << notes;
}

// The real sample scenes (JSON only, no .bin or images) all parse; the ones with sheen, clearcoat,
// specular and ior carry them.
TEST(BrdfMaterials, SharedSampleScenes) {
  const std::string dir = shared_scenes();
  if (dir.empty()) GTEST_SKIP() << "shared/scenes is absent";
  size_t files = 0, sheen = 0, coat = 0, spec = 0, ior = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".gltf") continue;
    ++files;
    const auto mats = read_materials(e.path().string());
    ASSERT_FALSE(mats.empty()) << e.path();
    for (const auto& m : mats) {
      sheen += m.params.sheen_color.r > 0 || m.params.sheen_color.g > 0 || m.params.sheen_color.b > 0;
      coat += m.params.clearcoat > 0;
      spec += m.params.specular_factor != 1.0 || m.params.specular_color_factor.r != 1.0;
      ior += m.params.ior != 1.5;
    }
  }
  EXPECT_GE(files, 10u);
  EXPECT_GT(sheen, 0u);
  EXPECT_GT(coat, 0u);
  EXPECT_GT(spec, 0u);
  EXPECT_GT(ior, 0u);
}

// ---- eval ---------------------------------------------------------------------------------------

TEST(CliEval, CsvMatchesTheReference) {
  const fs::path dir = temp_dir(), mats = materials_file();
  std::vector<double> pairs;
  write_text(dir / "pairs.csv", pairs_csv(500, 1u, pairs));
  for (const std::string name : {"plastic", "gold", "cloth"}) {
    const fs::path out = dir / ("f_" + name + ".csv");
    const CliRun r = run("eval --material " + mats.string() + " --name " + name + " -i " +
                         (dir / "pairs.csv").string() + " -o " + out.string() + " --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    const std::vector<double> got = parse_rgb_csv(read_text(out));
    ASSERT_EQ(got.size(), 3 * pairs.size() / 6);
    const auto all = parse_materials_json(kMaterials, "m");
    const NamedMaterial& m = find_material(all, name, "m");
    std::vector<double> want(got.size());
    eval_reference(*m.model, m.params, pairs.data(), pairs.size() / 6, want.data());
    for (size_t k = 0; k < got.size(); ++k) ASSERT_LE(error(got[k], want[k]), kCliFp32) << name << " value " << k;
  }
}

// The summary names the device and counts in words that agree with the number ("1 pair").
TEST(CliEval, SummaryNamesTheDeviceAndCountsPairs) {
  const fs::path dir = temp_dir(), mats = materials_file();
  std::vector<double> pairs;
  write_text(dir / "one.csv", pairs_csv(1, 7u, pairs));
  const CliRun r = run("eval --material " + mats.string() + " --name gold -i " + (dir / "one.csv").string() + " -o " +
                       (dir / "one_f.csv").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.rfind("1 pair, ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(" on "), std::string::npos) << "the device: " << r.err;
}

// More pairs than one chunk (1 << 16), through standard input and output, in order; the reference
// device gives the same rows.
TEST(CliEval, StreamsSeveralChunksThroughPipes) {
  const fs::path dir = temp_dir(), mats = materials_file();
  std::vector<double> pairs;
  write_text(dir / "many.csv", pairs_csv(70000, 2u, pairs));
  const CliRun r = run("eval --material " + mats.string() + " --name gold < " + (dir / "many.csv").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<double> got = parse_rgb_csv(r.out);
  ASSERT_EQ(got.size(), 3u * 70000u);
  const auto all = parse_materials_json(kMaterials, "m");
  std::vector<double> want(got.size());
  eval_reference(BrdfModel::Gltf, all[1].params, pairs.data(), 70000, want.data());
  for (size_t k = 0; k < got.size(); ++k) ASSERT_LE(error(got[k], want[k]), kCliFp32) << "value " << k;
  EXPECT_NE(r.err.find("70000 pairs"), std::string::npos) << r.err;
  // the scalar reference through the same command
  write_text(dir / "few.csv", pairs_csv(50, 3u, pairs));
  const CliRun ref = run("eval --material " + mats.string() + " --name gold --device reference --quiet -i " +
                         (dir / "few.csv").string());
  ASSERT_EQ(ref.code, 0) << ref.err;
  const std::vector<double> exact = parse_rgb_csv(ref.out);
  std::vector<double> want50(exact.size());
  eval_reference(BrdfModel::Gltf, all[1].params, pairs.data(), 50, want50.data());
  for (size_t k = 0; k < exact.size(); ++k) ASSERT_LE(error(exact[k], want50[k]), 1e-8) << k;
}

TEST(CliEval, BinaryMatchesCsv) {
  const fs::path dir = temp_dir(), mats = materials_file();
  std::vector<double> pairs;
  write_text(dir / "b.csv", pairs_csv(300, 4u, pairs));
  std::vector<float> f(pairs.begin(), pairs.end());
  {
    std::ofstream out(dir / "b.bin", std::ios::binary);
    out.write(reinterpret_cast<const char*>(f.data()), static_cast<std::streamsize>(f.size() * sizeof(float)));
  }
  const CliRun bin = run("eval --material " + mats.string() + " --name plastic --binary --quiet -i " +
                         (dir / "b.bin").string() + " -o " + (dir / "b.out").string());
  ASSERT_EQ(bin.code, 0) << bin.err;
  const std::string bytes = read_text(dir / "b.out");
  ASSERT_EQ(bytes.size(), 300u * 3u * sizeof(float));
  std::vector<float> got(300 * 3);
  std::memcpy(got.data(), bytes.data(), bytes.size());
  const auto all = parse_materials_json(kMaterials, "m");
  std::vector<double> fd(f.begin(), f.end()), want(got.size());
  eval_reference(BrdfModel::Disney, all[0].params, fd.data(), 300, want.data());
  for (size_t k = 0; k < got.size(); ++k) ASSERT_LE(error(got[k], want[k]), kCliFp32) << k;
}

// Each bad input: exit code 2, one line on stderr naming the problem (and the line or field), no file.
void expect_clean_failure(const std::string& args, const fs::path& out, const std::string& needle) {
  const CliRun r = run(args + " --quiet -o " + out.string());
  EXPECT_EQ(r.code, 2) << args << " -> " << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << args << " -> " << r.err;
  EXPECT_NE(r.err.find(needle), std::string::npos) << args << " -> " << r.err;
  EXPECT_FALSE(fs::exists(out)) << args;
  for (const auto& e : fs::directory_iterator(out.parent_path()))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << "left behind: " << e.path();
}

TEST(CliEval, BadInputGivesOneLineAndNoFile) {
  const fs::path dir = temp_dir() / "bad-eval";
  fs::create_directories(dir);
  const fs::path mats = materials_file(), out = dir / "f.csv";
  const std::string header = "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n";
  write_text(dir / "../field.csv", header + "0,0,1,0,0,1\n0.1,0.2,1,0,x7,1\n");
  write_text(dir / "../count.csv", header + "0,0,1,0,0,1\n\n0,0,1,0,1\n");
  write_text(dir / "../noheader.csv", "0,0,1,0,0,1\n");
  write_text(dir / "../zero.csv", header + "0,0,0,0,0,1\n");
  write_text(dir / "../inf.csv", header + "0,0,1,0,0,inf\n");
  write_text(dir / "../trunc.bin", std::string(30, '\0'));
  const std::string base = "eval --material " + mats.string() + " --name gold -i " + (dir / "..").string() + "/";
  expect_clean_failure(base + "field.csv", out, "line 3: field wo_y: 'x7' is not a number");
  expect_clean_failure(base + "count.csv", out, "line 4: expected 6 fields");
  expect_clean_failure(base + "noheader.csv", out, "line 1: expected the header wi_x,wi_y,wi_z,wo_x,wo_y,wo_z");
  expect_clean_failure(base + "zero.csv", out, "line 2: wi is the zero vector");
  expect_clean_failure(base + "inf.csv", out, "line 2: field wo_z is not finite");
  expect_clean_failure(base + "trunc.bin --binary", out, "not a whole number of pairs");
  expect_clean_failure(
      "eval --material " + mats.string() + " --name gold --model shiny -i " + (dir / "../zero.csv").string(), out,
      "--model: must be one of disney, gltf");
  expect_clean_failure("eval --material " + mats.string() + " -i " + (dir / "../zero.csv").string(), out,
                       "choose one with --name");
  expect_clean_failure("eval --material " + mats.string() + " --name silver -i " + (dir / "../zero.csv").string(), out,
                       "no material named 'silver'");
  write_text(dir / "../rough.json", R"({"materials": [{"name": "x", "model": "disney", "roughness": 2}]})");
  expect_clean_failure("eval --material " + (dir / "../rough.json").string() + " -i " + (dir / "../zero.csv").string(),
                       out, "roughness must be in [0, 1] (got 2)");
  write_text(dir / "../nomodel.json", R"({"materials": [{"name": "x"}]})");
  expect_clean_failure(
      "eval --material " + (dir / "../nomodel.json").string() + " -i " + (dir / "../zero.csv").string(), out,
      "names no model");
  expect_clean_failure("eval -i " + (dir / "../zero.csv").string(), out, "--material: missing");
}

// ---- tabulate -----------------------------------------------------------------------------------

TEST(CliTabulate, MerlFileWithSidecarMatchesTheReference) {
  const fs::path dir = temp_dir(), mats = materials_file(), out = dir / "gold.binary";
  const CliRun r =
      run("tabulate --material " + mats.string() + " --name gold --layout merl --quiet -o " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const MerlTable t = read_merl(out.string());
  ASSERT_TRUE(fs::exists(out.string() + ".json"));
  std::string meta;
  for (const auto& [k, v] : t.metadata) meta += k + "=" + v + "\n";
  for (const char* key :
       {"model=gltf", "layout=merl", "precision=fp32", "resolution=90x90x180", "conventions=", "generator="})
    EXPECT_NE(meta.find(key), std::string::npos) << key;
  const auto all = parse_materials_json(kMaterials, "m");
  const double pi = 3.14159265358979323846;
  for (int i : {5, 40, 80})
    for (int j : {3, 45})
      for (int k : {10, 90}) {
        const double u = (i + 0.5) / 90, th = u * u * pi / 2, td = (j + 0.5) / 90 * pi / 2, pd = (k + 0.5) / 180 * pi;
        const double st = std::sin(th), ct = std::cos(th), sd = std::sin(td), cd = std::cos(td), dx = sd * std::cos(pd);
        const Vec3 wi{dx * ct + cd * st, sd * std::sin(pd), cd * ct - dx * st};
        const Vec3 wo{2 * cd * st - wi.x, -wi.y, 2 * cd * ct - wi.z};
        const Rgb got = merl_lookup(t, wi, wo);
        if (wi.z <= 0 || wo.z <= 0) {
          EXPECT_EQ(got.r, kMerlBelowHorizon);
          continue;
        }
        double pair[6] = {wi.x, wi.y, wi.z, wo.x, wo.y, wo.z}, f[3];
        eval_reference(BrdfModel::Gltf, all[1].params, pair, 1, f);
        const Rgb want{f[0], f[1], f[2]};
        // the table's own fp32 bound (measured here: 2.2e-7)
        EXPECT_LE(error(got.r, want.r), test::kBrdfTableFp32) << i << " " << j << " " << k;
        EXPECT_LE(error(got.g, want.g), test::kBrdfTableFp32) << i << " " << j << " " << k;
        EXPECT_LE(error(got.b, want.b), test::kBrdfTableFp32) << i << " " << j << " " << k;
      }
}

TEST(CliTabulate, AlbedoGridAndSlice) {
  const fs::path dir = temp_dir(), mats = materials_file();
  // albedo of every material in the file, one row each
  const CliRun a =
      run("tabulate --material " + mats.string() + " --model gltf --layout albedo --res 12 --quiet -o - --format csv");
  ASSERT_EQ(a.code, 0) << a.err;
  int rows = 0;
  std::istringstream in(a.out);
  std::string line;
  while (std::getline(in, line))
    if (!line.empty() && line[0] != '#' && line.rfind("theta_o", 0) != 0) ++rows;
  EXPECT_EQ(rows, 3 * 12);
  EXPECT_NE(a.out.find("# material_names: plastic,gold,cloth"), std::string::npos);
  // a slice image
  const fs::path exr = dir / "slice.exr";
  const CliRun s = run("tabulate --material " + mats.string() +
                       " --name cloth --layout slice --res 40,30 --phi-d 1.2 --quiet -o " + exr.string());
  ASSERT_EQ(s.code, 0) << s.err;
  auto image = OIIO::ImageInput::open(exr.string());
  ASSERT_TRUE(image);
  EXPECT_EQ(image->spec().width, 40);
  EXPECT_EQ(image->spec().height, 30);
  image->close();
  // a grid as CSV
  const fs::path grid = dir / "grid.csv";
  const CliRun g = run("tabulate --material " + mats.string() +
                       " --name plastic --layout grid --res 4,5,3 --quiet -o " + grid.string());
  ASSERT_EQ(g.code, 0) << g.err;
  const std::string text = read_text(grid);
  EXPECT_NE(text.find("theta_o,theta_i,r,g,b"), std::string::npos);
  EXPECT_NE(text.find("# resolution: 4x5x3"), std::string::npos);
}

TEST(CliTabulate, GltfSceneMaterials) {
  const std::string dir = shared_scenes();
  if (dir.empty()) GTEST_SKIP() << "shared/scenes is absent";
  const fs::path scene = fs::path(dir) / "SheenChair.gltf";
  if (!fs::exists(scene)) GTEST_SKIP() << scene << " is absent";
  const CliRun r = run("tabulate --material " + scene.string() + " --layout albedo --res 8 --quiet -o - --format csv");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("# model: gltf"), std::string::npos);
}

TEST(CliTabulate, BadInputGivesOneLineAndNoFile) {
  const fs::path dir = temp_dir() / "bad-tab";
  fs::create_directories(dir);
  const fs::path mats = materials_file();
  const std::string base = "tabulate --material " + mats.string() + " --name gold ";
  expect_clean_failure(base + "--layout merl --res 10", dir / "t.binary", "its size is fixed");
  expect_clean_failure(base + "--layout cube", dir / "t.exr",
                       "--layout: must be one of merl, grid, albedo, slice (got 'cube')");
  expect_clean_failure(base + "--layout grid --res 4,4", dir / "t.exr", "takes 3 resolution values");
  expect_clean_failure(base + "--layout grid --res 0", dir / "t.exr", "--res: must be 1 to 3 integers");
  expect_clean_failure(base + "--layout albedo --phi-d 1", dir / "t.exr", "--phi-d: is for --layout slice");
  expect_clean_failure(base + "--layout slice --phi-d 4", dir / "t.exr", "--phi-d: must be a number in 0..3.14159265");
  expect_clean_failure(base + "--layout slice", dir / "t.tiff", ".tiff");
  expect_clean_failure("tabulate --material " + mats.string() + " --layout merl", dir / "t.binary", "--name");
  expect_clean_failure(base + "--precision fp16 --layout merl", dir / "t.binary", "unknown precision 'fp16'");
}

}  // namespace
}  // namespace brdfbake
