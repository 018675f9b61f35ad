// Scenes and the planner: glTF reading (.gltf, .glb, bad input), each rule on small files written
// here, zero factors, variants, missing buffers, deduplication, and every real scene of
// ../shared/scenes against the extension list of its SOURCES.md.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

#include "brdfbake/brdf.hpp"
#include "brdfbake/job.hpp"
#include "brdfbake/plan.hpp"
#include "brdfbake/preview.hpp"
#include "families/preview/model.hpp"
#include "io/png_image.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using namespace brdfbake;
using nlohmann::json;

// The test's temporary folder (removed when the test ends).
fs::path temp_dir() { return brdfbake::test::test_temp_root(); }

fs::path write_file(const std::string& name, const std::string& bytes) {
  const fs::path p = temp_dir() / name;
  std::ofstream(p, std::ios::binary) << bytes;
  return p;
}

// A glTF document with these materials, each used by one primitive of one mesh (unless `meshes`
// is given), and `extra` members appended to the root.
std::string gltf(const std::vector<std::string>& materials, const std::string& extra = "",
                 const std::string& meshes = "auto") {
  std::string m = "[";
  for (size_t i = 0; i < materials.size(); ++i) m += (i ? "," : "") + materials[i];
  m += "]";
  std::string mesh = meshes;
  if (meshes == "auto") {
    mesh = "[{\"primitives\":[";
    for (size_t i = 0; i < materials.size(); ++i)
      mesh += (i ? "," : "") + std::string("{\"attributes\":{},\"material\":") + std::to_string(i) + "}";
    mesh += "]}]";
  }
  return "{\"asset\":{\"version\":\"2.0\"},\"materials\":" + m + (mesh.empty() ? "" : ",\"meshes\":" + mesh) + extra +
         "}";
}

Plan plan_text(const std::string& text, PlanOptions o = {}) {
  return plan_scene(parse_scene_json(text, "test.gltf", ""), o);
}

bool fired(const Plan& p, const std::string& rule) {
  return std::find(p.rules_fired.begin(), p.rules_fired.end(), rule) != p.rules_fired.end();
}

std::vector<const TableRequest*> tables_of(const Plan& p, TableKind kind) {
  std::vector<const TableRequest*> out;
  for (const auto& t : p.job.tables)
    if (t.kind == kind) out.push_back(&t);
  return out;
}

const TableRequest* prefilter_of(const Plan& p, const std::string& distribution) {
  for (const auto* t : tables_of(p, TableKind::Prefilter))
    if (t->text("distribution") == distribution) return t;
  return nullptr;
}

const MaterialPlan& material(const Plan& p, const std::string& label_prefix) {
  for (const auto& m : p.materials)
    if (m.label.rfind(label_prefix, 0) == 0) return m;
  static MaterialPlan none;
  ADD_FAILURE() << "no material " << label_prefix;
  return none;
}

bool has_rule(const MaterialPlan& m, const std::string& rule) {
  return std::find(m.rules.begin(), m.rules.end(), rule) != m.rules.end();
}

bool requested_by(const TableRequest& t, const std::string& rule, const std::string& material_label) {
  for (const auto& r : t.requested_by)
    if (r.rule == rule && std::find(r.materials.begin(), r.materials.end(), material_label) != r.materials.end())
      return true;
  return false;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

// ---- reading --------------------------------------------------------------------------------------

TEST(Scene, ReadsFactorsWithTheSpecificationsDefaults) {
  const Scene s = parse_scene_json(
      gltf({R"({"name":"A"})",
            R"({"pbrMetallicRoughness":{"metallicFactor":0.25,"roughnessFactor":0.5,"baseColorFactor":[0.1,0.2,0.3,1]},
                "extensions":{"KHR_materials_sheen":{"sheenRoughnessFactor":0.4}}})"}),
      "t.gltf", "");
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.materials[0].label, "#0 A");
  EXPECT_EQ(s.materials[0].metallic, 1.0);
  EXPECT_EQ(s.materials[0].roughness, 1.0);
  EXPECT_EQ(s.materials[1].label, "#1");
  EXPECT_EQ(s.materials[1].metallic, 0.25);
  EXPECT_DOUBLE_EQ(s.materials[1].base_color[2], 0.3);
  EXPECT_TRUE(s.materials[1].sheen);
  EXPECT_EQ(s.materials[1].sheen_color[0], 0.0) << "sheenColorFactor defaults to black";
  EXPECT_DOUBLE_EQ(s.materials[1].sheen_roughness, 0.4);
  EXPECT_TRUE(s.materials[0].by_mesh);
}

TEST(Scene, JsonExtensionIsReadAsGltf) {
  const fs::path p =
      write_file("scene.json", gltf({R"({"extensions":{"KHR_materials_clearcoat":{"clearcoatFactor":1}}})"}));
  const Scene s = read_scene(p.string());
  EXPECT_EQ(s.container, "gltf");
  EXPECT_TRUE(fired(plan_scene(s), "KHR_materials_clearcoat"));
  const fs::path other = write_file("materials.json", R"({"materials": [{"name": "m", "model": "lambert"}]})");
  const std::string e = error_of([&] { read_scene(other.string()); });
  EXPECT_NE(e.find(other.string() + ": not a glTF 2.0 document"), std::string::npos) << e;
}

TEST(Scene, MalformedJsonNamesTheFile) {
  const fs::path p = write_file("broken.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"materials\": [");
  const std::string e = error_of([&] { read_scene(p.string()); });
  EXPECT_NE(e.find(p.string()), std::string::npos) << e;
  EXPECT_NE(e.find("malformed JSON"), std::string::npos) << e;
}

