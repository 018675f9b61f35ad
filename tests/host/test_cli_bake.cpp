// `brdfbake bake` and `brdfbake run`, run as a user runs them: the plan, what is written, exit
// codes, one-line errors, nothing half written.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

#include "brdfbake/engines.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/job.hpp"
#include "brdfbake/table.hpp"
#include "families/preview/bake_preview.hpp"
#include "io/ktx2.hpp"
#include "io/table_read.hpp"
#include "support/cli_runner.hpp"
#include "support/temp_dir.hpp"
#include "support/tolerances.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

using brdfbake::test::CliRun;
CliRun run(const std::string& args, const std::string& env = "") { return brdfbake::test::run_cli(args, {}, env); }

// The test's temporary folder (removed when the test ends).
fs::path temp_dir() { return brdfbake::test::test_temp_root(); }

fs::path write_file(const std::string& name, const std::string& bytes) {
  const fs::path p = temp_dir() / name;
  std::ofstream(p, std::ios::binary) << bytes;
  return p;
}

int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

// Small sizes: the point is the plumbing, not the tables.
const std::string kSizes = " --lut-size 8 --cube-size 16 --min-size 8 --fresnel-size 16 --prefilter-max-error 0";
const std::string kSmall = kSizes + " --quiet";

const char* kSheenScene = R"({"asset":{"version":"2.0"},
  "materials":[{"name":"Velvet","pbrMetallicRoughness":{"metallicFactor":0},
                "extensions":{"KHR_materials_sheen":{"sheenColorFactor":[1,0.2,0.2],"sheenRoughnessFactor":0.5}}},
               {"name":"Chrome","pbrMetallicRoughness":{"metallicFactor":1,"roughnessFactor":0.1}}],
  "meshes":[{"primitives":[{"attributes":{},"material":0},{"attributes":{},"material":1}]}],
  "buffers":[{"uri":"missing.bin","byteLength":4}]})";

void expect_clean_failure(const CliRun& r, int code, const std::string& needle, const fs::path& out) {
  EXPECT_EQ(r.code, code) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out)) << out;
  for (const auto& e : fs::directory_iterator(out.parent_path()))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << "left behind: " << e.path();
}

