// Issue 34, class 6: a bake folder is input. Every value the preview reads from one (the manifest's
// fields, the SH JSON, Filament's "sh" key, the DFG tables, the cubes) is typed, range- and
// finiteness-checked: a bad one is a one-line brdfbake::Error (the CLI's exit 2, Python's
// brdfbake.InputError) naming the file and the field, never an undefined read, a raw
// [json.exception...] or a render with NaN in it. One valid folder per reader kind (generic: JSON and
// KTX2 and EXR; filament: the KTX1 "sh" key), each shape applied to a fresh copy.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "brdfbake/engines.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/io.hpp"
#include "brdfbake/preview.hpp"
#include "families/preview/bake_files.hpp"
#include "families/preview/splitsum.hpp"
#include "support/temp_dir.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

const std::string kEnv = "builtin:studio";

CubeLevels chain(int size, int levels, const char* schedule) {
  CubeLevels c;
  c.size = size;
  for (int l = 0; l < levels; ++l) {
    const int s = std::max(size >> l, 1);
    c.levels.emplace_back(size_t(6 * s * s * 4), 0.5f + 0.25f * float(l));
  }
  c.set_meta("roughness_schedule", schedule);
  return c;
}

ShCoefficients sh(double scale) {
  ShCoefficients s;
  s.order = 3;
  s.radiance.assign(27, 0.1);
  s.irradiance_over_pi.assign(27, 0.0);
  for (int c = 0; c < 3; ++c) s.irradiance_over_pi[size_t(c)] = scale;
  return s;
}

json read_json(const fs::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}
void write_json(const fs::path& p, const json& j) { std::ofstream(p) << j.dump(2); }

Table dfg_table(float poison = 0.0f) {
  Table t;
  t.width = t.height = 8;
  t.channels = {"bias", "albedo"};
  t.data.assign(8 * 8 * 2, 0.0f);
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i) {
      t.at(i, j, 0) = 0.05f;
      t.at(i, j, 1) = 0.9f;
    }
  if (poison != 0.0f) t.at(3, 5, 0) = poison;
  return t;
}

// A generic bake: env_ggx.ktx2 (f32), env_sh.json, dfg.exr, manifest.json.
void make_generic(const fs::path& dir, const CubeLevels& c = chain(8, 4, "linear")) {
  EngineBake bake;
  bake.prefiltered = &c;
  const ShCoefficients s = sh(0.3);
  bake.sh = &s;
  EngineWriteOptions o;
  o.name = "env";
  o.override_pixel = true;
  o.pixel = PixelType::F32;
  write_engine_files(EngineTarget::Generic, bake, dir.string(), o);
  write_table(dfg_table(), (dir / "dfg.exr").string(), TableFormat::Exr);
  write_json(dir / "manifest.json",
             {{"files",
               {{{"path", "dfg.exr"}, {"kind", "ggx-multiscatter"}, {"parameters", {{"n_dot_v_axis", "uniform"}}}},
                {{"path", "env_ggx.ktx2"},
                 {"kind", "prefilter"},
                 {"parameters", {{"distribution", "ggx"}}},
                 {"environment", kEnv}},
                {{"path", "env_sh.json"}, {"kind", "irradiance"}}}}});
}

// A filament bake: env_ibl.ktx (with the "sh" key), env_skybox.ktx, sh.txt, manifest.json.
void make_filament(const fs::path& dir, double sh_scale = 0.3) {
  const CubeLevels c = chain(16, 1, "filament");
  EngineBake bake;
  bake.prefiltered = &c;
  const ShCoefficients s = sh(sh_scale);
  bake.sh = &s;
  EngineWriteOptions o;
  o.name = "env";
  write_engine_files(EngineTarget::Filament, bake, dir.string(), o);
  write_json(dir / "manifest.json",
             {{"engine", {{"target", "filament"}, {"files", {"env_ibl.ktx", "env_skybox.ktx", "sh.txt"}}}}});
}

struct Shape {
  const char* name;
  EngineTarget target;
  std::function<void(const fs::path&)> make;  // the folder, broken in one way
  std::vector<std::string> said;              // what the one-line message must hold
};