TEST(Scene, BadFieldsAreNamed) {
  EXPECT_NE(error_of([] { parse_scene_json("{\"materials\":[]}", "x.gltf", ""); }).find("x.gltf: not a glTF 2.0"),
            std::string::npos);
  EXPECT_NE(error_of([] { parse_scene_json("{\"asset\":{\"version\":\"1.0\"}}", "x.gltf", ""); }).find("asset.version"),
            std::string::npos);
  const std::string e =
      error_of([] { parse_scene_json(gltf({R"({"pbrMetallicRoughness":{"metallicFactor":"high"}})"}), "x.gltf", ""); });
  EXPECT_NE(e.find("x.gltf: materials[0].pbrMetallicRoughness.metallicFactor: must be a number"), std::string::npos)
      << e;
  const std::string r = error_of([] {
    parse_scene_json(gltf({R"({"extensions":{"KHR_materials_clearcoat":{"clearcoatFactor":1.5}}})"}), "x.gltf", "");
  });
  EXPECT_NE(r.find("materials[0].extensions.KHR_materials_clearcoat.clearcoatFactor: must be in [0, 1]"),
            std::string::npos)
      << r;
  const std::string i = error_of(
      [] { parse_scene_json(gltf({"{}"}, "", R"([{"primitives":[{"attributes":{},"material":3}]}])"), "x.gltf", ""); });
  EXPECT_NE(i.find("meshes[0].primitives[0].material: 3 is not a material index"), std::string::npos) << i;
}

TEST(Scene, UnknownRequiredExtensionIsAnError) {
  const std::string e = error_of([] {
    parse_scene_json(gltf({"{}"}, R"(,"extensionsUsed":["EXT_magic"],"extensionsRequired":["EXT_magic"])"), "x.gltf",
                     "");
  });
  EXPECT_NE(e.find("x.gltf: extensionsRequired[0]: 'EXT_magic'"), std::string::npos) << e;
  // Known required extensions are fine; unknown optional ones are warnings.
  const Scene ok = parse_scene_json(
      gltf({"{}"},
           R"(,"extensionsUsed":["KHR_texture_transform","EXT_magic"],"extensionsRequired":["KHR_texture_transform"])"),
      "x.gltf", "");
  ASSERT_EQ(ok.warnings.size(), 1u);
  EXPECT_NE(ok.warnings[0].find("EXT_magic"), std::string::npos);
}

TEST(Scene, MissingBuffersAndImagesAreWarningsAndStillPlan) {
  const fs::path p = write_file(
      "nobin.gltf", gltf({R"({"pbrMetallicRoughness":{"metallicFactor":0}})"},
                         R"(,"buffers":[{"uri":"nobin.bin","byteLength":12}],"images":[{"uri":"tex%20ture.png"}])"));
  write_file("tex ture.png", "png");  // present: percent-decoded
  const Scene s = read_scene(p.string());
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("'nobin.bin'"), std::string::npos) << s.warnings[0];
  const Plan plan = plan_scene(s);
  EXPECT_EQ(plan.job.tables.size(), 3u);
  EXPECT_EQ(plan.job.warnings, s.warnings);
}

// A .glb: header, JSON chunk (space padded), optional BIN chunk.
std::string glb(const std::string& json_text, uint32_t version = 2, bool bin = true) {
  std::string j = json_text;
  while (j.size() % 4) j += ' ';
  auto u32 = [](uint32_t v) {
    std::string s(4, '\0');
    for (int i = 0; i < 4; ++i) s[size_t(i)] = static_cast<char>((v >> (8 * i)) & 0xff);
    return s;
  };
  std::string chunks = u32(uint32_t(j.size())) + "JSON" + j;
  if (bin) chunks += u32(4) + std::string("BIN\0", 4) + std::string(4, '\0');
  return "glTF" + u32(version) + u32(uint32_t(12 + chunks.size())) + chunks;
}

TEST(Scene, ReadsGlb) {
  const fs::path p =
      write_file("ok.glb", glb(gltf({R"({"extensions":{"KHR_materials_sheen":{"sheenColorFactor":[1,1,1]}}})"})));
  const Scene s = read_scene(p.string());
  EXPECT_EQ(s.container, "glb");
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_TRUE(fired(plan_scene(s), "KHR_materials_sheen"));
}

// The material files of eval, tabulate and preview are read by the same reader: a .glb holds the
// same materials as its JSON, with the glTF defaults and its textures listed as notes.
TEST(Scene, MaterialFilesReadGltfAndGlbAlike) {
  const std::string doc =
      gltf({R"({"name":"cloth","pbrMetallicRoughness":{"roughnessFactor":0.25,"baseColorTexture":{"index":0}},
      "extensions":{"KHR_materials_sheen":{"sheenColorFactor":[1,0.5,0],"sheenRoughnessFactor":0.3}}})"});
  const fs::path json_file = write_file("m.gltf", doc), glb_file = write_file("m.glb", glb(doc));
  for (const fs::path& p : {json_file, glb_file}) {
    const std::vector<NamedMaterial> m = read_materials(p.string());
    ASSERT_EQ(m.size(), 1u) << p;
    EXPECT_EQ(m[0].name, "cloth");
    EXPECT_DOUBLE_EQ(m[0].params.roughness, 0.25);
    EXPECT_DOUBLE_EQ(m[0].params.metallic, 1.0);  // glTF 2.0's default
    EXPECT_DOUBLE_EQ(m[0].params.sheen_color.g, 0.5);
    EXPECT_DOUBLE_EQ(m[0].params.sheen_roughness, 0.3);
    ASSERT_FALSE(m[0].notes.empty());
    EXPECT_NE(m[0].notes[0].find("pbrMetallicRoughness.baseColorTexture"), std::string::npos) << m[0].notes[0];
  }
}

TEST(Scene, TruncatedOrCorruptGlbNamesTheFile) {
  const std::string good = glb(gltf({"{}"}));
  struct Case {
    std::string name, bytes, needle;
  };
  std::string wrong_length = good;
  wrong_length[8] = static_cast<char>(wrong_length[8] + 4);
  std::string long_chunk = good;
  long_chunk[13] = static_cast<char>(long_chunk[13] + 1);  // the JSON chunk claims 256 bytes more
  const std::vector<Case> cases = {
      {"short.glb", good.substr(0, 7), "truncated GLB"},
      {"cut.glb", good.substr(0, good.size() - 6), "truncated GLB"},
      {"cutjson.glb", good.substr(0, 30), "truncated GLB"},
      {"length.glb", wrong_length, "truncated GLB"},
      {"chunk.glb", long_chunk, "truncated GLB: the JSON chunk declares"},
      {"magic.glb", "gLTF" + good.substr(4), "not a binary glTF"},
      {"v1.glb", glb(gltf({"{}"}), 1), "version 1"},
  };
  for (const auto& c : cases) {
    const fs::path p = write_file(c.name, c.bytes);
    const std::string e = error_of([&] { read_scene(p.string()); });
    EXPECT_NE(e.find(p.string()), std::string::npos) << c.name << ": " << e;
    EXPECT_NE(e.find(c.needle), std::string::npos) << c.name << ": " << e;
  }
}