TEST(CliBake, DryRunJsonIsThePlan) {
  const fs::path scene = write_file("sheen.gltf", kSheenScene);
  const CliRun r = run("bake --scene " + scene.string() + " --dry-run --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("warning:"), std::string::npos) << "the missing .bin is a warning";
  const json plan = json::parse(r.out);
  std::map<std::string, json> by_kind;
  for (const auto& t : plan["tables"]) by_kind[t["kind"].get<std::string>() + "/" + t.value("distribution", "")] = t;
  ASSERT_TRUE(by_kind.count("ggx-multiscatter/"));
  ASSERT_TRUE(by_kind.count("charlie/"));
  ASSERT_TRUE(by_kind.count("prefilter/ggx"));
  ASSERT_TRUE(by_kind.count("prefilter/charlie"));
  ASSERT_TRUE(by_kind.count("irradiance/"));
  EXPECT_EQ(plan["tables"].size(), 5u);
  const json& charlie = by_kind["charlie/"];
  EXPECT_EQ(charlie["requested_by"][0]["rule"], "KHR_materials_sheen");
  EXPECT_EQ(charlie["materials"], json::array({"#0 Velvet"}));
  EXPECT_EQ(by_kind["irradiance/"]["materials"], json::array({"#0 Velvet"})) << "Chrome is fully metallic";
  EXPECT_EQ(by_kind["ggx-multiscatter/"]["materials"], json::array({"#0 Velvet", "#1 Chrome"}));
  EXPECT_EQ(plan["plan"]["rules_fired"], json::array({"metallic-roughness", "KHR_materials_sheen"}));
  // Without energy compensation the ggx table replaces ggx-multiscatter.
  const CliRun off = run("bake --scene " + scene.string() + " --dry-run --json --no-energy-compensation");
  ASSERT_EQ(off.code, 0);
  EXPECT_NE(off.out.find("\"kind\": \"ggx\""), std::string::npos);
  EXPECT_EQ(off.out.find("ggx-multiscatter"), std::string::npos);
  // The text plan names the rules and materials.
  const CliRun text = run("bake --scene " + scene.string() + " --dry-run");
  ASSERT_EQ(text.code, 0);
  EXPECT_NE(text.out.find("KHR_materials_sheen: sheen DFG"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("[#0 Velvet]"), std::string::npos) << text.out;
}

TEST(CliBake, DefaultBakesTheStandardSetAndPrintsASummary) {
  const fs::path out = temp_dir() / "default";
  fs::remove_all(out);
  const CliRun r = run("bake -o " + out.string() + kSizes + " --contact-sheet");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* f : {"dfg_ggx_multiscatter_8.exr", "prefilter_ggx_16.ktx2", "irradiance_sh3.json", "manifest.json",
                        "contact_sheet.png"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  // ... and each holds what the one-table command writes for the parameters the manifest records
  const fs::path one = temp_dir() / "default-one";
  fs::create_directories(one);
  ASSERT_EQ(run("lut --kind ggx-multiscatter --size 8 --quiet -o " + (one / "dfg.exr").string()).code, 0);
  ASSERT_EQ(run("prefilter --env builtin:studio --size 16 --min-size 8 --quiet -o " + (one / "p.ktx2").string()).code,
            0);
  ASSERT_EQ(run("irradiance --env builtin:studio --quiet -o " + (one / "sh.json").string()).code, 0);
  const brdfbake::Table dfg = brdfbake::io::read_table((out / "dfg_ggx_multiscatter_8.exr").string());
  EXPECT_EQ(dfg.meta("kind"), "ggx-multiscatter");
  EXPECT_EQ(dfg.width, 8);
  EXPECT_EQ(dfg.data, brdfbake::io::read_table((one / "dfg.exr").string()).data);
  const brdfbake::io::Ktx2Image chain = brdfbake::io::read_ktx2((out / "prefilter_ggx_16.ktx2").string());
  EXPECT_EQ(chain.faces, 6u);
  EXPECT_EQ(chain.levels, 2u);
  EXPECT_EQ(chain.level_data, brdfbake::io::read_ktx2((one / "p.ktx2").string()).level_data);
  const json sh = json::parse(std::ifstream(out / "irradiance_sh3.json")),
             sh_one = json::parse(std::ifstream(one / "sh.json"));
  EXPECT_EQ(sh["order"], 3);
  EXPECT_EQ(sh["irradiance_over_pi"], sh_one["irradiance_over_pi"]);
  EXPECT_EQ(sh["radiance"], sh_one["radiance"]);
  EXPECT_NE(r.out.find("wrote " + out.string() + ": 3 files from 3 bakes"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("manifest.json"), std::string::npos);
  // The DFG kind's runtime formula: ggx-multiscatter needs a different shader from ggx.
  EXPECT_NE(r.out.find("runtime: specular = mix(bias, albedo, F0) * (1 + F0 * (1 / albedo - 1))"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("contact sheet: " + out.string() + "/contact_sheet.png"), std::string::npos) << r.out;
  EXPECT_NE(run("bake --dry-run --contact-sheet").err.find("not with --dry-run"), std::string::npos);
  EXPECT_NE(run("bake --dry-run --preview").err.find("not with --dry-run"), std::string::npos);
  std::ifstream m(out / "manifest.json");
  const json manifest = json::parse(m);
  ASSERT_EQ(manifest["files"].size(), 3u);
  EXPECT_EQ(manifest["files"][0]["kind"], "ggx-multiscatter");
  fs::remove_all(out);
}

TEST(CliBake, SceneBakeAndRunOfItsPlanWriteTheSameFiles) {
  const fs::path scene = write_file("sheen2.gltf", kSheenScene);
  const fs::path a = temp_dir() / "bake_a";
  const fs::path b = temp_dir() / "bake_b";
  fs::remove_all(a);
  fs::remove_all(b);
  const CliRun baked = run("bake --scene " + scene.string() + " -o " + a.string() + kSmall);
  ASSERT_EQ(baked.code, 0) << baked.err;
  const CliRun plan = run("bake --scene " + scene.string() + " --dry-run --json" + kSmall);
  ASSERT_EQ(plan.code, 0) << plan.err;
  const fs::path job = write_file("plan.json", plan.out);
  const CliRun ran = run("run " + job.string() + " -o " + b.string() + " --quiet");
  ASSERT_EQ(ran.code, 0) << ran.err;
  std::set<std::string> files_a, files_b;
  for (const auto& e : fs::directory_iterator(a)) files_a.insert(e.path().filename().string());
  for (const auto& e : fs::directory_iterator(b)) files_b.insert(e.path().filename().string());
  EXPECT_EQ(files_a, files_b);
  EXPECT_EQ(files_a.size(), 6u) << "5 tables and the manifest";
  std::ifstream m(a / "manifest.json");
  const json manifest = json::parse(m);
  for (const auto& f : manifest["files"]) {
    EXPECT_FALSE(f["requested_by"].empty()) << f["path"];
    if (f["kind"] == "charlie") {
      EXPECT_EQ(f["materials"], json::array({"#0 Velvet"}));
    }
  }
  fs::remove_all(a);
  fs::remove_all(b);
}

TEST(CliBake, BadInputIsOneLineNonZeroAndNothingWritten) {
  const fs::path dir = temp_dir() / "bad";
  fs::create_directories(dir);
  const fs::path out = dir / "out";
  const fs::path malformed = write_file("malformed.gltf", "{\"asset\":{\"version\":\"2.0\"},\"materials\":[}");
  expect_clean_failure(run("bake --scene " + malformed.string() + " -o " + out.string()), 2,
                       malformed.string() + ": malformed JSON", out);
  const fs::path truncated = write_file("truncated.glb", std::string("glTF\2\0\0\0\xff\0\0\0", 12) + "{}");
  expect_clean_failure(run("bake --scene " + truncated.string() + " -o " + out.string()), 2,
                       truncated.string() + ": truncated GLB", out);
  const fs::path required =
      write_file("required.gltf",
                 R"({"asset":{"version":"2.0"},"extensionsUsed":["EXT_magic"],"extensionsRequired":["EXT_magic"]})");
  expect_clean_failure(run("bake --scene " + required.string() + " -o " + out.string()), 2,
                       "extensionsRequired[0]: 'EXT_magic'", out);
  expect_clean_failure(run("bake --scene " + (dir / "none.gltf").string() + " -o " + out.string()), 2, "none.gltf",
                       out);
  const fs::path kind = write_file("kind.json", R"({"tables": [{"kind": "phong"}]})");
  expect_clean_failure(run("run " + kind.string() + " -o " + out.string()), 2,
                       kind.string() + ": tables[0].kind: unknown table kind 'phong'", out);
  const fs::path size = write_file("size.json", R"({"tables": [{"kind": "ggx"}, {"kind": "ggx", "size": -8}]})");
  expect_clean_failure(run("run " + size.string() + " -o " + out.string()), 2,
                       size.string() + ": tables[1].size: must be an integer", out);
  const fs::path env = write_file("env.json", R"({"environment": "/no/such.hdr", "tables": [{"kind": "irradiance"}]})");
  const CliRun e = run("run " + env.string() + " -o " + out.string());
  EXPECT_EQ(e.code, 2) << "a missing environment is bad input: " << e.err;
  EXPECT_FALSE(fs::exists(out));
  expect_clean_failure(run("bake --dry-run --json --lut-size 0"), 2, "--lut-size", out);
  expect_clean_failure(run("bake --json"), 2, "--dry-run", out);
}

TEST(CliBake, AKindNotAvailableIsNamedAndNothingIsWritten) {
  const fs::path scene =
      write_file("irid.gltf",
                 R"({"asset":{"version":"2.0"},"materials":[{"name":"Film","pbrMetallicRoughness":{"metallicFactor":0},
        "extensions":{"KHR_materials_iridescence":{"iridescenceFactor":1,"iridescenceIor":1.5}}}]})");
  const fs::path out = temp_dir() / "irid_out";
  fs::remove_all(out);
  // The plan lists the table either way.
  const CliRun plan = run("bake --scene " + scene.string() + " --dry-run");
  ASSERT_EQ(plan.code, 0);
  EXPECT_NE(plan.out.find("thin-film"), std::string::npos) << plan.out;
  const CliRun r =
      run("bake --scene " + scene.string() + " -o " + out.string() + kSmall, "BRDFBAKE_UNAVAILABLE_KINDS=thin-film");
  expect_clean_failure(r, 1, "not available in this build", out);
  EXPECT_NE(r.err.find("thin-film"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("KHR_materials_iridescence"), std::string::npos) << r.err;
}

TEST(CliBake, EveryRealSceneHasAPlan) {
  const fs::path scenes = fs::path(BRDFBAKE_SHARED_DIR) / "scenes";
  if (!fs::exists(scenes)) GTEST_SKIP() << scenes.string() << " is missing: the real scenes are not checked";
  int n = 0;
  for (const auto& e : fs::directory_iterator(scenes)) {
    if (e.path().extension() != ".gltf") continue;
    ++n;
    const CliRun r = run("bake --scene " + e.path().string() + " --dry-run --json");
    EXPECT_EQ(r.code, 0) << e.path() << ": " << r.err;
    EXPECT_TRUE(json::accept(r.out)) << e.path();
  }
  EXPECT_EQ(n, 18);
}

}  // namespace

namespace {

// `bake --target T` writes the engine's file set (brdfbake/engines.hpp) beside the tables, in the
// engine's conventions, and lists it in the manifest; a job that lacks what the set needs is refused
// with nothing written.
// irradiance --target: the engine's SH window unless given, and its coefficients beside ours. For
// glTF (EXT_lights_image_based), E_lm = s_k pi (E/pi)_lm with s_k the Condon-Shortley sign (-1 at
// m = +-1), from the JSON's own irradiance_over_pi.
TEST(CliBake, IrradianceTargetAddsTheEnginesCoefficients) {
  const fs::path dir = temp_dir() / "irr_target";
  fs::create_directories(dir);
  for (const std::string& target : {std::string("gltf"), std::string("filament")}) {
    const fs::path out = dir / (target + ".json");
    const CliRun r = run("irradiance --env builtin:studio --target " + target + " --quiet -o " + out.string());
    ASSERT_EQ(r.code, 0) << r.err;
    const json j = json::parse(std::ifstream(out));
    const brdfbake::EngineSettings e = brdfbake::engine_settings(brdfbake::engine_target_from_name(target));
    EXPECT_EQ(j["window"], brdfbake::sh_window_name(e.sh_window)) << target;
    ASSERT_EQ(j["engine"]["target"], target);
    ASSERT_EQ(j["engine"]["coefficients"].size(), 9u);
    if (target != "gltf") continue;
    for (size_t k = 0; k < 9; ++k) {
      const double sign = (k == 1 || k == 3 || k == 5 || k == 7) ? -1.0 : 1.0;
      for (size_t c = 0; c < 3; ++c) {
        const double want = sign * 3.14159265358979323846 * j["irradiance_over_pi"][k][c].get<double>();
        EXPECT_NEAR(j["engine"]["coefficients"][k][c].get<double>(), want,
                    brdfbake::test::kRoundingFewOps * (1.0 + std::fabs(want)))
            << k;
      }
    }
  }
  // an explicit window wins over the engine's
  const CliRun w = run("irradiance --env builtin:studio --target filament --sh-window lanczos --quiet -o " +
                       (dir / "w.json").string());
  ASSERT_EQ(w.code, 0) << w.err;
  EXPECT_EQ(json::parse(std::ifstream(dir / "w.json"))["window"], "lanczos");
  fs::remove_all(dir);
}

TEST(CliBake, EveryEngineTargetWritesItsFileSet) {
  const fs::path dir = temp_dir() / "targets";
  fs::create_directories(dir);
  for (const std::string& target : brdfbake::engine_target_names()) {
    if (target == "generic") continue;
    const fs::path out = dir / ("set_" + target);
    const std::string name = out.filename().string();
    const CliRun r =
        run("bake --target " + target + " --cube-size 16 --min-size 4 --lut-size 8 --quiet -o " + out.string());
    if (target == "filament" || target == "babylon") {
      // these engines fix their sizes (power-of-two chains down to their own smallest level)
      const CliRun own = run("bake --target " + target + " --quiet -o " + out.string());
      ASSERT_EQ(own.code, 0) << target << ": " << own.err;
    } else {
      ASSERT_EQ(r.code, 0) << target << ": " << r.err;
    }
    const brdfbake::EngineSettings e = brdfbake::engine_settings(brdfbake::engine_target_from_name(target));
    const json m = json::parse(std::ifstream(out / "manifest.json"));
    ASSERT_TRUE(m.contains("engine")) << target;
    EXPECT_EQ(m["engine"]["target"], target);
    for (std::string f : e.files) {
      // patterns (per-level images) and optional files (a Charlie chain) are checked through the manifest
      if (f.find('<') != std::string::npos || f.find('(') != std::string::npos) continue;
      const auto at = f.find("NAME");
      if (at != std::string::npos) f.replace(at, 4, name);
      EXPECT_TRUE(fs::exists(out / f)) << target << ": " << f;
    }
    for (const auto& f : m["engine"]["files"])
      EXPECT_TRUE(fs::exists(out / f.get<std::string>())) << target << ": " << f.get<std::string>();
    // every file has its entry: its size, and a delivered error where it holds texels (issue 35)
    ASSERT_EQ(m["engine"]["file_entries"].size(), m["engine"]["files"].size()) << target;
    for (size_t k = 0; k < m["engine"]["files"].size(); ++k) {
      const json& entry = m["engine"]["file_entries"][k];
      const std::string path = m["engine"]["files"][k].get<std::string>();
      EXPECT_EQ(entry["path"], path) << target;
      EXPECT_EQ(entry["bytes"].get<std::uint64_t>(), fs::file_size(out / path)) << target << ": " << path;
      const std::string ext = fs::path(path).extension().string();
      if (ext == ".ktx" || ext == ".ktx2" || ext == ".env" || ext == ".png") {
        ASSERT_TRUE(entry["error_rms_rel"].is_number()) << target << ": " << entry.dump();
        EXPECT_GT(entry["error_rms_rel"].get<double>(), 0.0) << target << ": " << path << ": every encoding is lossy";
        EXPECT_LT(entry["error_rms_rel"].get<double>(), 0.05) << target << ": " << path;
        EXPECT_GE(entry["error_max_rel"].get<double>(), entry["error_rms_rel"].get<double>() * 0.5) << path;
      } else {
        EXPECT_TRUE(entry["error_rms_rel"].is_null()) << target << ": " << path;
      }
    }
    // the chain the set was made from has the engine's schedule
    for (const auto& f : m["files"]) {
      if (f["kind"] == "prefilter") {
        EXPECT_EQ(f["parameters"]["schedule"], std::string(brdfbake::roughness_schedule_name(e.schedule))) << target;
      }
    }
  }
  // a job with a target but no irradiance table: refused, nothing written
  std::ofstream(dir / "job.json")
      << R"({"target": "filament", "tables": [{"kind": "prefilter", "size": 16, "min_size": 4}]})";
  const CliRun bad = run("run " + (dir / "job.json").string() + " --quiet -o " + (dir / "bad").string());
  EXPECT_EQ(bad.code, 2) << bad.err;
  EXPECT_NE(bad.err.find("needs a GGX prefiltered chain and an irradiance table"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "bad"));
  fs::remove_all(dir);
}

// A scene of metals asks for no irradiance, yet every engine target's file set holds the diffuse
// light (Filament's SH key, the .env's polynomial, the glTF light's irradianceCoefficients, the
// viewer's Lambertian cube): the plan adds it for the set, and the bake writes the whole set (it
// was refused: "needs ... an irradiance table", stop 41).
TEST(CliBake, ASceneOfMetalsBakesEveryEngineTargetsWholeSet) {
  const fs::path dir = temp_dir() / "metals";
  fs::create_directories(dir);
  std::ofstream(dir / "metals.gltf") << R"({"asset": {"version": "2.0"}, "materials": [{"name": "gold", )"
                                        R"("pbrMetallicRoughness": {"baseColorFactor": [1, 0.8, 0.3, 1], )"
                                        R"("metallicFactor": 1, "roughnessFactor": 0.3}}]})";
  for (const std::string& target : brdfbake::engine_target_names()) {
    if (target == "generic") continue;
    const fs::path out = dir / ("set_" + target);
    const CliRun r = run("bake --scene " + (dir / "metals.gltf").string() + " --env builtin:sun --target " + target +
                         " --chain-size 32 --lut-size 16 --quiet -o " + out.string());
    ASSERT_EQ(r.code, 0) << target << ": " << r.err;
    const json m = json::parse(std::ifstream(out / "manifest.json"));
    bool irradiance = false;
    for (const auto& f : m["files"]) irradiance = irradiance || f["kind"] == "irradiance";
    EXPECT_TRUE(irradiance) << target << ": " << m["files"].dump();
    ASSERT_TRUE(m.contains("engine")) << target;
    EXPECT_FALSE(m["engine"]["files"].empty()) << target;
    for (const auto& f : m["engine"]["files"])
      EXPECT_TRUE(fs::exists(out / f.get<std::string>())) << target << ": " << f.get<std::string>();
  }
  // The generic target keeps the materials' plan (no irradiance), and its preview shades the metals
  // without one; the default grid's dielectrics need one: refused, naming a sphere, nothing written.
  const fs::path generic = dir / "generic";
  const CliRun baked = run("bake --scene " + (dir / "metals.gltf").string() +
                           " --env builtin:sun --chain-size 32 --lut-size 16 --quiet -o " + generic.string());
  ASSERT_EQ(baked.code, 0) << baked.err;
  EXPECT_FALSE(fs::exists(generic / "irradiance_sh3.json"));
  const CliRun shown = run("preview --bake " + generic.string() + " --scene " + (dir / "metals.gltf").string() +
                           " --env builtin:sun --width 64 --height 64 --quiet -o " + (dir / "p.png").string());
  ASSERT_EQ(shown.code, 0) << shown.err;
  const json p = json::parse(std::ifstream(dir / "p.json"));
  ASSERT_EQ(p["spheres"].size(), 1u);
  EXPECT_EQ(p["spheres"][0]["name"], "gold");
  EXPECT_TRUE(std::isfinite(p["spheres"][0]["error"]["linear"]["rms"].get<double>()));
  EXPECT_EQ(p["bake"]["diffuse"].get<std::string>().rfind("none", 0), 0u) << p["bake"].dump();
  const CliRun grid = run("preview --bake " + generic.string() + " --env builtin:sun --width 192 --height 96 -o " +
                          (dir / "q.png").string());
  EXPECT_EQ(grid.code, 2) << grid.err;
  EXPECT_NE(grid.err.find("holds no irradiance table"), std::string::npos) << grid.err;
  EXPECT_FALSE(fs::exists(dir / "q.png"));
  // bake --preview: a scene's bake without irradiance may have one; no scene, no irradiance: refused
  brdfbake::Job job;
  job.scene = (dir / "metals.gltf").string();
  brdfbake::TableRequest chain;
  chain.kind = brdfbake::TableKind::Prefilter;
  chain.params.push_back({"distribution", std::string("ggx")});
  job.tables.push_back(chain);
  EXPECT_NO_THROW(brdfbake::detail::preview::check_bake_preview(job));
  job.scene.clear();
  EXPECT_THROW(brdfbake::detail::preview::check_bake_preview(job), brdfbake::Error);
  fs::remove_all(dir);
}

// Issue 24, item 3: a job with a Charlie chain baked for khronos-viewer writes NAME_charlie.ktx2
// beside NAME_ggx.ktx2 (docs/ENGINES.md), listed with the engine's files; without one, none.
TEST(CliBake, KhronosViewerWritesTheCharlieChainItIsGiven) {
  const fs::path dir = brdfbake::test::test_temp_dir("kv-charlie");
  const std::string tables = R"({"kind": "prefilter", "size": 16, "output": "ggx.ktx2"},
      {"kind": "irradiance", "cube_size": 8, "output": "irr.ktx2"})";
  std::ofstream(dir / "with.json")
      << R"({"environment": "builtin:sun", "target": "khronos-viewer", "tables": [)" << tables
      << R"(, {"kind": "prefilter", "distribution": "charlie", "size": 16, "output": "charlie.ktx2"}]})";
  std::ofstream(dir / "without.json") << R"({"environment": "builtin:sun", "target": "khronos-viewer", "tables": [)"
                                      << tables << "]}";
  const CliRun with = run("run " + (dir / "with.json").string() + " --quiet -o " + (dir / "kv").string());
  ASSERT_EQ(with.code, 0) << with.err;
  EXPECT_TRUE(fs::exists(dir / "kv" / "kv_charlie.ktx2"));
  EXPECT_NE(
      [&] {
        std::ifstream in(dir / "kv" / "manifest.json");
        return std::string(std::istreambuf_iterator<char>(in), {});
      }()
          .find("kv_charlie.ktx2"),
      std::string::npos);
  const CliRun without = run("run " + (dir / "without.json").string() + " --quiet -o " + (dir / "plain").string());
  ASSERT_EQ(without.code, 0) << without.err;
  EXPECT_TRUE(fs::exists(dir / "plain" / "plain_ggx.ktx2"));
  EXPECT_FALSE(fs::exists(dir / "plain" / "plain_charlie.ktx2"));
  fs::remove_all(dir);
}

}  // namespace