std::function<void(const fs::path&)> edit_manifest(std::function<void(json&)> edit) {
  return [edit](const fs::path& d) {
    make_generic(d);
    json m = read_json(d / "manifest.json");
    edit(m);
    write_json(d / "manifest.json", m);
  };
}

std::function<void(const fs::path&)> edit_sh(std::function<void(json&)> edit) {
  return [edit](const fs::path& d) {
    make_generic(d);
    json s = read_json(d / "env_sh.json");
    edit(s);
    write_json(d / "env_sh.json", s);
  };
}

const EngineTarget G = EngineTarget::Generic;

std::vector<Shape> shapes() {
  return {
      {"an entry without path",
       G,
       edit_manifest([](json& m) { m["files"][1].erase("path"); }),
       {"manifest.json': files[1].path: missing"}},
      {"files an object",
       G,
       edit_manifest([](json& m) { m["files"] = json::object(); }),
       {"files: expected an array, not an object"}},
      {"a kind of number",
       G,
       edit_manifest([](json& m) { m["files"][0]["kind"] = 7; }),
       {"files[0].kind: expected a string, not a number"}},
      {"a path of number",
       G,
       edit_manifest([](json& m) { m["files"][2]["path"] = 3.5; }),
       {"files[2].path: expected a string"}},
      {"a path out of the folder",
       G,
       edit_manifest([](json& m) { m["files"][0]["path"] = "../../etc/passwd"; }),
       {"files[0].path: expected the name of a file inside the bake folder"}},
      {"parameters an array",
       G,
       edit_manifest([](json& m) { m["files"][1]["parameters"] = json::array(); }),
       {"files[1].parameters: expected an object, not an array"}},
      {"a distribution of null",
       G,
       edit_manifest([](json& m) { m["files"][1]["parameters"]["distribution"] = nullptr; }),
       {"files[1].parameters.distribution: expected a string, not null"}},
      {"an n_dot_v_axis of bool",
       G,
       edit_manifest([](json& m) { m["files"][0]["parameters"]["n_dot_v_axis"] = true; }),
       {"files[0].parameters.n_dot_v_axis: expected a string, not a boolean"}},
      {"an environment of number",
       G,
       edit_manifest([](json& m) { m["files"][1]["environment"] = 1; }),
       {"files[1].environment: expected a string"}},
      {"engine a string",
       G,
       edit_manifest([](json& m) { m["engine"] = "filament"; }),
       {"manifest.json': engine: expected an object, not a string"}},
      {"engine.target an array",
       G,
       edit_manifest([](json& m) {
         m["engine"] = {{"target", json::array()}};
       }),
       {"engine.target: expected a string, not an array"}},
      {"the manifest an array",
       G,
       [](const fs::path& d) {
         make_generic(d);
         write_json(d / "manifest.json", json::array({1, 2}));
       },
       {"manifest.json': expected an object"}},
      {"an SH order of string",
       G,
       edit_sh([](json& s) { s["order"] = "3"; }),
       {"env_sh.json': order: expected a number"}},
      {"an SH order of 9", G, edit_sh([](json& s) { s["order"] = 9; }), {"env_sh.json': order: 9 is outside [3, 5]"}},
      {"an SH order of 3.5", G, edit_sh([](json& s) { s["order"] = 3.5; }), {"order: expected an integer"}},
      {"SH coefficients of 1e308",
       G,
       edit_sh([](json& s) { s["irradiance_over_pi"][4][1] = 1e308; }),
       {"env_sh.json': irradiance_over_pi[4][1]: 1e+308 is outside [-1e+20, 1e+20]"}},
      {"an SH coefficient of string",
       G,
       edit_sh([](json& s) { s["irradiance_over_pi"][2][0] = "x"; }),
       {"irradiance_over_pi[2][0]: expected a number, not a string"}},
      {"8 SH coefficients",
       G,
       edit_sh([](json& s) { s["irradiance_over_pi"].erase(8); }),
       {"irradiance_over_pi: expected 9 RGB coefficients (27 numbers), not 24 numbers"}},
      {"no irradiance_over_pi",
       G,
       edit_sh([](json& s) { s.erase("irradiance_over_pi"); }),
       {"env_sh.json': irradiance_over_pi: missing"}},
      {"a NaN in the DFG table",
       G,
       [](const fs::path& d) {
         make_generic(d);
         write_table(dfg_table(std::nanf("")), (d / "dfg.exr").string(), TableFormat::Exr);
       },
       {"dfg.exr': texel (3, 5) channel bias: nan"}},
      {"an infinity in the DFG table",
       G,
       [](const fs::path& d) {
         make_generic(d);
         write_table(dfg_table(INFINITY), (d / "dfg.exr").string(), TableFormat::Exr);
       },
       {"dfg.exr': texel (3, 5) channel bias: inf"}},
      {"a NaN texel in the chain",
       G,
       [](const fs::path& d) {
         CubeLevels c = chain(8, 4, "linear");
         c.levels[2][4 * 7 + 1] = std::nanf("");
         make_generic(d, c);
       },
       {"env_ggx.ktx2': level 2, face 1, texel 3: nan"}},
      {"a Filament sh of 1e39",
       EngineTarget::Filament,
       [](const fs::path& d) { make_filament(d, 1e39 / 0.28209479177387814); },
       {"env_ibl.ktx': the sh key: number 1 (1e+39) is outside [-1e+20, 1e+20]"}},
      {"Filament engine.files of numbers",
       EngineTarget::Filament,
       [](const fs::path& d) {
         make_filament(d);
         write_json(d / "manifest.json", {{"engine", {{"target", "filament"}, {"files", {1, 2}}}}});
       },
       {"engine.files[0]: expected a string, not a number"}},
  };
}