// ---- rules ----------------------------------------------------------------------------------------

TEST(Rules, CoreBakesTheGgxTablesAndIrradianceOnlyForNonMetals) {
  const Plan metal = plan_text(gltf({R"({"pbrMetallicRoughness":{"metallicFactor":1}})"}));
  EXPECT_TRUE(fired(metal, "metallic-roughness"));
  EXPECT_EQ(tables_of(metal, TableKind::GgxMultiscatter).size(), 1u);
  EXPECT_NE(prefilter_of(metal, "ggx"), nullptr);
  EXPECT_TRUE(tables_of(metal, TableKind::Irradiance).empty()) << "fully metallic: no diffuse";
  const Plan textured =
      plan_text(gltf({R"({"pbrMetallicRoughness":{"metallicFactor":1,"metallicRoughnessTexture":{"index":0}}})"}));
  EXPECT_EQ(tables_of(textured, TableKind::Irradiance).size(), 1u) << "a metallic texture may lower it";
  const Plan dielectric = plan_text(gltf({R"({"pbrMetallicRoughness":{"metallicFactor":0.5}})"}));
  EXPECT_EQ(tables_of(dielectric, TableKind::Irradiance).size(), 1u);
  EXPECT_EQ(dielectric.job.tables.size(), 3u);
}

// An engine target's file set holds the diffuse light beside the chain whatever the materials: a
// scene of metals (which asks for no irradiance) still gets it for every target, requested by the
// engine-file-set rule and no material; the generic target keeps the materials' plan; a scene that
// asks for irradiance itself is not given a second one.
TEST(Rules, EngineTargetsGetTheIrradianceTheirFileSetHolds) {
  const std::string metals = gltf({R"({"pbrMetallicRoughness":{"metallicFactor":1}})"});
  for (const char* target : {"filament", "babylon", "gltf", "khronos-viewer"}) {
    PlanOptions o;
    o.target = target;
    const Plan p = plan_text(metals, o);
    ASSERT_EQ(tables_of(p, TableKind::Irradiance).size(), 1u) << target;
    const TableRequest& irr = *tables_of(p, TableKind::Irradiance)[0];
    ASSERT_EQ(irr.requested_by.size(), 1u) << target;
    EXPECT_EQ(irr.requested_by[0].rule, "engine-file-set") << target;
    EXPECT_TRUE(irr.requested_by[0].materials.empty()) << target;
    EXPECT_TRUE(fired(p, "engine-file-set")) << target;
    EXPECT_NE(prefilter_of(p, "ggx"), nullptr) << target;
  }
  const Plan generic = plan_text(metals);
  EXPECT_TRUE(tables_of(generic, TableKind::Irradiance).empty()) << "generic: only what the materials ask";
  EXPECT_FALSE(fired(generic, "engine-file-set"));
  PlanOptions o;
  o.target = "filament";
  const Plan dielectric = plan_text(gltf({R"({"pbrMetallicRoughness":{"metallicFactor":0}})"}), o);
  ASSERT_EQ(tables_of(dielectric, TableKind::Irradiance).size(), 1u);
  EXPECT_EQ(tables_of(dielectric, TableKind::Irradiance)[0]->requested_by.at(0).rule, "metallic-roughness");
  EXPECT_FALSE(fired(dielectric, "engine-file-set"));
}

TEST(Rules, EnergyCompensationChoosesTheDfgForm) {
  const std::string g = gltf({"{}"});
  EXPECT_EQ(tables_of(plan_text(g), TableKind::Ggx).size(), 0u);
  PlanOptions o;
  o.energy_compensation = false;
  const Plan p = plan_text(g, o);
  EXPECT_EQ(tables_of(p, TableKind::Ggx).size(), 1u);
  EXPECT_EQ(tables_of(p, TableKind::GgxMultiscatter).size(), 0u);
}

TEST(Rules, DefaultPlanIsTheStandardSet) {
  const Plan p = plan_default();
  ASSERT_EQ(p.job.tables.size(), 3u);
  EXPECT_EQ(p.job.tables[0].kind, TableKind::GgxMultiscatter);
  EXPECT_EQ(p.job.tables[1].kind, TableKind::Prefilter);
  EXPECT_EQ(p.job.tables[1].text("distribution"), "ggx");
  EXPECT_EQ(p.job.tables[2].kind, TableKind::Irradiance);
  EXPECT_EQ(p.job.environment, "builtin:studio");
}

TEST(Rules, SheenBakesCharlieTablesUnlessItsColourIsZero) {
  const Plan p = plan_text(gltf(
      {R"({"name":"S","extensions":{"KHR_materials_sheen":{"sheenColorFactor":[1,0.5,0],"sheenRoughnessFactor":0.3}}})",
       R"({"name":"Z","extensions":{"KHR_materials_sheen":{"sheenColorFactor":[0,0,0],"sheenRoughnessFactor":0.3}}})"}));
  EXPECT_TRUE(fired(p, "KHR_materials_sheen"));
  const auto charlie = tables_of(p, TableKind::Charlie);
  ASSERT_EQ(charlie.size(), 1u) << "the sheen DFG and the albedo table are the same table (estevez-kulla): baked once";
  EXPECT_TRUE(requested_by(*charlie[0], "KHR_materials_sheen", "#0 S"));
  EXPECT_EQ(charlie[0]->requested_by.size(), 2u) << "two purposes: DFG and albedo scaling";
  EXPECT_FALSE(requested_by(*charlie[0], "KHR_materials_sheen", "#1 Z"));
  ASSERT_NE(prefilter_of(p, "charlie"), nullptr);
  EXPECT_NE(charlie[0]->requested_by[0].note.find("sheen roughness 0.3"), std::string::npos);
  EXPECT_FALSE(has_rule(material(p, "#1 Z"), "KHR_materials_sheen"));
  // Neubelt's visibility for the DFG table makes the albedo table a second one.
  PlanOptions o;
  o.sheen_visibility = "neubelt";
  EXPECT_EQ(tables_of(plan_text(gltf({R"({"extensions":{"KHR_materials_sheen":{"sheenColorFactor":[1,1,1]}}})"}), o),
                      TableKind::Charlie)
                .size(),
            2u);
  // Only zero factors: nothing of the sheen.
  const Plan zero = plan_text(gltf({R"({"extensions":{"KHR_materials_sheen":{"sheenRoughnessFactor":1}}})"}));
  EXPECT_FALSE(fired(zero, "KHR_materials_sheen"));
  EXPECT_TRUE(tables_of(zero, TableKind::Charlie).empty());
  EXPECT_EQ(prefilter_of(zero, "charlie"), nullptr);
}

TEST(Rules, ClearcoatUsesTheGgxTablesAndNotesItsRoughnessRange) {
  const Plan p = plan_text(gltf(
      {R"({"name":"C","extensions":{"KHR_materials_clearcoat":{"clearcoatFactor":1,"clearcoatRoughnessFactor":0.2}}})",
       R"({"name":"T","extensions":{"KHR_materials_clearcoat":{"clearcoatFactor":0.5,"clearcoatRoughnessFactor":0.6,"clearcoatRoughnessTexture":{"index":0}}}})",
       R"({"name":"Z","extensions":{"KHR_materials_clearcoat":{"clearcoatFactor":0,"clearcoatRoughnessFactor":0.9}}})"}));
  EXPECT_TRUE(fired(p, "KHR_materials_clearcoat"));
  const auto dfg = tables_of(p, TableKind::GgxMultiscatter);
  ASSERT_EQ(dfg.size(), 1u);
  EXPECT_TRUE(requested_by(*dfg[0], "KHR_materials_clearcoat", "#0 C"));
  EXPECT_FALSE(requested_by(*dfg[0], "KHR_materials_clearcoat", "#2 Z"));
  bool noted = false;
  for (const auto& r : dfg[0]->requested_by)
    if (r.rule == "KHR_materials_clearcoat") noted = r.note == "clearcoat roughness 0 to 0.6";
  EXPECT_TRUE(noted) << "the textured material spans 0 to its factor";
  EXPECT_EQ(p.job.tables.size(), 2u) << "no table of its own (metallic by default: no irradiance)";
}

TEST(Rules, IorSpecularAndDispersionBakeFresnelTablesForTheIorsInUse) {
  const Plan p = plan_text(gltf({
      R"({"name":"I","extensions":{"KHR_materials_ior":{"ior":1.33}}})",
      R"({"name":"I2","extensions":{"KHR_materials_ior":{"ior":1.3300000429153442}}})",
      R"({"name":"One","extensions":{"KHR_materials_ior":{"ior":1}}})",
      R"({"name":"S","extensions":{"KHR_materials_specular":{"specularColorFactor":[1,0.5,0.5]}}})",
      R"({"name":"S0","extensions":{"KHR_materials_specular":{"specularFactor":0}}})",
      R"({"name":"SC0","extensions":{"KHR_materials_specular":{"specularColorFactor":[0,0,0]}}})",
      R"({"name":"D","extensions":{"KHR_materials_ior":{"ior":1.5},"KHR_materials_dispersion":{"dispersion":1},
          "KHR_materials_transmission":{"transmissionFactor":1},"KHR_materials_volume":{"thicknessFactor":0.1}}})",
      R"({"name":"D0","extensions":{"KHR_materials_dispersion":{"dispersion":0},
          "KHR_materials_transmission":{"transmissionFactor":1},"KHR_materials_volume":{"thicknessFactor":0.1}}})",
  }));
  EXPECT_TRUE(fired(p, "KHR_materials_ior"));
  EXPECT_TRUE(fired(p, "KHR_materials_specular"));
  EXPECT_TRUE(fired(p, "KHR_materials_dispersion"));
  std::map<std::string, const TableRequest*> by_output;
  for (const auto* t : tables_of(p, TableKind::Fresnel)) by_output[t->output] = t;
  ASSERT_TRUE(by_output.count("fresnel_dielectric_ior1.33.exr"));
  const TableRequest& t133 = *by_output["fresnel_dielectric_ior1.33.exr"];
  EXPECT_TRUE(requested_by(t133, "KHR_materials_ior", "#0 I"));
  EXPECT_TRUE(requested_by(t133, "KHR_materials_ior", "#1 I2")) << "float32 1.33 is the same IOR";
  ASSERT_TRUE(by_output.count("fresnel_schlick_ior1.33_vs_exact.csv")) << "Schlick's error at that IOR";
  EXPECT_TRUE(by_output["fresnel_schlick_ior1.33_vs_exact.csv"]->flag("vs_exact"));
  ASSERT_TRUE(by_output.count("fresnel_dielectric_ior1.5.exr"));
  EXPECT_TRUE(requested_by(*by_output["fresnel_dielectric_ior1.5.exr"], "KHR_materials_specular", "#3 S"))
      << "specular without an IOR: the default 1.5";
  EXPECT_TRUE(requested_by(*by_output["fresnel_dielectric_ior1.5.exr"], "KHR_materials_transmission", "#7 D0"));
  // dispersion 1 at IOR 1.5: half spread (1.5 - 1) 0.025 = 0.0125 on either side of green
  ASSERT_TRUE(by_output.count("fresnel_dielectric_ior1.4875_1.5_1.5125.exr"));
  const TableRequest& disp = *by_output["fresnel_dielectric_ior1.4875_1.5_1.5125.exr"];
  EXPECT_TRUE(requested_by(disp, "KHR_materials_dispersion", "#6 D"));
  for (const char* m : {"#2 One", "#4 S0", "#5 SC0"}) {
    const MaterialPlan& mp = material(p, m);
    EXPECT_FALSE(has_rule(mp, "KHR_materials_ior")) << m;
    EXPECT_FALSE(has_rule(mp, "KHR_materials_specular")) << m;
    EXPECT_FALSE(mp.notes.empty()) << m << ": says why it does not fire";
  }
  EXPECT_FALSE(has_rule(material(p, "#7 D0"), "KHR_materials_dispersion"));
  for (const auto* t : tables_of(p, TableKind::Fresnel))
    for (const auto& r : t->requested_by)
      for (const auto& m : r.materials) EXPECT_TRUE(m != "#2 One" && m != "#4 S0" && m != "#5 SC0") << t->output;
}