class BakeFolderChecks : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = brdfbake::test::test_temp_root(); }  // removed when the test ends
  fs::path dir_;
};

// The valid folders read and render finite values: what the shapes below break.
TEST_F(BakeFolderChecks, TheValidFoldersReadAndShadeFinite) {
  for (const EngineTarget target : {EngineTarget::Generic, EngineTarget::Filament}) {
    const fs::path d = dir_ / engine_target_name(target);
    if (target == EngineTarget::Generic)
      make_generic(d);
    else
      make_filament(d);
    const detail::preview::SplitSum split(
        detail::preview::read_bake_files(d.string(), target, target == EngineTarget::Generic ? kEnv : ""));
    PreviewMaterial m;
    m.roughness = 0.4;
    const Rgb c = split.shade({0.0, 0.0, 1.0}, {0.0, 0.6, 0.8}, m);
    EXPECT_TRUE(std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b)) << engine_target_name(target);
    EXPECT_GT(c.r, 0.0) << engine_target_name(target);
  }
}

TEST_F(BakeFolderChecks, EveryBadValueIsAOneLineInputErrorNamingTheField) {
  int i = 0;
  for (const Shape& s : shapes()) {
    const fs::path d = dir_ / ("shape" + std::to_string(i++));
    s.make(d);
    std::string message;
    bool input_error = false, rendered = false;
    try {
      const detail::preview::SplitSum split(
          detail::preview::read_bake_files(d.string(), s.target, s.target == EngineTarget::Generic ? kEnv : ""));
      rendered = true;  // a folder that reads must at least shade finite values
      const Rgb c = split.shade({0.0, 0.0, 1.0}, {0.0, 0.6, 0.8}, PreviewMaterial{});
      message = std::isfinite(c.r + c.g + c.b) ? "read without an error" : "read, and shaded NaN or Inf";
    } catch (const RuntimeFailure& e) {
      message = std::string("a RuntimeFailure (exit 1, not an input error): ") + e.what();
    } catch (const Error& e) {
      input_error = true;
      message = e.what();
    } catch (const std::exception& e) {
      message = std::string("not a brdfbake::Error: ") + e.what();
    }
    SCOPED_TRACE(s.name);
    EXPECT_FALSE(rendered) << message;
    EXPECT_TRUE(input_error) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_EQ(message.find("json.exception"), std::string::npos) << message;
    for (const std::string& said : s.said) EXPECT_NE(message.find(said), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace brdfbake