TEST(Rules, TransmissionAndVolume) {
  const Plan p = plan_text(gltf({
      R"({"name":"Thin","pbrMetallicRoughness":{"metallicFactor":0},"extensions":{"KHR_materials_transmission":{"transmissionFactor":1}}})",
      R"({"name":"Vol","pbrMetallicRoughness":{"metallicFactor":0},"extensions":{"KHR_materials_ior":{"ior":2},"KHR_materials_transmission":{"transmissionFactor":0.5},"KHR_materials_volume":{"thicknessFactor":1}}})",
      R"({"name":"Off","pbrMetallicRoughness":{"metallicFactor":0},"extensions":{"KHR_materials_transmission":{"transmissionFactor":0},"KHR_materials_volume":{"thicknessFactor":1}}})",
  }));
  EXPECT_TRUE(fired(p, "KHR_materials_transmission"));
  EXPECT_TRUE(fired(p, "KHR_materials_volume"));
  const TableRequest* ggx = prefilter_of(p, "ggx");
  ASSERT_NE(ggx, nullptr);
  EXPECT_TRUE(requested_by(*ggx, "KHR_materials_transmission", "#0 Thin")) << "refracted radiance";
  bool entry = false, exit = false;
  for (const auto* t : tables_of(p, TableKind::Fresnel)) {
    if (t->output == "fresnel_dielectric_ior1.5.exr") entry = requested_by(*t, "KHR_materials_transmission", "#0 Thin");
    if (t->output == "fresnel_dielectric_ior1_from2.exr") exit = requested_by(*t, "KHR_materials_volume", "#1 Vol");
  }
  EXPECT_TRUE(entry);
  EXPECT_TRUE(exit);
  EXPECT_FALSE(has_rule(material(p, "#2 Off"), "KHR_materials_transmission"));
  EXPECT_FALSE(has_rule(material(p, "#2 Off"), "KHR_materials_volume"));
  EXPECT_FALSE(has_rule(material(p, "#0 Thin"), "KHR_materials_volume")) << "no volume: thin-walled";
  const auto irr = tables_of(p, TableKind::Irradiance);
  ASSERT_EQ(irr.size(), 1u);
  EXPECT_FALSE(requested_by(*irr[0], "metallic-roughness", "#0 Thin")) << "fully transmissive: no diffuse";
  EXPECT_TRUE(requested_by(*irr[0], "metallic-roughness", "#1 Vol"));
}

TEST(Rules, IridescenceBakesAThinFilmTablePerFilmIor) {
  const Plan p = plan_text(gltf({
      R"({"name":"A","pbrMetallicRoughness":{"metallicFactor":0},"extensions":{"KHR_materials_iridescence":{"iridescenceFactor":1,"iridescenceIor":1.8,"iridescenceThicknessMinimum":200,"iridescenceThicknessMaximum":600,"iridescenceThicknessTexture":{"index":0}}}})",
      R"({"name":"B","pbrMetallicRoughness":{"metallicFactor":0},"extensions":{"KHR_materials_iridescence":{"iridescenceFactor":1,"iridescenceIor":1.8,"iridescenceThicknessMaximum":700}}})",
      R"({"name":"M","pbrMetallicRoughness":{"metallicFactor":1,"baseColorFactor":[0.9,0.6,0.2,1]},"extensions":{"KHR_materials_iridescence":{"iridescenceFactor":1}}})",
      R"({"name":"Z","extensions":{"KHR_materials_iridescence":{"iridescenceFactor":0,"iridescenceIor":2}}})",
  }));
  EXPECT_TRUE(fired(p, "KHR_materials_iridescence"));
  const auto films = tables_of(p, TableKind::ThinFilm);
  ASSERT_EQ(films.size(), 2u);
  const TableRequest* dielectric = films[0]->find("base_ior") ? films[0] : films[1];
  const TableRequest* metal = films[0]->find("base_ior") ? films[1] : films[0];
  EXPECT_DOUBLE_EQ(dielectric->number("film_ior"), 1.8);
  EXPECT_DOUBLE_EQ(dielectric->number("base_ior"), 1.5);
  EXPECT_DOUBLE_EQ(dielectric->number("thickness_min"), 200) << "A's textured range and B's 700 nm";
  EXPECT_DOUBLE_EQ(dielectric->number("thickness_max"), 700);
  EXPECT_TRUE(requested_by(*dielectric, "KHR_materials_iridescence", "#0 A"));
  EXPECT_TRUE(requested_by(*dielectric, "KHR_materials_iridescence", "#1 B"));
  EXPECT_DOUBLE_EQ(metal->number("film_ior"), 1.3) << "the extension's default";
  ASSERT_NE(metal->find("base_f0"), nullptr);
  EXPECT_EQ(metal->number("height"), 1) << "one thickness (400 nm): one row";
  EXPECT_FALSE(has_rule(material(p, "#3 Z"), "KHR_materials_iridescence"));
}

TEST(Rules, AnisotropyUsesTheIsotropicTables) {
  const Plan p =
      plan_text(gltf({R"({"name":"A","extensions":{"KHR_materials_anisotropy":{"anisotropyStrength":0.5}}})",
                      R"({"name":"Z","extensions":{"KHR_materials_anisotropy":{"anisotropyStrength":0}}})"}));
  EXPECT_TRUE(fired(p, "KHR_materials_anisotropy"));
  EXPECT_EQ(p.job.tables.size(), 2u) << "DFG and GGX chain, nothing of its own (fully metallic: no irradiance)";
  EXPECT_TRUE(requested_by(*prefilter_of(p, "ggx"), "KHR_materials_anisotropy", "#0 A"));
  EXPECT_FALSE(has_rule(material(p, "#1 Z"), "KHR_materials_anisotropy"));
}

TEST(Rules, UnlitAndEmissiveOnlyNeedNothing) {
  const Plan p =
      plan_text(gltf({R"({"name":"U","extensions":{"KHR_materials_unlit":{}}})",
                      R"({"name":"E","emissiveFactor":[1,0.5,0],"pbrMetallicRoughness":{"baseColorFactor":[0,0,0,1]},
                                     "extensions":{"KHR_materials_emissive_strength":{"emissiveStrength":5}}})"},
                     R"(,"extensionsUsed":["KHR_materials_unlit"],"extensionsRequired":["KHR_materials_unlit"])"));
  EXPECT_TRUE(fired(p, "KHR_materials_unlit"));
  EXPECT_TRUE(fired(p, "emissive-only"));
  EXPECT_FALSE(fired(p, "metallic-roughness"));
  EXPECT_TRUE(p.job.tables.empty());
  // An emitter with a lit base colour is a metallic-roughness material.
  const Plan lit = plan_text(gltf({R"({"emissiveFactor":[1,1,1]})"}));
  EXPECT_TRUE(fired(lit, "metallic-roughness"));
  EXPECT_FALSE(fired(lit, "emissive-only"));
}

TEST(Rules, VariantOnlyMaterialsCountAndUnreferencedOnesDoNot) {
  const std::string meshes = R"([{"primitives":[{"attributes":{},"material":0,
      "extensions":{"KHR_materials_variants":{"mappings":[{"material":1,"variants":[0]}]}}}]}])";
  const Plan p = plan_text(gltf(
      {R"({"name":"Base"})", R"({"name":"Velvet","extensions":{"KHR_materials_sheen":{"sheenColorFactor":[1,0,0]}}})",
       R"({"name":"Orphan","extensions":{"KHR_materials_clearcoat":{"clearcoatFactor":1}}})"},
      R"(,"extensions":{"KHR_materials_variants":{"variants":[{"name":"red"}]}})", meshes));
  EXPECT_EQ(material(p, "#1 Velvet").reached_by, "variant");
  EXPECT_TRUE(material(p, "#1 Velvet").counted);
  EXPECT_TRUE(fired(p, "KHR_materials_sheen")) << "reachable only through a variant: counts";
  EXPECT_EQ(material(p, "#2 Orphan").reached_by, "unreferenced");
  EXPECT_FALSE(material(p, "#2 Orphan").counted);
  EXPECT_FALSE(fired(p, "KHR_materials_clearcoat"));
  // A file of materials without meshes is a library: every material counts.
  const Plan lib = plan_text(gltf({R"({"extensions":{"KHR_materials_clearcoat":{"clearcoatFactor":1}}})"}, "", ""));
  EXPECT_TRUE(fired(lib, "KHR_materials_clearcoat"));
  // A primitive without a material uses the default one (metallic 1: no irradiance).
  const Plan def = plan_text(gltf({}, "", R"([{"primitives":[{"attributes":{}}]}])"));
  EXPECT_EQ(material(def, "default material").reached_by, "default");
  EXPECT_EQ(def.job.tables.size(), 2u);
}

TEST(Rules, IdenticalTablesAreListedOnceWithEveryMaterial) {
  std::vector<std::string> mats;
  for (int i = 0; i < 5; ++i) mats.push_back(R"({"pbrMetallicRoughness":{"metallicFactor":0}})");
  const Plan p = plan_text(gltf(mats));
  ASSERT_EQ(p.job.tables.size(), 3u);
  for (const auto& t : p.job.tables) {
    ASSERT_EQ(t.requested_by.size(), 1u);
    EXPECT_EQ(t.requested_by[0].materials.size(), 5u);
    EXPECT_EQ(t.materials().size(), 5u);
  }
}

TEST(Rules, PlanJsonIsAJobThatReadsBack) {
  const Plan p = plan_text(gltf(
      {R"({"name":"S","extensions":{"KHR_materials_sheen":{"sheenColorFactor":[1,1,1]},"KHR_materials_ior":{"ior":1.4}}})"}));
  const std::string text = plan_to_json(p);
  const json j = json::parse(text);
  ASSERT_TRUE(j.contains("tables"));
  for (const auto& t : j["tables"]) {
    EXPECT_TRUE(t.contains("kind"));
    EXPECT_TRUE(t.contains("requested_by"));
    EXPECT_TRUE(t.contains("materials"));
    EXPECT_FALSE(t["requested_by"][0]["rule"].get<std::string>().empty());
  }
  EXPECT_TRUE(j["plan"]["energy_compensation"].get<bool>());
  const Job back = parse_job(text, "plan.json");
  ASSERT_EQ(back.tables.size(), p.job.tables.size());
  for (size_t i = 0; i < back.tables.size(); ++i) {
    EXPECT_EQ(back.tables[i].output, p.job.tables[i].output);
    EXPECT_EQ(back.tables[i].params.size(), p.job.tables[i].params.size());
    EXPECT_EQ(back.tables[i].requested_by.size(), p.job.tables[i].requested_by.size());
  }
  EXPECT_EQ(job_to_json(back), job_to_json(p.job));
}

// ---- the real scenes ------------------------------------------------------------------------------

fs::path scenes_dir() { return fs::path(BRDFBAKE_SHARED_DIR) / "scenes"; }

struct SourcesRow {
  int materials = 0;
  std::set<std::string> extensions;  // material-level, as rule names
};

// The "Extensions per file" table of SOURCES.md: file -> material count and material-level extensions.
std::map<std::string, SourcesRow> read_sources() {
  std::map<std::string, SourcesRow> rows;
  std::ifstream in(scenes_dir() / "SOURCES.md");
  std::string line;
  bool in_table = false;
  const std::map<std::string, std::string> names = {{"sheen", "KHR_materials_sheen"},
                                                    {"clearcoat", "KHR_materials_clearcoat"},
                                                    {"specular", "KHR_materials_specular"},
                                                    {"ior", "KHR_materials_ior"},
                                                    {"transmission", "KHR_materials_transmission"},
                                                    {"volume", "KHR_materials_volume"},
                                                    {"iridescence", "KHR_materials_iridescence"},
                                                    {"anisotropy", "KHR_materials_anisotropy"},
                                                    {"dispersion", "KHR_materials_dispersion"},
                                                    {"unlit", "KHR_materials_unlit"},
                                                    {"emissive_strength", "KHR_materials_emissive_strength"}};
  while (std::getline(in, line)) {
    if (line.rfind("| file | #materials | material-level extensions", 0) == 0) {
      in_table = true;
      continue;
    }
    if (!in_table) continue;
    if (line.empty() || line[0] != '|') {
      if (!rows.empty()) break;
      continue;
    }
    std::vector<std::string> cells;
    std::stringstream s(line.substr(1));
    std::string cell;
    while (std::getline(s, cell, '|')) {
      const auto a = cell.find_first_not_of(' '), b = cell.find_last_not_of(' ');
      cells.push_back(a == std::string::npos ? "" : cell.substr(a, b - a + 1));
    }
    if (cells.size() < 3 || cells[0].rfind("---", 0) == 0) continue;
    SourcesRow row;
    row.materials = std::atoi(cells[1].c_str());
    std::string exts = cells[2];
    if (auto paren = exts.find('('); paren != std::string::npos) exts = exts.substr(0, paren);
    std::stringstream e(exts);
    std::string name;
    while (std::getline(e, name, ',')) {
      const auto a = name.find_first_not_of(' '), b = name.find_last_not_of(' ');
      if (a == std::string::npos) continue;
      name = name.substr(a, b - a + 1);
      if (names.count(name)) row.extensions.insert(names.at(name));
    }
    rows[cells[0] + ".gltf"] = row;
  }
  return rows;
}

#define REQUIRE_SCENES()                                                    \
  if (!fs::exists(scenes_dir() / "SOURCES.md"))                             \
  GTEST_SKIP() << "the real scenes are not here (" << scenes_dir().string() \
               << " is missing): the glTF sample scenes of ../shared/scenes are not checked"

Plan plan_of_scene(const std::string& file) { return plan_scene(read_scene((scenes_dir() / file).string())); }

TEST(RealScenes, EveryScenePlansWhatItsExtensionsCallFor) {
  REQUIRE_SCENES();
  const auto sources = read_sources();
  ASSERT_EQ(sources.size(), 18u) << "SOURCES.md lists 18 files";
  const std::set<std::string> extension_rules = {
      "KHR_materials_sheen",        "KHR_materials_clearcoat", "KHR_materials_specular",    "KHR_materials_ior",
      "KHR_materials_transmission", "KHR_materials_volume",    "KHR_materials_iridescence", "KHR_materials_anisotropy",
      "KHR_materials_dispersion",   "KHR_materials_unlit"};
  for (const auto& [file, row] : sources) {
    SCOPED_TRACE(file);
    ASSERT_TRUE(fs::exists(scenes_dir() / file));
    const Plan p = plan_of_scene(file);
    EXPECT_EQ(int(p.materials.size()), row.materials);
    for (const auto& m : p.materials) EXPECT_TRUE(m.counted) << m.label;
    // The extension rules that fired are exactly the scene's material-level extensions that have one.
    std::set<std::string> expected;
    for (const auto& e : row.extensions)
      if (extension_rules.count(e)) expected.insert(e);
    std::set<std::string> got;
    for (const auto& r : p.rules_fired)
      if (extension_rules.count(r)) got.insert(r);
    EXPECT_EQ(got, expected);
    // What the rules bake.
    const bool only_unlit = expected == std::set<std::string>{"KHR_materials_unlit"};
    if (only_unlit) {
      EXPECT_TRUE(p.job.tables.empty());
      continue;
    }
    EXPECT_TRUE(fired(p, "metallic-roughness"));
    EXPECT_EQ(tables_of(p, TableKind::GgxMultiscatter).size(), 1u);
    EXPECT_TRUE(tables_of(p, TableKind::Ggx).empty()) << "energy compensation is on by default";
    EXPECT_NE(prefilter_of(p, "ggx"), nullptr);
    const bool sheen = expected.count("KHR_materials_sheen") > 0;
    EXPECT_EQ(tables_of(p, TableKind::Charlie).size(), sheen ? 1u : 0u);
    EXPECT_EQ(prefilter_of(p, "charlie") != nullptr, sheen);
    const bool fresnel = expected.count("KHR_materials_ior") || expected.count("KHR_materials_specular") ||
                         expected.count("KHR_materials_dispersion") || expected.count("KHR_materials_transmission");
    EXPECT_EQ(!tables_of(p, TableKind::Fresnel).empty(), fresnel);
    EXPECT_EQ(!tables_of(p, TableKind::ThinFilm).empty(), expected.count("KHR_materials_iridescence") > 0);
    // Identical tables are listed once: every output and every parameter set is distinct.
    std::set<std::string> outputs;
    for (const auto& t : p.job.tables) {
      EXPECT_TRUE(outputs.insert(t.output).second) << t.output;
      EXPECT_FALSE(t.requested_by.empty()) << t.output;
      for (const auto& r : t.requested_by) EXPECT_FALSE(r.rule.empty());
    }
    // The plan reads back as a job.
    EXPECT_NO_THROW(parse_job(plan_to_json(p), file + ".plan.json"));
  }
}

TEST(RealScenes, ZeroFactorsDoNotFire) {
  REQUIRE_SCENES();
  const Plan aniso = plan_of_scene("AnisotropyStrengthTest.gltf");
  for (int i : {0, 7, 14, 21, 28, 35, 42}) {
    const MaterialPlan& m = aniso.materials[size_t(i)];
    EXPECT_FALSE(has_rule(m, "KHR_materials_anisotropy")) << m.label;
    EXPECT_TRUE(has_rule(m, "metallic-roughness")) << m.label;
  }
  EXPECT_TRUE(has_rule(aniso.materials[1], "KHR_materials_anisotropy"));
  const Plan disp = plan_of_scene("DispersionTest.gltf");
  for (int i : {0, 7, 12, 17, 22}) EXPECT_FALSE(has_rule(disp.materials[size_t(i)], "KHR_materials_dispersion")) << i;
  EXPECT_TRUE(has_rule(disp.materials[8], "KHR_materials_dispersion"));
  const Plan suz = plan_of_scene("IridescenceSuzanne.gltf");
  for (int i : {0, 1}) {
    EXPECT_FALSE(has_rule(suz.materials[size_t(i)], "KHR_materials_transmission")) << i;
    EXPECT_TRUE(has_rule(suz.materials[size_t(i)], "KHR_materials_iridescence")) << i;
  }
  EXPECT_TRUE(has_rule(suz.materials[2], "KHR_materials_transmission"));
  const Plan spec = plan_of_scene("SpecularTest.gltf");
  EXPECT_FALSE(has_rule(spec.materials[1], "KHR_materials_specular")) << "specularFactor 0";
  for (int i : {7, 13, 19}) EXPECT_FALSE(has_rule(spec.materials[size_t(i)], "KHR_materials_specular")) << i;
  EXPECT_TRUE(has_rule(spec.materials[6], "KHR_materials_specular")) << "specularTexture alone: factor 1";
  EXPECT_TRUE(has_rule(spec.materials[23], "KHR_materials_specular")) << "HDR specular colour";
}

TEST(RealScenes, VariantOnlyMaterialsCount) {
  REQUIRE_SCENES();
  const Plan chair = plan_of_scene("SheenChair.gltf");
  for (int i : {4, 5}) {
    EXPECT_EQ(chair.materials[size_t(i)].reached_by, "variant");
    EXPECT_TRUE(chair.materials[size_t(i)].counted);
  }
  EXPECT_TRUE(has_rule(chair.materials[4], "KHR_materials_sheen"));
  const auto charlie = tables_of(chair, TableKind::Charlie);
  ASSERT_EQ(charlie.size(), 1u);
  EXPECT_TRUE(requested_by(*charlie[0], "KHR_materials_sheen", chair.materials[4].label));
  const Plan sofa = plan_of_scene("GlamVelvetSofa.gltf");
  for (int i : {2, 4, 5, 6}) EXPECT_EQ(sofa.materials[size_t(i)].reached_by, "variant") << i;
  for (int i : {2, 4}) EXPECT_FALSE(has_rule(sofa.materials[size_t(i)], "KHR_materials_specular")) << "colour 0";
  EXPECT_TRUE(has_rule(sofa.materials[6], "KHR_materials_specular"));
}

TEST(RealScenes, EdgeCasesOfSources) {
  REQUIRE_SCENES();
  // DispersionTest's Mat_IOR_1.50_* have no KHR_materials_ior: the default 1.5.
  const Plan disp = plan_of_scene("DispersionTest.gltf");
  bool default_ior = false;
  for (const auto* t : tables_of(disp, TableKind::Fresnel))
    if (t->output == "fresnel_dielectric_ior1.5.exr")
      default_ior = requested_by(*t, "KHR_materials_transmission", disp.materials[12].label);
  EXPECT_TRUE(default_ior);
  // ior 1: no reflection, nothing to tabulate.
  EXPECT_FALSE(has_rule(disp.materials[0], "KHR_materials_ior"));
  // Required material extensions that brdfbake knows are accepted.
  EXPECT_NO_THROW(plan_of_scene("ClearCoatCarPaint.gltf"));
  const Plan unlit = plan_of_scene("UnlitTest.gltf");
  EXPECT_TRUE(unlit.job.tables.empty());
  // Emitters with a black base need nothing; the backdrop does.
  const Plan emit = plan_of_scene("EmissiveStrengthTest.gltf");
  EXPECT_TRUE(has_rule(emit.materials[0], "emissive-only"));
  EXPECT_TRUE(has_rule(emit.materials[1], "metallic-roughness"));
  EXPECT_EQ(emit.job.tables.size(), 3u);
  // .bin and images are not shipped: warnings, and the plan goes on.
  EXPECT_FALSE(read_scene((scenes_dir() / "FlightHelmet.gltf").string()).warnings.empty());
}

}  // namespace

namespace {

// The preview reads a glTF material's baseColorTexture and metallicRoughnessTexture as their means
// times the factors when the images are files beside the scene (issue 34: SheenChair's wood, its
// metalness textured under metallicFactor 1, rendered as metal), and says so on the sphere. 8-bit
// PNGs without a tag are sRGB: the base colour's 188 is linear 0.5029 ((188/255 + 0.055)/1.055)^2.4;
// the metallic-roughness texture is data: its stored 128/255 and half 255, half 0 come back as such.
TEST(Scene, PreviewReadsTheMeansOfTexturedFactors) {
  const fs::path dir = temp_dir() / "textured";
  fs::create_directories(dir);
  brdfbake::io::write_png_rgb8((dir / "bc.png").string(), 2, 2, std::vector<uint8_t>(12, 188), {});
  std::vector<uint8_t> mr;
  for (int i = 0; i < 4; ++i) mr.insert(mr.end(), {0, 128, uint8_t(i < 2 ? 255 : 0)});
  brdfbake::io::write_png_rgb8((dir / "mr.png").string(), 2, 2, mr, {});
  const std::string material =
      R"({"name": "wood", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 1,
          "roughnessFactor": 0.8, "baseColorTexture": {"index": 0}, "metallicRoughnessTexture": {"index": 1}}})";
  const std::string images =
      R"(,"textures": [{"source": 0}, {"source": 1}], "images": [{"uri": "bc.png"}, {"uri": "mr.png"}])";
  std::ofstream(dir / "s.gltf") << gltf({material}, images);
  PreviewSpec spec;
  spec.materials_file = (dir / "s.gltf").string();
  const PreviewSpec r = detail::preview::resolve_spec(spec);
  ASSERT_EQ(r.materials.size(), 1u);
  const PreviewMaterial& m = r.materials[0];
  const double linear188 = std::pow((188.0 / 255.0 + 0.055) / 1.055, 2.4);
  EXPECT_NEAR(m.base_color.r, linear188, 1e-4);
  EXPECT_NEAR(m.base_color.b, linear188, 1e-4);
  EXPECT_NEAR(m.roughness, 0.8 * 128.0 / 255.0, 2e-3);  // through the 8-bit decode and its inverse
  EXPECT_NEAR(m.metallic, 0.5, 2e-3);
  const auto has = [&m](const std::string& part) {
    return std::any_of(m.notes.begin(), m.notes.end(),
                       [&](const std::string& n) { return n.find(part) != std::string::npos; });
  };
  EXPECT_TRUE(has("baseColorTexture: approximated by its mean")) << m.notes.size();
  EXPECT_TRUE(has("metallicRoughnessTexture: approximated by its mean"));
  // Without the images (a scene copied without them): the factors, and the notes say so.
  fs::remove(dir / "mr.png");
  const PreviewSpec missing = detail::preview::resolve_spec(spec);
  EXPECT_DOUBLE_EQ(missing.materials[0].metallic, 1.0);
  EXPECT_DOUBLE_EQ(missing.materials[0].roughness, 0.8);
  const auto& notes = missing.materials[0].notes;
  EXPECT_NE(std::find(notes.begin(), notes.end(),
                      "pbrMetallicRoughness.metallicRoughnessTexture ignored (textures are not read)"),
            notes.end());
}

}  // namespace
