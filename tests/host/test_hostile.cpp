// The hostile-input table (issue 17, docs/RELIABILITY.md): every input path of the product run the
// way a hostile or careless user runs it. Each row is a command line, the files it reads (written
// into the row's own folder first), its standard input, and what must follow: the exit code (2 bad
// input, 1 runtime or I/O failure, 0 success), words the one-line message must hold, files that must
// not exist afterwards, files that must keep their content, and for some successful rows their
// output read back against the value it must hold. Every row also checks what must never
// happen: a crash or a signal, a library's raw exception text, a sanitizer report, a stray temporary.
//
// Rows marked `pending` (none today) wait for a piece of work named in their reason: they are
// skipped with that reason until it lands.
//
// The rows come from two sources: written by hand per class of issue 17, and generated from every
// kind's parameter schema (each numeric, named and list parameter with values out of range, not
// finite, of the wrong type), on the command line and in a job.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/output_lock.hpp"
#include "brdfbake/plan.hpp"
#include "brdfbake/tables.hpp"
#include "io/ktx2.hpp"
#include "support/temp_dir.hpp"
#include "support/tolerances.hpp"

#ifndef BRDFBAKE_CLI
#define BRDFBAKE_CLI "brdfbake"
#endif

namespace {

namespace fs = std::filesystem;
using brdfbake::ParamDef;
using brdfbake::ParamType;
using brdfbake::TableKind;

// ---- Inputs the rows write ------------------------------------------------------------------------

std::string repeat(const std::string& s, size_t n) {
  std::string out;
  out.reserve(s.size() * n);
  for (size_t i = 0; i < n; ++i) out += s;
  return out;
}

// A value nested `depth` arrays deep: what killed the parsers' recursive message code.
std::string deep(size_t depth) { return repeat("[", depth) + "1" + repeat("]", depth); }

// A Radiance .hdr (RGBE) of w x h pixels of grey `v` (flat scanlines: no RLE run starts with 2, 2).
std::string rgbe(int w, int h, double v) {
  std::string s = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " + std::to_string(h) + " +X " + std::to_string(w) + "\n";
  char px[4] = {0, 0, 0, 0};
  if (v > 0) {
    int e = 0;
    const double m = std::frexp(v, &e);
    const unsigned char b = static_cast<unsigned char>(std::min(255.0, m * 256.0));
    px[0] = px[1] = px[2] = static_cast<char>(b);
    px[3] = static_cast<char>(std::min(255, e + 128));
  }
  for (int i = 0; i < w * h; ++i) s.append(px, 4);
  return s;
}

// A KTX2 cube (RGBA32F, faces of `size`) of grey `v`, with `bad` texels set to `bad_value`.
std::string ktx2_cube(int size, float v, int bad = 0, float bad_value = NAN) {
  brdfbake::io::Ktx2Image k;
  k.vk_format = brdfbake::io::kVkFormatR32G32B32A32Sfloat;
  k.width = k.height = static_cast<uint32_t>(size);
  k.faces = 6;
  std::vector<float> texels(6u * size_t(size) * size_t(size) * 4u, v);
  for (size_t t = 0; t < texels.size(); t += 4) texels[t + 3] = 1.0f;
  for (int b = 0; b < bad; ++b) texels[4 * size_t(b)] = bad_value;
  k.level_data.resize(1);
  k.level_data[0].resize(texels.size() * sizeof(float));
  std::memcpy(k.level_data[0].data(), texels.data(), k.level_data[0].size());
  const std::vector<uint8_t> bytes = brdfbake::io::encode_ktx2(k);
  return std::string(bytes.begin(), bytes.end());
}

std::string le32(uint32_t v) {
  std::string s(4, '\0');
  for (int i = 0; i < 4; ++i) s[size_t(i)] = static_cast<char>((v >> (8 * i)) & 0xFF);
  return s;
}

// A binary glTF holding `json` (padded with spaces), with the header's length `length` (0: correct).
std::string glb(const std::string& json, uint32_t length = 0, uint32_t version = 2) {
  std::string chunk = json;
  while (chunk.size() % 4) chunk += ' ';
  const uint32_t total = static_cast<uint32_t>(12 + 8 + chunk.size());
  return "glTF" + le32(version) + le32(length ? length : total) + le32(static_cast<uint32_t>(chunk.size())) + "JSON" +
         chunk;
}

std::string floats(const std::vector<float>& v) {
  return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(float));
}

const std::string kMaterials =
    R"({"materials": [{"name": "a", "model": "gltf", "baseColor": [0.5, 0.5, 0.5], "roughness": 0.5}]})";
const std::string kTwoMaterials =
    R"({"materials": [{"name": "a", "model": "gltf"}, {"name": "b", "model": "lambert"}]})";
const std::string kScene =
    R"({"asset": {"version": "2.0"}, "materials": [{"name": "m", "pbrMetallicRoughness": {"roughnessFactor": 0.5}}]})";
const std::string kPairs = "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,1,0.5,0,0.8\n";
// A job of one small table (runs in well under a second on a CPU device).
std::string job(const std::string& tables, const std::string& extra = "") {
  return R"({"brdfbake_job": 1)" + extra + R"(, "tables": [)" + tables + "]}";
}
const std::string kLut = R"({"kind": "ggx", "size": 4, "output": "t.exr"})";

// ---- Rows -----------------------------------------------------------------------------------------

struct File {
  std::string name;  // relative to the row's folder; "{deadpid}" is replaced by a pid no process has
  std::string bytes;
};

struct Row {
  std::string name;                 // [A-Za-z0-9_] (a gtest name)
  std::string args;                 // brdfbake's arguments; {d} is the row's folder (shell-quoted)
  std::vector<File> files;          // written before the run
  int code = 2;                     // the expected exit code
  std::vector<std::string> words;   // in standard error
  std::vector<std::string> absent;  // must not exist afterwards ({d}-relative)
  std::vector<std::string> kept;    // files of `files` that must still hold their bytes
  std::string input;                // standard input
  std::string env;                  // NAME=value ... for the command
  std::string pending;              // not empty: expected to fail until this is done (skipped)
  int max_lines = 1;                // lines of standard error a failure may print
  std::vector<std::pair<std::string, std::string>> file_has, file_lacks;  // (file, text)
  std::vector<std::string> allowed_tmp;  // temporaries that must stay (a live process's)
  bool as_root_skip = false;             // permissions mean nothing to root
  std::string hold_lock;                 // the test holds the lock of {d}/<this> during the run
  int release_after_ms = 0;              // ... and releases it after this long (0: at the end)
  long memory_cap_kib = 0;               // the run's address space is capped (ulimit -v): what it allocates must fit
  std::function<void(const fs::path&)> check_output;  // reads a successful row's output back ({d} given)
  // Special files and signals: a shell command run in the row's folder first (mkfifo, ln), and a
  // script that replaces the plain command line: {cli} is the bounded brdfbake, {err} the file its
  // standard error must go to, {status} the file its exit status may be written to (a pipeline's
  // status is its last command's), {in} its standard input, {d} the row's folder.
  std::string setup;
  std::string script;
  bool silent_ok = false;               // a failure may print nothing (its stderr was a closed pipe)
  std::vector<std::string> never;       // words standard error must not hold
  std::vector<std::string> still_fifo;  // FIFOs of `setup` that must still be FIFOs afterwards
  std::vector<std::string> still_link;  // symbolic links of `setup` that must not have been replaced
};

// Chained setters so that the table reads as a table.
struct R {
  Row r;
  R(std::string name, std::string args, int code) {
    r.name = std::move(name);
    r.args = std::move(args);
    r.code = code;
  }
  R& file(std::string n, std::string b) {
    r.files.push_back({std::move(n), std::move(b)});
    return *this;
  }
  R& says(std::string w) {
    r.words.push_back(std::move(w));
    return *this;
  }
  R& no(std::string p) {
    r.absent.push_back(std::move(p));
    return *this;
  }
  R& keeps(std::string p) {
    r.kept.push_back(std::move(p));
    return *this;
  }
  R& stdin_(std::string s) {
    r.input = std::move(s);
    return *this;
  }
  R& env(std::string e) {
    r.env = std::move(e);
    return *this;
  }
  R& pending(std::string why) {
    r.pending = std::move(why);
    return *this;
  }
  R& lines(int n) {
    r.max_lines = n;
    return *this;
  }
  R& has(std::string f, std::string t) {
    r.file_has.push_back({std::move(f), std::move(t)});
    return *this;
  }
  R& lacks(std::string f, std::string t) {
    r.file_lacks.push_back({std::move(f), std::move(t)});
    return *this;
  }
  R& allow_tmp(std::string p) {
    r.allowed_tmp.push_back(std::move(p));
    return *this;
  }
  R& root_skip() {
    r.as_root_skip = true;
    return *this;
  }
  R& memory_cap_mib(long mib) {
    r.memory_cap_kib = mib * 1024;
    return *this;
  }
  R& lock(std::string target, int release_ms = 0) {
    r.hold_lock = std::move(target);
    r.release_after_ms = release_ms;
    return *this;
  }
  R& output(std::function<void(const fs::path&)> check) {
    r.check_output = std::move(check);
    return *this;
  }
  R& setup(std::string shell) {
    r.setup = std::move(shell);
    return *this;
  }
  R& script(std::string shell) {
    r.script = std::move(shell);
    return *this;
  }
  R& silent_ok() {
    r.silent_ok = true;
    return *this;
  }
  R& never(std::string w) {
    r.never.push_back(std::move(w));
    return *this;
  }
  R& still_fifo(std::string p) {
    r.still_fifo.push_back(std::move(p));
    return *this;
  }
  R& still_link(std::string p) {
    r.still_link.push_back(std::move(p));
    return *this;
  }
  operator Row() const { return r; }
};

// -- Class 1: deep and large JSON, everywhere JSON is read.
void deep_json(std::vector<Row>& rows) {
  const std::string d = deep(100000);
  rows.push_back(R("deep_job_document", "run {d}/job.json -o {d}/out", 2)
                     .file("job.json", d)
                     .says("nested deeper than 64")
                     .no("out"));
  rows.push_back(R("deep_job_value", "run {d}/job.json -o {d}/out", 2)
                     .file("job.json", job(R"({"kind": "ggx", "size": )" + d + "}"))
                     .says("nested deeper than 64")
                     .says("tables[0].size")
                     .no("out"));
  rows.push_back(R("deep_job_requested_by", "run {d}/job.json -o {d}/out", 2)
                     .file("job.json", job(R"({"kind": "ggx", "requested_by": )" + d + "}"))
                     .says("nested deeper than 64")
                     .no("out"));
  rows.push_back(R("deep_job_unknown_field", "run {d}/job.json -o {d}/out", 2)
                     .file("job.json", job(kLut, R"(, "zzz": )" + d))
                     .says("nested deeper than 64"));
  rows.push_back(R("deep_scene_gltf", "bake --scene {d}/s.gltf --dry-run", 2)
                     .file("s.gltf", R"({"asset": {"version": "2.0"}, "materials": )" + d + "}")
                     .says("nested deeper than 64"));
  rows.push_back(R("deep_scene_glb", "bake --scene {d}/s.glb --dry-run", 2)
                     .file("s.glb", glb(R"({"asset": {"version": "2.0"}, "extras": )" + d + "}"))
                     .says("nested deeper than 64"));
  rows.push_back(R("deep_material_json_eval", "eval --material {d}/m.json -i {d}/p.csv -o {d}/f.csv", 2)
                     .file("m.json", R"({"materials": [{"name": "a", "roughness": )" + d + "}]}")
                     .file("p.csv", kPairs)
                     .says("nested deeper than 64")
                     .no("f.csv"));
  rows.push_back(R("deep_material_gltf_tabulate", "tabulate --material {d}/m.gltf --layout albedo -o {d}/t.exr", 2)
                     .file("m.gltf", R"({"asset": {"version": "2.0"}, "materials": [{"extensions": )" + d + "}]}")
                     .says("nested deeper than 64")
                     .no("t.exr"));
  rows.push_back(R("deep_object_nesting", "run {d}/job.json -o {d}/out", 2)
                     .file("job.json", repeat(R"({"a":)", 5000) + "1" + repeat("}", 5000))
                     .says("nested deeper than 64"));
  rows.push_back(R("large_job_document", "run {d}/job.json -o {d}/out", 2)
                     .file("job.json", job(kLut) + std::string((64u << 20) + 16, ' '))
                     .says("larger than 64 MiB")
                     .no("out"));
  rows.push_back(R("large_scene_document", "bake --scene {d}/s.gltf --dry-run", 2)
                     .file("s.gltf", kScene + std::string((64u << 20) + 16, ' '))
                     .says("larger than 64 MiB"));
  rows.push_back(R("large_glb_json_chunk", "bake --scene {d}/s.glb --dry-run", 2)
                     .file("s.glb", glb(kScene + std::string((64u << 20) + 16, ' ')))
                     .says("larger than 64 MiB"));
}

// -- Class 2: numbers a double cannot hold and JSON values of the wrong type: a message naming the
// field, exit 2, never the library's exception text.
void raw_exceptions(std::vector<Row>& rows) {
  struct J {
    const char* name;
    std::string doc;
    const char* field;
  };
  const std::vector<J> jobs = {
      {"job_size_1e999", job(R"({"kind": "ggx", "size": 1e999})"), "tables[0].size"},
      {"job_size_minus_1e999", job(R"({"kind": "ggx", "size": -1e999})"), "tables[0].size"},
      {"job_version_1e999", R"({"brdfbake_job": 1e999, "tables": []})", "brdfbake_job"},
      {"job_version_huge_integer", R"({"brdfbake_job": 18446744073709551615, "tables": []})", "brdfbake_job"},
      {"job_version_text", R"({"brdfbake_job": "1", "tables": []})", "brdfbake_job"},
      {"job_tables_object", R"({"brdfbake_job": 1, "tables": {"kind": "ggx"}})", "tables"},
      {"job_tables_number", R"({"brdfbake_job": 1, "tables": 3})", "tables"},
      {"job_table_not_object", job("3"), "tables[0]"},
      {"job_kind_number", job(R"({"kind": 7})"), "tables[0].kind"},
      {"job_kind_unknown", job(R"({"kind": "phong"})"), "tables[0].kind"},
      {"job_kind_missing", job(R"({"size": 4})"), "tables[0].kind"},
      {"job_output_number", job(R"({"kind": "ggx", "output": 5})"), "tables[0].output"},
      {"job_precision_number", job(R"({"kind": "ggx", "precision": 64})"), "tables[0].precision"},
      {"job_precision_fp16", job(R"({"kind": "ggx", "precision": "fp16"})"), "tables[0].precision"},
      {"job_sanitize_text", job(kLut, R"(, "sanitize": "yes")"), "sanitize"},
      {"job_environment_number", job(kLut, R"(, "environment": 1)"), "environment"},
      {"job_environment_empty", job(kLut, R"(, "environment": "")"), "environment"},
      {"job_notes_number", job(kLut, R"(, "notes": 1)"), "notes"},
      {"job_notes_numbers", job(kLut, R"(, "notes": [1, 2])"), "notes"},
      {"job_requested_by_object", job(R"({"kind": "ggx", "requested_by": {}})"), "tables[0].requested_by"},
      {"job_requested_by_unknown", job(R"({"kind": "ggx", "requested_by": [{"who": "x"}]})"),
       "tables[0].requested_by[0]"},
      {"job_requested_by_number_rule", job(R"({"kind": "ggx", "requested_by": [{"rule": 5}]})"),
       "tables[0].requested_by[0].rule"},
      {"job_materials_numbers", job(R"({"kind": "ggx", "materials": [1]})"), "tables[0].materials"},
      {"job_param_object", job(R"({"kind": "ggx", "size": {"a": 1}})"), "tables[0].size"},
      {"job_param_null", job(R"({"kind": "ggx", "size": null})"), "tables[0].size"},
      {"job_param_list_of_text", job(R"({"kind": "fresnel", "model": "schlick", "f0": ["a", "b", "c"]})"),
       "tables[0].f0"},
      {"job_param_nested_list", job(R"({"kind": "fresnel", "model": "schlick", "f0": [[1], [2], [3]]})"),
       "tables[0].f0"},
      {"job_unknown_field", job(R"({"kind": "ggx", "colour": 1})"), "tables[0].colour"},
      {"job_unknown_top_field", job(kLut, R"(, "colour": 1)"), "colour"},
      {"job_not_object", "[1, 2]", "a job is a JSON object"},
      {"job_empty_text", "", "malformed JSON"},
      {"job_binary_garbage", std::string("\x89PNG\r\n\x1a\n\0\0", 10), "malformed JSON"},
      {"job_trailing_text", job(kLut) + " x", "malformed JSON"},
      {"job_bad_utf8", std::string("{\"brdfbake_job\": 1, \"tables\": [], \"notes\": [\"\xff\xfe\"]}"),
       "malformed JSON"},
      {"job_duplicate_output",
       job(R"({"kind": "ggx", "size": 4, "output": "t.exr"}, {"kind": "ggx", "size": 8, "output": "t.exr"})"),
       "tables[1].output"},
      {"job_output_absolute", job(R"({"kind": "ggx", "output": "/tmp/x.exr"})"), "tables[0].output"},
      {"job_output_parent", job(R"({"kind": "ggx", "output": "../x.exr"})"), "tables[0].output"},
      {"job_output_manifest", job(R"({"kind": "ggx", "output": "manifest.json"})"), "tables[0].output"},
      {"job_output_empty", job(R"({"kind": "ggx", "output": ""})"), "tables[0]"},
      {"job_sh_json_parent", job(R"({"kind": "irradiance", "output": "c.ktx2", "sh_json": "../sh.json"})"),
       "tables[0].sh_json"},
      {"job_eval_input_stdin", job(R"({"kind": "eval", "material": "m.json", "input": "-"})"), "tables[0].input"},
  };
  for (const J& j : jobs)
    rows.push_back(R(j.name, "run {d}/job.json -o {d}/out", 2)
                       .file("job.json", j.doc)
                       .file("m.json", kMaterials)
                       .says(j.field)
                       .no("out"));

  struct G {
    const char* name;
    std::string scene;
    const char* field;
  };
  auto scene = [](const std::string& material) {
    return R"({"asset": {"version": "2.0"}, "materials": [)" + material + "]}";
  };
  const std::vector<G> scenes = {
      {"gltf_metallic_1e999", scene(R"({"pbrMetallicRoughness": {"metallicFactor": 1e999}})"), "metallicFactor"},
      {"gltf_roughness_text", scene(R"({"pbrMetallicRoughness": {"roughnessFactor": "x"}})"), "roughnessFactor"},
      {"gltf_roughness_2", scene(R"({"pbrMetallicRoughness": {"roughnessFactor": 2}})"), "roughnessFactor"},
      {"gltf_base_color_object", scene(R"({"pbrMetallicRoughness": {"baseColorFactor": {}}})"), "baseColorFactor"},
      {"gltf_base_color_short", scene(R"({"pbrMetallicRoughness": {"baseColorFactor": [1, 1]}})"), "baseColorFactor"},
      {"gltf_base_color_nan_text", scene(R"({"pbrMetallicRoughness": {"baseColorFactor": [1, "NaN", 1, 1]}})"),
       "baseColorFactor[1]"},
      {"gltf_pbr_number", scene(R"({"pbrMetallicRoughness": 5})"), "pbrMetallicRoughness"},
      {"gltf_extensions_list", scene(R"({"extensions": []})"), "extensions"},
      {"gltf_sheen_number", scene(R"({"extensions": {"KHR_materials_sheen": 3}})"), "KHR_materials_sheen"},
      {"gltf_sheen_color_1e999",
       scene(R"({"extensions": {"KHR_materials_sheen": {"sheenColorFactor": [1e999, 0, 0]}}})"), "sheenColorFactor"},
      {"gltf_ior_half", scene(R"({"extensions": {"KHR_materials_ior": {"ior": 0.5}}})"), "ior"},
      {"gltf_ior_minus_1e999", scene(R"({"extensions": {"KHR_materials_ior": {"ior": -1e999}}})"), "ior"},
      {"gltf_texture_negative", scene(R"({"pbrMetallicRoughness": {"baseColorTexture": {"index": -1}}})"),
       "baseColorTexture.index"},
      {"gltf_texture_text", scene(R"({"emissiveTexture": {"index": "0"}})"), "emissiveTexture.index"},
      {"gltf_material_number", scene("3"), "materials[0]"},
      {"gltf_name_number", scene(R"({"name": 5})"), "materials[0].name"},
      {"gltf_no_asset", R"({"materials": []})", "asset"},
      {"gltf_version_1", R"({"asset": {"version": "1.0"}})", "asset.version"},
      {"gltf_version_number", R"({"asset": {"version": 2}})", "asset.version"},
      {"gltf_required_unknown", R"({"asset": {"version": "2.0"}, "extensionsRequired": ["ACME_magic"]})", "ACME_magic"},
      {"gltf_required_number", R"({"asset": {"version": "2.0"}, "extensionsRequired": [1]})", "extensionsRequired[0]"},
      {"gltf_materials_object", R"({"asset": {"version": "2.0"}, "materials": {}})", "materials"},
      {"gltf_mesh_material_out_of_range",
       R"({"asset": {"version": "2.0"}, "materials": [{}], "meshes": [{"primitives": [{"material": 7}]}]})",
       "meshes[0].primitives[0].material"},
      {"gltf_mesh_material_huge",
       R"({"asset": {"version": "2.0"}, "materials": [{}], "meshes": [{"primitives": [{"material": 1e300}]}]})",
       "meshes[0].primitives[0].material"},
      {"gltf_mesh_material_negative",
       R"({"asset": {"version": "2.0"}, "materials": [{}], "meshes": [{"primitives": [{"material": -9223372036854775808}]}]})",
       "meshes[0].primitives[0].material"},
      {"gltf_mesh_number", R"({"asset": {"version": "2.0"}, "meshes": [5]})", "meshes[0]"},
      {"gltf_variant_mapping_bad",
       R"({"asset": {"version": "2.0"}, "materials": [{}], "meshes": [{"primitives": [{"extensions": {"KHR_materials_variants": {"mappings": [{"material": 0, "variants": [3]}]}}}]}]})",
       "variants[0]"},
      {"gltf_not_object", "[]", "not a glTF document"},
  };
  for (const G& g : scenes) {
    rows.push_back(R(std::string("bake_") + g.name, "bake --scene {d}/s.gltf -o {d}/out --quiet", 2)
                       .file("s.gltf", g.scene)
                       .says(g.field)
                       .no("out"));
  }
  // The same documents as eval's material files (glTF materials): the fields it reads.
  const std::vector<G> eval_gltf = {
      {"gltf_metallic_1e999", scene(R"({"pbrMetallicRoughness": {"metallicFactor": 1e999}})"), "metallicFactor"},
      {"gltf_roughness_text", scene(R"({"pbrMetallicRoughness": {"roughnessFactor": "x"}})"), "roughnessFactor"},
      {"gltf_base_color_object", scene(R"({"pbrMetallicRoughness": {"baseColorFactor": {}}})"), "baseColorFactor"},
      {"gltf_pbr_number", scene(R"({"pbrMetallicRoughness": 5})"), "pbrMetallicRoughness"},
      {"gltf_sheen_number", scene(R"({"extensions": {"KHR_materials_sheen": 3}})"), "KHR_materials_sheen"},
      {"gltf_sheen_roughness_null", scene(R"({"extensions": {"KHR_materials_sheen": {"sheenRoughnessFactor": null}}})"),
       "sheenRoughnessFactor"},
      {"gltf_ior_1e999", scene(R"({"extensions": {"KHR_materials_ior": {"ior": 1e999}}})"), "ior"},
      {"gltf_specular_color_negative",
       scene(R"({"extensions": {"KHR_materials_specular": {"specularColorFactor": [-1, 0, 0]}}})"),
       "specularColorFactor"},
      {"gltf_material_number", scene("3"), "materials[0]"},
  };
  for (const G& g : eval_gltf)
    rows.push_back(R(std::string("eval_") + g.name, "eval --material {d}/m.gltf -i {d}/p.csv -o {d}/f.csv", 2)
                       .file("m.gltf", g.scene)
                       .file("p.csv", kPairs)
                       .says(g.field)
                       .no("f.csv"));

  struct M {
    const char* name;
    std::string doc;
    const char* words;
  };
  const std::vector<M> materials = {
      {"material_roughness_1e999", R"({"materials": [{"name": "a", "model": "gltf", "roughness": 1e999}]})",
       "materials[0].roughness"},
      {"material_roughness_text", R"({"materials": [{"name": "a", "model": "gltf", "roughness": "x"}]})", "roughness"},
      {"material_roughness_2", R"({"materials": [{"name": "a", "model": "gltf", "roughness": 2}]})", "roughness"},
      {"material_base_color_short", R"({"materials": [{"name": "a", "model": "gltf", "baseColor": [1]}]})",
       "baseColor"},
      {"material_base_color_1e999", R"({"materials": [{"name": "a", "model": "gltf", "baseColor": [0, 1e999, 0]}]})",
       "baseColor"},
      {"material_name_number", R"({"materials": [{"name": 5}]})", "name"},
      {"material_model_number", R"({"materials": [{"name": "a", "model": 7}]})", "model"},
      {"material_model_unknown", R"({"materials": [{"name": "a", "model": "magic"}]})", "magic"},
      {"material_unknown_parameter", R"({"materials": [{"name": "a", "model": "gltf", "glow": 1}]})", "glow"},
      {"material_not_object", R"({"materials": [5]})", "material #0"},
      {"materials_object", R"({"materials": {}})", "materials"},
      {"materials_empty", R"({"materials": []})", "empty"},
      {"material_ior_half", R"({"materials": [{"name": "a", "model": "gltf", "ior": 0.5}]})", "ior"},
      {"material_shininess_huge", R"({"materials": [{"name": "a", "model": "phong", "shininess": 1e300}]})",
       "shininess"},
      {"material_normalized_text", R"({"materials": [{"name": "a", "model": "phong", "normalized": "yes"}]})",
       "normalized"},
      {"material_distribution_number", R"({"materials": [{"name": "a", "model": "cook-torrance", "distribution": 1}]})",
       "distribution"},
      {"material_name_twice", R"({"materials": [{"name": "a", "model": "gltf"}, {"name": "a", "model": "gltf"}]})",
       "used twice"},
      {"material_long_name_missing", kMaterials, "no material named"},
  };
  for (const M& m : materials) {
    const std::string extra = std::string(m.name) == "material_long_name_missing" ? " --name " + repeat("x", 5000) : "";
    rows.push_back(R(std::string("eval_") + m.name, "eval --material {d}/m.json -i {d}/p.csv -o {d}/f.csv" + extra, 2)
                       .file("m.json", m.doc)
                       .file("p.csv", kPairs)
                       .says(m.words)
                       .no("f.csv"));
  }
  rows.push_back(R("tabulate_material_1e999", "tabulate --material {d}/m.json --layout grid --res 4 -o {d}/t.exr", 2)
                     .file("m.json", R"({"materials": [{"name": "a", "model": "gltf", "metallic": 1e999}]})")
                     .says("materials[0].metallic")
                     .no("t.exr"));
  rows.push_back(
      R("tabulate_two_materials_no_name", "tabulate --material {d}/m.json --layout grid --res 4 -o {d}/t.exr", 2)
          .file("m.json", kTwoMaterials)
          .says("--name")
          .no("t.exr"));
  rows.push_back(R("tabulate_models_differ", "tabulate --material {d}/m.json --layout albedo --res 4 -o {d}/t.exr", 2)
                     .file("m.json", kTwoMaterials)
                     .says("--model")
                     .no("t.exr"));
  // A binary glTF material file is read like its JSON (the one glTF reader, scene.cpp), found by its
  // extension or by its magic under another name: one row of f, finite and positive.
  const auto one_finite_row = [](const fs::path& d) {
    std::ifstream in(d / "f.csv");
    std::string header, row;
    std::getline(in, header);
    std::getline(in, row);
    EXPECT_EQ(header, "r,g,b");
    const double r = std::strtod(row.c_str(), nullptr);
    EXPECT_TRUE(std::isfinite(r) && r > 0) << row;
  };
  rows.push_back(R("eval_material_glb", "eval --material {d}/m.glb -i {d}/p.csv -o {d}/f.csv", 0)
                     .file("m.glb", glb(kScene))
                     .file("p.csv", kPairs)
                     .output(one_finite_row));
  rows.push_back(R("eval_material_glb_magic", "eval --material {d}/m.json -i {d}/p.csv -o {d}/f.csv", 0)
                     .file("m.json", glb(kScene))
                     .file("p.csv", kPairs)
                     .output(one_finite_row));
}

// The grey radiance of {d}/huge.hdr as the product reads it.
double huge_radiance(const fs::path& dir) {
  const brdfbake::EnvImage env = brdfbake::load_environment((dir / "huge.hdr").string());
  EXPECT_FALSE(env.rgb.empty());
  return env.rgb.empty() ? 0.0 : double(env.rgb[0]);
}

// A cube (RGBA32F, `levels` levels from `size`^2) of the constant environment {d}/huge.hdr, near
// FLT_MAX: every texel of every level holds that radiance, finite, within `tolerance` (relative): a
// prefiltered level is a lobe average of a constant (fp32 sums, kEnvFurnace), an irradiance cube
// E / pi = L up to the device's cosine convolution of a coarse source (kEnvIrradianceDevice).
void expect_constant_cube(const fs::path& dir, const std::string& file, uint32_t levels, size_t size,
                          double tolerance) {
  const double radiance = huge_radiance(dir);
  EXPECT_GT(radiance, 1e38);
  const brdfbake::io::Ktx2Image k = brdfbake::io::read_ktx2((dir / file).string());
  ASSERT_EQ(k.vk_format, brdfbake::io::kVkFormatR32G32B32A32Sfloat);
  ASSERT_EQ(k.faces, 6u);
  ASSERT_EQ(k.levels, levels);
  for (size_t l = 0; l < k.levels; ++l) {
    std::vector<float> texels(k.level_data[l].size() / sizeof(float));
    std::memcpy(texels.data(), k.level_data[l].data(), texels.size() * sizeof(float));
    ASSERT_EQ(texels.size(), 6u * 4u * (size >> l) * (size >> l));
    for (size_t t = 0; t < texels.size(); ++t) {
      if (t % 4 == 3) continue;  // alpha
      ASSERT_NEAR(double(texels[t]) / radiance, 1.0, tolerance) << file << " level " << l << " texel " << t / 4;
    }
  }
}

// SH coefficients of that environment (order `order`): radiance L gives L_00 = 2 sqrt(pi) L in both
// the radiance and E / pi (A_0 / pi = 1, band 0 unwindowed), every other coefficient 0; the host
// projection of equirect pixels is exact.
void expect_constant_sh(const fs::path& dir, const std::string& file, size_t order) {
  const double l00 = 2.0 * std::sqrt(3.14159265358979323846) * huge_radiance(dir);
  std::ifstream in(dir / file);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  ASSERT_TRUE(j.is_object()) << file << " is not JSON";
  for (const char* key : {"radiance", "irradiance_over_pi"}) {
    ASSERT_EQ(j[key].size(), order * order) << key;
    for (size_t k = 0; k < order * order; ++k)
      for (size_t c = 0; c < 3; ++c)
        EXPECT_NEAR(j[key][k][c].get<double>() / l00, k == 0 ? 1.0 : 0.0, brdfbake::test::kShExactProjection)
            << file << " " << key << " " << k;
  }
}

// -- Class 3: outputs that cannot hold a value, and radiance near FLT_MAX.
void numeric_outputs(std::vector<Row>& rows) {
  const std::string huge = rgbe(16, 8, 1.69e38);  // near FLT_MAX: sums of two overflow in fp32
  rows.push_back(
      R("sh_of_radiance_near_flt_max", "irradiance --env {d}/huge.hdr --source-size 8 --quiet -o {d}/sh.json", 0)
          .file("huge.hdr", huge)
          .has("sh.json", "irradiance_over_pi")
          .lacks("sh.json", "null")
          .lacks("sh.json", "inf")
          .lines(0)
          .output([](const fs::path& d) { expect_constant_sh(d, "sh.json", 3); }));
  rows.push_back(R("sh5_of_radiance_near_flt_max",
                   "irradiance --env {d}/huge.hdr --sh 5 --sh-window lanczos --source-size 8 --quiet -o {d}/sh.json", 0)
                     .file("huge.hdr", huge)
                     .has("sh.json", "\"order\": 5")
                     .lacks("sh.json", "null")
                     .lines(0)
                     .output([](const fs::path& d) { expect_constant_sh(d, "sh.json", 5); }));
  rows.push_back(R("irradiance_cube_of_radiance_near_flt_max",
                   "irradiance --env {d}/huge.hdr --source-size 8 --cube 4 --pixel f32 --quiet -o {d}/c.ktx2 --sh-json "
                   "{d}/sh.json",
                   0)
                     .file("huge.hdr", huge)
                     .lacks("sh.json", "null")
                     .lines(0)
                     .output([](const fs::path& d) {
                       expect_constant_cube(d, "c.ktx2", 1, 4, brdfbake::test::kEnvIrradianceDevice);
                       expect_constant_sh(d, "sh.json", 3);
                     }));
  rows.push_back(
      R("prefilter_of_radiance_near_flt_max",
        "prefilter --env {d}/huge.hdr --size 8 --min-size 4 --pixel f32 --quiet -o {d}/p.ktx2", 0)
          .file("huge.hdr", huge)
          .lines(0)
          .output([](const fs::path& d) { expect_constant_cube(d, "p.ktx2", 2, 8, brdfbake::test::kEnvFurnace); }));
  rows.push_back(R("job_sh_of_radiance_near_flt_max", "run {d}/job.json -o {d}/out --quiet", 0)
                     .file("huge.hdr", huge)
                     .file("job.json", job(R"({"kind": "irradiance", "source_size": 8, "output": "sh.json"})",
                                           R"(, "environment": "huge.hdr")"))
                     .lines(0)
                     .output([](const fs::path& d) { expect_constant_sh(d, "out/sh.json", 3); }));
  // NaN and infinite radiance: refused, or replaced and recorded with --sanitize.
  const std::string nan_cube = ktx2_cube(4, 1.0f, 5, NAN), inf_cube = ktx2_cube(4, 1.0f, 3, INFINITY);
  rows.push_back(R("prefilter_nan_env_refused", "prefilter --env {d}/e.ktx2 --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                     .file("e.ktx2", nan_cube)
                     .says("5 NaN")
                     .says("--sanitize")
                     .no("p.ktx2"));
  rows.push_back(R("prefilter_inf_env_refused", "prefilter --env {d}/e.ktx2 --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                     .file("e.ktx2", inf_cube)
                     .says("3 infinite")
                     .no("p.ktx2"));
  rows.push_back(
      R("prefilter_negative_env_refused", "prefilter --env {d}/e.ktx2 --size 8 --min-size 4 -o {d}/p.ktx2", 2)
          .file("e.ktx2", ktx2_cube(4, 1.0f, 2, -4.0f))
          .says("2 negative")
          .no("p.ktx2"));
  rows.push_back(
      R("prefilter_nan_env_sanitized", "prefilter --env {d}/e.ktx2 --size 8 --min-size 4 --sanitize -o {d}/p.ktx2", 0)
          .file("e.ktx2", nan_cube)
          .says("replaced 5 NaN")
          .has("p.ktx2", "sanitized"));
  rows.push_back(
      R("irradiance_nan_env_sanitized", "irradiance --env {d}/e.ktx2 --source-size 8 --sanitize -o {d}/sh.json", 0)
          .file("e.ktx2", nan_cube)
          .says("replaced 5 NaN")
          .has("sh.json", "sanitized")
          .lacks("sh.json", "null"));
  rows.push_back(R("irradiance_inf_env_refused", "irradiance --env {d}/e.ktx2 --source-size 8 -o {d}/sh.json", 2)
                     .file("e.ktx2", inf_cube)
                     .says("infinite")
                     .no("sh.json"));
  rows.push_back(
      R("bake_nan_env_refused", "bake --env {d}/e.ktx2 --lut-size 4 --cube-size 8 --min-size 4 -o {d}/out --quiet", 2)
          .file("e.ktx2", nan_cube)
          .says("--sanitize")
          .no("out"));
  rows.push_back(R("run_nan_env_sanitized", "run {d}/job.json -o {d}/out --sanitize --quiet", 0)
                     .file("e.ktx2", nan_cube)
                     .file("job.json", job(R"({"kind": "irradiance", "source_size": 8, "output": "sh.json"})",
                                           R"(, "environment": "e.ktx2")"))
                     .has("out/manifest.json", "sanitized")
                     .lines(0));
  rows.push_back(R("run_nan_env_job_sanitize", "run {d}/job.json -o {d}/out --quiet", 0)
                     .file("e.ktx2", nan_cube)
                     .file("job.json", job(R"({"kind": "irradiance", "source_size": 8, "output": "sh.json"})",
                                           R"(, "environment": "e.ktx2", "sanitize": true)"))
                     .has("out/manifest.json", "sanitized")
                     .has("out/sh.json", "sanitized")
                     .lines(0));
  // Above 65504 in half floats: refused with the options that fix it, or clamped and recorded on request.
  const std::string sun = rgbe(16, 8, 1.0e5);
  rows.push_back(
      R("prefilter_f16_overflow_ktx2", "prefilter --env {d}/sun.hdr --size 8 --min-size 4 --pixel f16 -o {d}/p.ktx2", 2)
          .file("sun.hdr", sun)
          .says("65504")
          .says("--pixel f32")
          .no("p.ktx2"));
  rows.push_back(
      R("prefilter_f16_overflow_dds", "prefilter --env {d}/sun.hdr --size 8 --min-size 4 --pixel f16 -o {d}/p.dds", 2)
          .file("sun.hdr", sun)
          .says("65504")
          .no("p.dds"));
  rows.push_back(
      R("irradiance_f16_overflow_cube", "irradiance --env {d}/sun.hdr --source-size 8 --cube 4 -o {d}/c.ktx2", 2)
          .file("sun.hdr", sun)
          .says("65504")
          .no("c.ktx2"));
  // a Phong lobe of shininess 1e6 sampled 1e-4 rad from its peak: 152 098
  const std::string sharp =
      R"({"materials": [{"name": "a", "model": "phong", "shininess": 1000000, "specularColor": [1, 1, 1]}]})";
  rows.push_back(R("tabulate_f16_overflow_header",
                   "tabulate --material {d}/m.json --layout slice --res 64 --pixel f16 -o {d}/t.h", 2)
                     .file("m.json", sharp)
                     .says("65504")
                     .says("--clamp-f16")
                     .no("t.h"));
  rows.push_back(R("tabulate_f16_overflow_ktx2",
                   "tabulate --material {d}/m.json --layout slice --res 64 --pixel f16 -o {d}/t.ktx2", 2)
                     .file("m.json", sharp)
                     .says("65504")
                     .says("--pixel f32")
                     .no("t.ktx2"));
  rows.push_back(R("tabulate_f16_clamp_recorded",
                   "tabulate --material {d}/m.json --layout slice --res 64 --pixel f16 --clamp-f16 -o {d}/t.h", 0)
                     .file("m.json", sharp)
                     .says("warning: ")
                     .says("clamped to 65504")
                     .has("t.h", "f16_clamped")
                     .lines(2));
  rows.push_back(R("tabulate_f32_keeps_the_peak",
                   "tabulate --material {d}/m.json --layout slice --res 64 --pixel f32 --quiet -o {d}/t.h", 0)
                     .file("m.json", sharp)
                     .lacks("t.h", "clamped")
                     .lines(0));
  rows.push_back(R("prefilter_f16_clamp_recorded",
                   "prefilter --env {d}/sun.hdr --size 8 --min-size 4 --pixel f16 --clamp-f16 -o {d}/p.ktx2", 0)
                     .file("sun.hdr", sun)
                     .has("p.ktx2", "f16_clamped")
                     .says("warning: ")
                     .lines(2));
  rows.push_back(R("prefilter_f16_clamp_dds",
                   "prefilter --env {d}/sun.hdr --size 8 --min-size 4 --pixel f16 --clamp-f16 --quiet -o {d}/p.dds", 0)
                     .file("sun.hdr", sun)
                     .says("clamped to 65504"));
  rows.push_back(R("irradiance_f16_clamp_cube",
                   "irradiance --env {d}/sun.hdr --source-size 8 --cube 4 --clamp-f16 --quiet -o {d}/c.ktx2", 0)
                     .file("sun.hdr", sun)
                     .has("c.ktx2", "f16_clamped"));
  rows.push_back(R("prefilter_f32_no_clamp_needed",
                   "prefilter --env {d}/sun.hdr --size 8 --min-size 4 --pixel f32 --quiet -o {d}/p.ktx2", 0)
                     .file("sun.hdr", sun)
                     .lacks("p.ktx2", "clamped")
                     .lines(0));
  rows.push_back(R("bake_f16_overflow_refused",
                   "bake --env {d}/sun.hdr --lut-size 4 --cube-size 8 --min-size 4 -o {d}/out --quiet", 2)
                     .file("sun.hdr", sun)
                     .says("65504")
                     .says("--clamp-f16")
                     .no("out"));
  rows.push_back(R("bake_f16_clamp_in_manifest",
                   "bake --env {d}/sun.hdr --lut-size 4 --cube-size 8 --min-size 4 --clamp-f16 -o {d}/out --quiet", 0)
                     .file("sun.hdr", sun)
                     .has("out/manifest.json", "clamped to 65504")
                     .says("warning: "));
  rows.push_back(R("run_f16_overflow_refused", "run {d}/job.json -o {d}/out --quiet", 2)
                     .file("sun.hdr", sun)
                     .file("job.json",
                           job(R"({"kind": "prefilter", "size": 8, "min_size": 4, "pixel": "f16", "output": "p.ktx2"})",
                               R"(, "environment": "sun.hdr")"))
                     .says("65504")
                     .says("clamp_f16")
                     .no("out"));
  rows.push_back(
      R("run_f16_clamp_in_manifest", "run {d}/job.json -o {d}/out --quiet", 0)
          .file("sun.hdr", sun)
          .file(
              "job.json",
              job(R"({"kind": "prefilter", "size": 8, "min_size": 4, "pixel": "f16", "clamp_f16": true, "output": "p.ktx2"})",
                  R"(, "environment": "sun.hdr")"))
          .has("out/manifest.json", "clamped to 65504")
          .has("out/p.ktx2", "f16_clamped")
          .says("warning: "));
}

// -- Class 4: memory before validation: headers are checked against the file's length and the
// memory budget before any pixel buffer exists (the memory each run may take: kRowMemoryKiB).
void memory_before_validation(std::vector<Row>& rows) {
  rows.push_back(
      R("hdr_header_promises_16384x8192", "prefilter --env {d}/big.hdr --size 8 --min-size 4 -o {d}/p.ktx2", 2)
          .file("big.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8192 +X 16384\n")
          .says("promises 16384x8192")
          .says("truncated")
          .no("p.ktx2"));
  // The same without a device (SH runs on the host) in 512 MiB of address space: the 1.5 GiB the
  // header promises is never allocated (else: "out of memory", exit 1).
  rows.push_back(R("hdr_header_promises_in_512mib", "irradiance --env {d}/big.hdr -o {d}/sh.json", 2)
                     .file("big.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8192 +X 16384\n")
                     .says("truncated")
                     .no("sh.json")
                     .memory_cap_mib(512));
  rows.push_back(R("hdr_budget_in_512mib", "irradiance --env {d}/e.hdr --memory-budget 1KiB -o {d}/sh.json", 2)
                     .file("e.hdr", rgbe(64, 32, 1.0))
                     .says("memory budget")
                     .no("sh.json")
                     .memory_cap_mib(512));
  rows.push_back(R("hdr_small_in_512mib", "irradiance --env {d}/e.hdr --quiet -o {d}/sh.json", 0)
                     .file("e.hdr", rgbe(64, 32, 1.0))
                     .memory_cap_mib(512)
                     .lines(0));
  rows.push_back(R("webp_sniffed_13057x14338", "prefilter --env {d}/x.hdr --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                     .file("x.hdr", std::string("RIFF\x0c\0\0\0WEBPVP8L\x00\x00\x00\x00\x2f\x00\xc0\xff\x7f", 25))
                     .no("p.ktx2"));
  rows.push_back(
      R("memory_budget_option", "prefilter --env {d}/e.hdr --memory-budget 1KiB --size 8 --min-size 4 -o {d}/p.ktx2", 2)
          .file("e.hdr", rgbe(16, 8, 1.0))
          .says("memory budget")
          .says("--memory-budget")
          .no("p.ktx2"));
  rows.push_back(R("memory_budget_fits",
                   "prefilter --env {d}/e.hdr --memory-budget 2KiB --size 8 --min-size 4 --quiet -o {d}/p.ktx2", 0)
                     .file("e.hdr", rgbe(16, 8, 1.0))
                     .lines(0));
  rows.push_back(
      R("memory_budget_ktx2", "prefilter --env {d}/e.ktx2 --memory-budget 1KiB --size 4 --min-size 4 -o {d}/p.ktx2", 2)
          .file("e.ktx2", ktx2_cube(4, 1.0f))
          .says("memory budget")
          .no("p.ktx2"));
  rows.push_back(
      R("memory_budget_bake",
        "bake --env {d}/e.hdr --memory-budget 1KiB --lut-size 4 --cube-size 8 --min-size 4 -o {d}/out --quiet", 2)
          .file("e.hdr", rgbe(16, 8, 1.0))
          .says("memory budget")
          .no("out"));
  rows.push_back(R("memory_budget_run", "run {d}/job.json -o {d}/out --memory-budget 1KiB --quiet", 2)
                     .file("e.hdr", rgbe(16, 8, 1.0))
                     .file("job.json", job(R"({"kind": "irradiance", "source_size": 8, "output": "sh.json"})",
                                           R"(, "environment": "e.hdr")"))
                     .says("memory budget")
                     .no("out"));
  const std::pair<const char*, const char*> bad_sizes[] = {{"word", "lots"},    {"negative", "-1GiB"}, {"zero", "0"},
                                                           {"huge", "1e99TiB"}, {"unit", "5 parsecs"}, {"nan", "nan"}};
  for (const auto& [label, bad] : bad_sizes)
    rows.push_back(R(std::string("memory_budget_bad_") + label,
                     std::string("prefilter --env builtin:studio --memory-budget '") + bad +
                         "' --size 8 --min-size 4 -o {d}/p.ktx2",
                     2)
                       .says("--memory-budget")
                       .says("is not a size")
                       .no("p.ktx2"));
  // Containers whose headers promise more than the file holds are refused before allocation.
  std::string big = ktx2_cube(4, 1.0f);
  // pixelWidth/pixelHeight at bytes 20..27: claim 65536 x 65536
  big.replace(20, 8, le32(65536) + le32(65536));
  rows.push_back(R("ktx2_header_promises_65536", "prefilter --env {d}/e.ktx2 --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                     .file("e.ktx2", big)
                     .says("KTX2")
                     .no("p.ktx2"));
  rows.push_back(R("glb_header_promises_4gb", "bake --scene {d}/s.glb --dry-run", 2)
                     .file("s.glb", glb(kScene, 0xFFFFFFF0u))
                     .says("truncated GLB"));
  std::string chunk = glb(kScene);
  chunk.replace(12, 4, le32(0x7FFFFFF0u));
  rows.push_back(
      R("glb_json_chunk_promises_2gb", "bake --scene {d}/s.glb --dry-run", 2).file("s.glb", chunk).says("JSON chunk"));
}

// -- Class 5: out-of-range knobs, named as the user typed them, with the valid range.
void knobs(std::vector<Row>& rows) {
  struct K {
    const char* name;
    const char* args;
    std::vector<std::string> words;
  };
  const std::vector<K> ks = {
      {"lut_samples_1000000", "lut --samples 1000000", {"--samples", "32768"}},
      {"lut_samples_1e6", "lut --samples 1e6", {"--samples", "32768"}},
      {"lut_vndf_samples_int_max", "lut --estimator vndf --samples 2147483647", {"--samples", "2147483647"}},
      {"lut_vndf_work_bound", "lut --size 8192 --estimator vndf --samples 1000000", {"--samples", "2^40"}},
      {"lut_table_too_large", "lut --size 16384", {"--size", "67108864"}},
      {"lut_height_too_large", "lut --size 8 --height 100000", {"--height", "1..16384"}},
      {"lut_samples_and_max_error", "lut --samples 64 --max-error 0.01", {"--samples", "--max-error"}},
      {"lut_uniform_for_ggx", "lut --kind ggx --estimator uniform", {"uniform"}},
      {"lut_sheen_visibility_for_ggx", "lut --kind ggx --sheen-visibility neubelt", {"--sheen-visibility"}},
      {"lut_samples_negative_zero", "lut --samples -0", {"--samples"}},
      {"lut_samples_hex", "lut --samples 0x10p99", {"--samples"}},
      {"lut_samples_empty", "lut --samples ''", {"--samples"}},
      {"lut_size_missing_value", "lut --size", {"size"}},
      // --cube-size: the old name of --chain-size (an alias); messages name the option canonically
      {"bake_cube_size_5000", "bake --cube-size 5000", {"--chain-size", "1..2048"}},
      {"bake_min_size_above_cube_size", "bake --cube-size 16 --min-size 64", {"--min-size", "--chain-size"}},
      {"bake_chain_size_and_cube_size",
       "bake --chain-size 16 --cube-size 16",
       {"--chain-size", "--cube-size", "give one"}},
      {"bake_sh_4", "bake --sh 4", {"--sh"}},
      {"bake_json_without_dry_run", "bake --json", {"--json", "--dry-run"}},
      {"bake_pixel_f8", "bake --pixel f8", {"--pixel"}},
      // --size, --cube: old names (aliases) of --chain-size and --irradiance-size, named canonically
      {"prefilter_size_5000", "prefilter --size 5000", {"--chain-size", "1..2048"}},
      {"prefilter_samples_65537", "prefilter --estimator sampling --samples 65537", {"--samples", "65536"}},
      {"prefilter_samples_with_quadrature", "prefilter --samples 64", {"--samples", "--estimator sampling"}},
      {"prefilter_min_size_above_size", "prefilter --size 16 --min-size 32", {"--min-size", "--chain-size"}},
      {"prefilter_refinement_1", "prefilter --refinement 1", {"--refinement", "1.5..64"}},
      {"prefilter_clamp_zero", "prefilter --clamp 0", {"--clamp", "greater than 0"}},
      {"prefilter_layout_for_container", "prefilter --layout cross --size 8 --min-size 4 -o {d}/p.ktx2", {"--layout"}},
      {"prefilter_stdout", "prefilter --size 8 -o -", {"--format csv"}},
      {"irradiance_cube_5000", "irradiance --cube 5000 -o x.ktx2", {"--irradiance-size", "1..1024"}},
      {"irradiance_source_size_99999", "irradiance --source-size 99999", {"--source-size", "1..2048"}},
      {"irradiance_sh_4", "irradiance --sh 4", {"--sh", "3 or 5"}},
      {"irradiance_cube_for_json", "irradiance --cube 8 -o x.json", {"--irradiance-size", ".json"}},
      {"fresnel_size_1e9", "fresnel --model schlick --f0 0.04 --size 1e9", {"--size", "16777216"}},
      {"fresnel_2d_too_many_cells", "fresnel --model schlick --table 2d --size 8192 --height 8192", {"cells"}},
      {"fresnel_ior_1e999", "fresnel --model dielectric --ior 1e999", {"--ior"}},
      {"fresnel_f0_three_values_of_four", "fresnel --model schlick --f0 1,2,3,4", {"--f0"}},
      {"thin_film_size_1e6", "thin-film --base-ior 1.5 --size 1e6", {"--size", "1..8192"}},
      {"thin_film_thickness_negative", "thin-film --base-ior 1.5 --thickness-min -5", {"--thickness-min", "0..100000"}},
      {"thin_film_both_bases", "thin-film --base-ior 1.5 --base-f0 0.5", {"--base-ior", "--base-f0"}},
      {"tabulate_res_100000", "tabulate --material {d}/m.json --layout grid --res 100000", {"--res", "1..4096"}},
      {"tabulate_res_four_values", "tabulate --material {d}/m.json --layout grid --res 1,2,3,4", {"--res"}},
      {"tabulate_res_for_merl", "tabulate --material {d}/m.json --layout merl --res 8", {"--res", "merl"}},
      {"tabulate_phi_d_for_grid", "tabulate --material {d}/m.json --layout grid --phi-d 1", {"--phi-d"}},
      {"tabulate_layout_missing", "tabulate --material {d}/m.json", {"--layout"}},
      {"tabulate_grid_too_many_cells", "tabulate --material {d}/m.json --layout grid --res 4096", {"cells"}},
      {"eval_format_given", "eval --material {d}/m.json -i {d}/p.csv --format csv", {"format"}},
      {"eval_model_unknown", "eval --material {d}/m.json -i {d}/p.csv --model magic", {"--model"}},
  };
  for (const K& k : ks) {
    R row(k.name, std::string(k.args) + " -o {d}/out.exr", 2);
    // a command with its own -o keeps it (the first -o wins in cxxopts? no: refuse two): give none
    if (std::string(k.args).find(" -o ") != std::string::npos) row.r.args = k.args;
    for (const auto& w : k.words) row.says(w);
    row.file("m.json", kMaterials).file("p.csv", kPairs).no("out.exr");
    rows.push_back(row);
  }
  rows.push_back(R("fresnel_list_materials_with_size", "fresnel --list-materials --size 8", 2).says("--size"));
  rows.push_back(R("unknown_command", "bakery", 2).says("unknown command"));
  rows.push_back(R("no_command", "", 2).says("usage").lines(25));
  rows.push_back(R("stray_argument", "lut --size 8 stray -o {d}/t.exr", 2).says("stray").no("t.exr"));
  rows.push_back(R("devices_unknown_option", "devices --bogus", 2).says("bogus"));
  rows.push_back(R("kinds_unknown_option", "kinds --bogus", 2).says("bogus"));
  rows.push_back(R("run_without_job", "run", 2).says("missing the job file"));
  rows.push_back(R("run_without_output", "run {d}/job.json", 2).file("job.json", job(kLut)).says("-o DIR"));
  rows.push_back(
      R("device_unknown", "lut --size 4 --device no-such-device -o {d}/t.exr", 2).says("no-such-device").no("t.exr"));
  rows.push_back(R("device_index_unknown", "lut --size 4 --device 9:9 -o {d}/t.exr", 2).says("9:9").no("t.exr"));
  rows.push_back(R("precision_fp16", "lut --size 4 --precision fp16 -o {d}/t.exr", 2).says("fp16").no("t.exr"));
}

// -- Class 6: misleading messages: folders, missing and unreadable files, malformed ones.
void messages(std::vector<Row>& rows) {
  rows.push_back(R("job_is_a_folder", "run {d}/dir -o {d}/out", 2).file("dir/x", "").says("it is a folder").no("out"));
  rows.push_back(R("job_missing", "run {d}/none.json -o {d}/out", 2).says("no such file").no("out"));
  rows.push_back(R("scene_is_a_folder", "bake --scene {d}/dir --dry-run", 2).file("dir/x", "").says("it is a folder"));
  rows.push_back(
      R("scene_glb_is_a_folder", "bake --scene {d}/dir.glb --dry-run", 2).file("dir.glb/x", "").says("it is a folder"));
  rows.push_back(R("scene_missing", "bake --scene {d}/none.gltf --dry-run", 2).says("no such file"));
  rows.push_back(R("material_is_a_folder", "eval --material {d}/dir -i {d}/p.csv -o {d}/f.csv", 2)
                     .file("dir/x", "")
                     .file("p.csv", kPairs)
                     .says("it is a folder")
                     .no("f.csv"));
  rows.push_back(R("material_missing", "tabulate --material {d}/none.json --layout grid -o {d}/t.exr", 2)
                     .says("no such file")
                     .no("t.exr"));
  rows.push_back(R("eval_input_is_a_folder", "eval --material {d}/m.json -i {d}/dir -o {d}/f.csv", 2)
                     .file("m.json", kMaterials)
                     .file("dir/x", "")
                     .says("it is a folder")
                     .no("f.csv"));
  rows.push_back(R("eval_input_missing", "eval --material {d}/m.json -i {d}/none.csv -o {d}/f.csv", 2)
                     .file("m.json", kMaterials)
                     .says("No such file")
                     .no("f.csv"));
  rows.push_back(R("env_is_a_folder", "prefilter --env {d}/dir --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                     .file("dir/x", "")
                     .says("it is a folder")
                     .no("p.ktx2"));
  rows.push_back(R("env_ktx2_is_a_folder", "prefilter --env {d}/dir.ktx2 --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                     .file("dir.ktx2/x", "")
                     .says("folder")
                     .no("p.ktx2"));
  rows.push_back(
      R("env_missing", "irradiance --env {d}/none.hdr -o {d}/sh.json", 2).says("no such file").no("sh.json"));
  rows.push_back(
      R("env_missing_in_bake", "bake --env {d}/none.hdr -o {d}/out --quiet", 2).says("no such file").no("out"));
  rows.push_back(R("env_builtin_unknown", "prefilter --env builtin:moon --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                     .says("builtin:moon")
                     .no("p.ktx2"));
  rows.push_back(R("env_empty", "prefilter --env '' -o {d}/p.ktx2", 2).says("--env").no("p.ktx2"));
  rows.push_back(R("env_five_faces", "prefilter --env a,b,c,d,e -o {d}/p.ktx2", 2).says("six files").no("p.ktx2"));
  rows.push_back(
      R("env_face_pattern_missing", "prefilter --env {d}/f_{face}.hdr --size 8 --min-size 4 -o {d}/p.ktx2", 2)
          .says("f_px.hdr")
          .no("p.ktx2"));
  rows.push_back(R("env_faces_not_square", "prefilter --env {d}/f_{face}.hdr --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                     .file("f_px.hdr", rgbe(8, 4, 1))
                     .file("f_nx.hdr", rgbe(8, 4, 1))
                     .file("f_py.hdr", rgbe(8, 4, 1))
                     .file("f_ny.hdr", rgbe(8, 4, 1))
                     .file("f_pz.hdr", rgbe(8, 4, 1))
                     .file("f_nz.hdr", rgbe(8, 4, 1))
                     .says("square")
                     .no("p.ktx2"));
  rows.push_back(R("env_faces_of_two_sizes", "prefilter --env {d}/f_{face}.hdr --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                     .file("f_px.hdr", rgbe(8, 8, 1))
                     .file("f_nx.hdr", rgbe(4, 4, 1))
                     .file("f_py.hdr", rgbe(8, 8, 1))
                     .file("f_ny.hdr", rgbe(8, 8, 1))
                     .file("f_pz.hdr", rgbe(8, 8, 1))
                     .file("f_nz.hdr", rgbe(8, 8, 1))
                     .says("f_nx.hdr")
                     .no("p.ktx2"));
  rows.push_back(R("env_aspect_3_to_1", "prefilter --env {d}/e.hdr --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                     .file("e.hdr", rgbe(24, 8, 1))
                     .says("24x8")
                     .no("p.ktx2"));
  rows.push_back(R("env_hdr_truncated", "prefilter --env {d}/e.hdr --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                     .file("e.hdr", rgbe(16, 8, 1).substr(0, 100))
                     .says("e.hdr")
                     .no("p.ktx2"));
  rows.push_back(R("env_hdr_garbage", "prefilter --env {d}/e.hdr --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                     .file("e.hdr", "this is not an image at all\n")
                     .says("e.hdr")
                     .no("p.ktx2"));
  rows.push_back(R("env_empty_file", "prefilter --env {d}/e.exr --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                     .file("e.exr", "")
                     .says("e.exr")
                     .no("p.ktx2"));
  rows.push_back(R("env_unreadable", "prefilter --env {d}/e.hdr --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                     .file("e.hdr", rgbe(16, 8, 1))
                     .says("ermission denied")
                     .no("p.ktx2")
                     .root_skip());
  std::string ktx = ktx2_cube(4, 1.0f);
  rows.push_back(R("env_ktx2_truncated", "prefilter --env {d}/e.ktx2 --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                     .file("e.ktx2", ktx.substr(0, ktx.size() - 17))
                     .says("KTX2")
                     .no("p.ktx2"));
  rows.push_back(R("env_ktx2_bad_identifier", "prefilter --env {d}/e.ktx2 --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                     .file("e.ktx2", "KTX 11" + ktx.substr(6))
                     .says("KTX2")
                     .no("p.ktx2"));
  rows.push_back(R("env_ktx2_header_only", "prefilter --env {d}/e.ktx2 --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                     .file("e.ktx2", ktx.substr(0, 40))
                     .says("KTX2")
                     .no("p.ktx2"));
  {
    std::string one_face = ktx;
    one_face.replace(36, 4, le32(1));  // faceCount
    rows.push_back(R("env_ktx2_face_count_1", "prefilter --env {d}/e.ktx2 --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                       .file("e.ktx2", one_face)
                       .says("e.ktx2")
                       .no("p.ktx2"));
    std::string format = ktx;
    format.replace(12, 4, le32(37));  // vkFormat R8G8B8A8_UNORM
    rows.push_back(R("env_ktx2_format_unsupported", "prefilter --env {d}/e.ktx2 --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                       .file("e.ktx2", format)
                       .says("vkFormat")
                       .no("p.ktx2"));
    std::string levels = ktx;
    levels.replace(40, 4, le32(0xFFFFFFFFu));  // levelCount
    rows.push_back(R("env_ktx2_level_count_huge", "prefilter --env {d}/e.ktx2 --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                       .file("e.ktx2", levels)
                       .says("levelCount")
                       .no("p.ktx2"));
  }
  rows.push_back(R("scene_glb_truncated", "bake --scene {d}/s.glb --dry-run", 2)
                     .file("s.glb", glb(kScene).substr(0, 30))
                     .says("GLB"));
  rows.push_back(
      R("scene_glb_short", "bake --scene {d}/s.glb --dry-run", 2).file("s.glb", "glTF").says("truncated GLB"));
  rows.push_back(R("scene_glb_version_1", "bake --scene {d}/s.glb --dry-run", 2)
                     .file("s.glb", glb(kScene, 0, 1))
                     .says("version 1"));
  rows.push_back(R("scene_glb_not_json", "bake --scene {d}/s.glb --dry-run", 2)
                     .file("s.glb", glb("not json"))
                     .says("malformed JSON"));
  rows.push_back(R("scene_glb_bad_magic", "bake --scene {d}/s.glb --dry-run", 2)
                     .file("s.glb", "GLTF" + glb(kScene).substr(4))
                     .says("not a binary glTF"));
  {
    std::string bin = glb(kScene);
    bin += le32(64) + "BIN" + std::string(1, '\0') + std::string(8, '\0');  // a chunk promising 64 bytes, holding 8
    bin.replace(8, 4, le32(static_cast<uint32_t>(bin.size())));
    rows.push_back(R("scene_glb_bin_chunk_truncated", "bake --scene {d}/s.glb --dry-run", 2)
                       .file("s.glb", bin)
                       .says("truncated GLB"));
  }
  rows.push_back(R("scene_gltf_not_json", "bake --scene {d}/s.gltf --dry-run", 2)
                     .file("s.gltf", "{\"asset\": ")
                     .says("malformed JSON"));
  rows.push_back(
      R("scene_gltf_empty", "bake --scene {d}/s.gltf --dry-run", 2).file("s.gltf", "").says("malformed JSON"));
  rows.push_back(R("scene_unreadable", "bake --scene {d}/s.gltf --dry-run", 2)
                     .file("s.gltf", kScene)
                     .says("ermission denied")
                     .root_skip());
  rows.push_back(R("job_unreadable", "run {d}/job.json -o {d}/out", 2)
                     .file("job.json", job(kLut))
                     .says("ermission denied")
                     .root_skip());
}

// -- Class 7: outputs and faults: I/O failures exit 1, nothing partial, existing outputs kept,
// stale temporaries removed, one run per folder.
void outputs(std::vector<Row>& rows) {
  // A path through a regular file cannot be written, even by root.
  struct O {
    const char* name;
    std::string args;
  };
  const std::vector<O> io = {
      {"lut_through_a_file", "lut --size 4 -o {d}/plain/t.exr"},
      {"fresnel_through_a_file", "fresnel --model schlick --f0 0.04 --size 4 -o {d}/plain/f.csv"},
      {"thin_film_through_a_file", "thin-film --base-ior 1.5 --size 4 -o {d}/plain/t.exr"},
      {"tabulate_merl_through_a_file", "tabulate --material {d}/m.json --layout merl -o {d}/plain/t.binary"},
      {"tabulate_grid_through_a_file", "tabulate --material {d}/m.json --layout grid --res 4 -o {d}/plain/t.exr"},
      {"eval_through_a_file", "eval --material {d}/m.json -i {d}/p.csv -o {d}/plain/f.csv"},
      {"prefilter_folder_through_a_file", "prefilter --env {d}/e.hdr --size 8 --min-size 4 -o {d}/plain/dir/"},
      {"prefilter_ktx2_through_a_file", "prefilter --env {d}/e.hdr --size 8 --min-size 4 -o {d}/plain/p.ktx2"},
      {"irradiance_through_a_file", "irradiance --env {d}/e.hdr --source-size 8 -o {d}/plain/sh.json"},
      {"run_through_a_file", "run {d}/job.json -o {d}/plain/out"},
      {"bake_through_a_file", "bake --lut-size 4 --env {d}/e.hdr -o {d}/plain/out"},
      {"run_output_is_a_file", "run {d}/job.json -o {d}/plain"},
  };
  for (const O& o : io)
    rows.push_back(R(o.name, o.args + " --quiet", 1)
                       .file("plain", "a file")
                       .file("m.json", kMaterials)
                       .file("p.csv", kPairs)
                       .file("e.hdr", rgbe(16, 8, 1.0))
                       .file("job.json", job(kLut))
                       .says("cannot write")
                       .keeps("plain"));
  rows.push_back(R("eval_stdout_full", "eval --material {d}/m.json -i {d}/p.csv -o - >/dev/full", 1)
                     .file("m.json", kMaterials)
                     .file("p.csv", kPairs)
                     .says("cannot write 'standard output'"));
  rows.push_back(R("lut_stdout_csv", "lut --size 2 --format csv -o - --quiet", 0).lines(0));
  // A failure keeps what was there.
  rows.push_back(R("failed_lut_keeps_old_file", "lut --size 0 -o {d}/t.exr", 2)
                     .file("t.exr", "old")
                     .keeps("t.exr")
                     .says("--size"));
  rows.push_back(R("failed_run_keeps_old_folder", "run {d}/job.json -o {d}/out", 2)
                     .file("out/manifest.json", "old")
                     .file("job.json", job(R"({"kind": "ggx", "size": -1})"))
                     .keeps("out/manifest.json")
                     .says("tables[0].size"));
  rows.push_back(R("irradiance_cube_failure_keeps_sh_json",
                   "irradiance --env {d}/e.hdr --source-size 8 --cube 4 --sh-json {d}/sh.json -o {d}/plain/c.ktx2", 1)
                     .file("plain", "a file")
                     .file("sh.json", "old")
                     .file("e.hdr", rgbe(16, 8, 1.0))
                     .keeps("sh.json")
                     .says("cannot write"));
  rows.push_back(R("run_nan_env_keeps_old_folder", "run {d}/job.json -o {d}/out", 2)
                     .file("out/manifest.json", "old")
                     .file("e.ktx2", ktx2_cube(4, 1.0f, 1, NAN))
                     .file("job.json", job(R"({"kind": "irradiance", "source_size": 8, "output": "sh.json"})",
                                           R"(, "environment": "e.ktx2")"))
                     .keeps("out/manifest.json")
                     .says("NaN")
                     .no("out/sh.json"));
  // Temporaries of killed runs are removed by the next run into that folder; a live process's stay.
  rows.push_back(R("run_removes_stale_staging_folder", "run {d}/job.json -o {d}/out --quiet", 0)
                     .file("job.json", job(kLut))
                     .file(".out.tmp-{deadpid}-12345/t.exr", "partial")
                     .no(".out.tmp-{deadpid}-12345")
                     .lines(0));
  rows.push_back(R("run_keeps_live_staging_folder", "run {d}/job.json -o {d}/out --quiet", 0)
                     .file("job.json", job(kLut))
                     .file(".out.tmp-{livepid}-1/t.exr", "partial")
                     .allow_tmp(".out.tmp-{livepid}-1")
                     .lines(0));
  rows.push_back(R("lut_removes_stale_temporary_file", "lut --size 4 --quiet -o {d}/t.exr", 0)
                     .file(".t.exr.tmp-{deadpid}-00ff00ff00ff00ff", "partial")
                     .no(".t.exr.tmp-{deadpid}-00ff00ff00ff00ff")
                     .lines(0));
  rows.push_back(
      R("prefilter_removes_stale_folder", "prefilter --env {d}/e.hdr --size 8 --min-size 4 --quiet -o {d}/cube/", 0)
          .file("e.hdr", rgbe(16, 8, 1.0))
          .file(".cube.tmp-{deadpid}-7/level_0_px.exr", "partial")
          .no(".cube.tmp-{deadpid}-7")
          .lines(0));
  rows.push_back(R("bake_dry_run_touches_nothing", "bake --dry-run --json -o {d}/out", 0)
                     .file(".out.tmp-{deadpid}-7/x", "partial")
                     .allow_tmp(".out.tmp-{deadpid}-7")
                     .lines(50));
  // One run per folder: a second fails at once naming the first, or waits with --wait.
  rows.push_back(R("run_into_locked_folder", "run {d}/job.json -o {d}/out --quiet", 1)
                     .file("job.json", job(kLut))
                     .lock("out")
                     .says("being written by another brdfbake run (pid")
                     .says("--wait")
                     .no("out"));
  rows.push_back(R("bake_into_locked_folder", "bake --lut-size 4 -o {d}/out --quiet", 1)
                     .lock("out")
                     .says("being written by")
                     .no("out"));
  rows.push_back(
      R("prefilter_into_locked_folder", "prefilter --env {d}/e.hdr --size 8 --min-size 4 --quiet -o {d}/cube/", 1)
          .file("e.hdr", rgbe(16, 8, 1.0))
          .lock("cube")
          .says("being written by")
          .no("cube"));
  rows.push_back(R("run_waits_for_locked_folder", "run {d}/job.json -o {d}/out --wait --quiet", 0)
                     .file("job.json", job(kLut))
                     .lock("out", 1500)
                     .has("out/manifest.json", "t.exr")
                     .lines(0));
  rows.push_back(R("run_waits_and_says_so", "run {d}/job.json -o {d}/out --wait", 0)
                     .file("job.json", job(kLut))
                     .lock("out", 800)
                     .says("waiting for another brdfbake run")
                     .lines(5));
  rows.push_back(R("lock_left_by_dead_process", "run {d}/job.json -o {d}/out --quiet", 0)
                     .file("job.json", job(kLut))
                     .file(".out.lock", "999999999\n")
                     .has("out/manifest.json", "t.exr")
                     .lines(0));
  // Kinds this build is told to lack: exit 1 before anything is written.
  rows.push_back(R("run_kind_not_available", "run {d}/job.json -o {d}/out", 1)
                     .file("job.json", job(kLut))
                     .env("BRDFBAKE_UNAVAILABLE_KINDS=ggx")
                     .says("not available")
                     .no("out"));
}

// -- Class 8: eval's input streams.
void eval_streams(std::vector<Row>& rows) {
  struct E {
    const char* name;
    std::string input;
    const char* words;
    int code;
  };
  const std::string h = "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n";
  const std::vector<E> es = {
      {"csv_empty", "", "empty input", 2},
      {"csv_comments_only", "# nothing\n\n", "empty input", 2},
      {"csv_no_header", "0,0,1,0,0,1\n", "expected the header", 2},
      {"csv_wrong_header", "a,b,c,d,e,f\n", "expected the header", 2},
      {"csv_five_fields", h + "0,0,1,0,0\n", "line 2", 2},
      {"csv_seven_fields", h + "0,0,1,0,0,1,7\n", "line 2", 2},
      {"csv_nan", h + "nan,0,1,0,0,1\n", "wi_x", 2},
      {"csv_inf", h + "0,inf,1,0,0,1\n", "wi_y", 2},
      {"csv_1e999", h + "0,0,1e999,0,0,1\n", "wi_z", 2},
      {"csv_text", h + "0,0,1,x,0,1\n", "wo_x", 2},
      {"csv_empty_field", h + "0,0,1,,0,1\n", "wo_x", 2},
      {"csv_zero_wi", h + "0,0,0,0,0,1\n", "wi is the zero vector", 2},
      {"csv_zero_wo", h + "0,0,1,0,0,0\n", "wo is the zero vector", 2},
      {"csv_long_line", h + repeat("1", 100000) + "\n", "line 2", 2},
      {"csv_nul_bytes", h + std::string("0,0,1,0\0,0,1\n", 13), "line 2", 2},
      {"csv_crlf", "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\r\n0,0,1,0,0,1\r\n", "", 0},
      {"csv_header_only", h, "", 0},
      {"csv_below_horizon", h + "0,0,-1,0,0,1\n", "", 0},
  };
  for (const E& e : es) {
    R row(std::string("eval_") + e.name, "eval --material {d}/m.json -i - -o {d}/f.csv --quiet", e.code);
    row.file("m.json", kMaterials).stdin_(e.input);
    if (e.code)
      row.says(e.words).no("f.csv");
    else
      row.has("f.csv", "r,g,b").lines(0);
    rows.push_back(row);
  }
  struct B {
    const char* name;
    std::string input;
    const char* words;
    int code;
  };
  const std::vector<B> bs = {
      {"binary_empty", "", "", 0},
      {"binary_25_bytes", floats({0, 0, 1, 0, 0, 1}) + "x", "not a whole number of pairs", 2},
      {"binary_nan", floats({NAN, 0, 1, 0, 0, 1}), "pair 0", 2},
      {"binary_inf", floats({0, 0, 1, 0, INFINITY, 1}), "wo", 2},
      {"binary_zero", floats({0, 0, 0, 0, 0, 1}), "wi", 2},
      {"binary_one_pair", floats({0, 0, 1, 0, 0, 1}), "", 0},
  };
  for (const B& b : bs) {
    R row(std::string("eval_") + b.name, "eval --material {d}/m.json --binary -i {d}/p.f32 -o {d}/f.f32 --quiet",
          b.code);
    row.file("m.json", kMaterials).file("p.f32", b.input);
    if (b.code)
      row.says(b.words).no("f.f32");
    else
      row.lines(0);
    rows.push_back(row);
  }
  rows.push_back(R("eval_stdin_binary_truncated", "eval --material {d}/m.json --binary -i - -o - --quiet", 2)
                     .file("m.json", kMaterials)
                     .stdin_(std::string(7, '\1'))
                     .says("not a whole number"));
  rows.push_back(
      R("eval_in_job_bad_input", "run {d}/job.json -o {d}/out --quiet", 2)
          .file("m.json", kMaterials)
          .file("p.csv", "wi_x\n")
          .file("job.json", job(R"({"kind": "eval", "material": "m.json", "input": "p.csv", "output": "f.csv"})"))
          .says("expected the header")
          .no("out"));
}

// -- Class 9: device limits and faults, through the test switch BRDFBAKE_DEVICE_LIMITS.
void device_limits(std::vector<Row>& rows) {
  rows.push_back(R("fp64_on_device_without_it", "lut --size 4 --precision fp64 -o {d}/t.exr", 2)
                     .env("BRDFBAKE_DEVICE_LIMITS=fp64=0")
                     .says("no fp64 support")
                     .says("device '")
                     .no("t.exr"));
  rows.push_back(
      R("fp64_on_device_without_it_before_env", "prefilter --env {d}/e.ktx2 --precision fp64 -o {d}/p.ktx2", 2)
          .file("e.ktx2", ktx2_cube(4, 1.0f, 1, NAN))  // the device is refused before the file is read
          .env("BRDFBAKE_DEVICE_LIMITS=fp64=0")
          .says("no fp64 support")
          .no("p.ktx2"));
  rows.push_back(R("fp64_job_on_device_without_it", "run {d}/job.json -o {d}/out", 2)
                     .file("job.json", job(kLut, R"(, "precision": "fp64")"))
                     .env("BRDFBAKE_DEVICE_LIMITS=fp64=0")
                     .says("no fp64 support")
                     .no("out"));
  rows.push_back(R("max_alloc_too_small", "lut --size 64 -o {d}/t.exr", 1)
                     .env("BRDFBAKE_DEVICE_LIMITS=max_alloc=1024")
                     .says("CL_DEVICE_MAX_MEM_ALLOC_SIZE")
                     .no("t.exr"));
  rows.push_back(R("global_memory_too_small", "prefilter --env {d}/e.hdr --size 64 --min-size 4 -o {d}/p.ktx2", 1)
                     .file("e.hdr", rgbe(16, 8, 1.0))
                     .env("BRDFBAKE_DEVICE_LIMITS=global_memory=65536")
                     .says("CL_DEVICE_GLOBAL_MEM_SIZE")
                     .no("p.ktx2"));
  // No kernel launches fixed work-groups since SH moved to the host: a device with tiny work-groups
  // still bakes (check_work_group stays, tested by DeviceLimits.*).
  rows.push_back(
      R("work_group_small_device_still_bakes", "irradiance --env {d}/e.hdr --source-size 8 --cube 4 -o {d}/c.ktx2", 0)
          .file("e.hdr", rgbe(16, 8, 1.0))
          .env("BRDFBAKE_DEVICE_LIMITS=max_work_group_size=16")
          .has("c.ktx2", "irradiance"));
  rows.push_back(R("no_device_at_all", "lut --size 4 -o {d}/t.exr", 1)
                     .env("OCL_ICD_VENDORS=/nonexistent OCL_ICD_FILENAMES=/nonexistent")
                     .says("no OpenCL device")
                     .no("t.exr"));
  rows.push_back(R("reference_prefilter_refused",
                   "prefilter --env {d}/e.hdr --device reference --size 128 --min-size 4 -o {d}/p.ktx2", 2)
                     .file("e.hdr", rgbe(16, 8, 1.0))
                     .says("reference")
                     .no("p.ktx2"));
}

// -- Issue 24, special files as inputs and outputs: a device, a FIFO or standard output named as a
// file is streamed where the option streams (CSV tables, eval, documents) and refused elsewhere,
// without blocking and without replacing it; every read is bounded and a stop ends it; no output
// is the same file as an input, by device and inode.

// A PNG (8 or 16-bit RGB, every sample `value`) with the chunks given (type, data) before the image
// data; zlib's stored blocks, so that no compressor is needed.
uint32_t crc32_of(const std::string& bytes) {
  uint32_t c = 0xFFFFFFFFu;
  for (char ch : bytes) {
    c ^= static_cast<unsigned char>(ch);
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return ~c;
}
std::string be32(uint32_t v) {
  return std::string{char(v >> 24), char((v >> 16) & 0xFF), char((v >> 8) & 0xFF), char(v & 0xFF)};
}
std::string png_chunk(const std::string& type, const std::string& data) {
  return be32(uint32_t(data.size())) + type + data + be32(crc32_of(type + data));
}
std::string zlib_stored(const std::string& raw) {
  std::string z = "\x78\x01";
  uint32_t a = 1, b = 0;
  for (char ch : raw) {
    a = (a + static_cast<unsigned char>(ch)) % 65521u;
    b = (b + a) % 65521u;
  }
  for (size_t at = 0; at < raw.size() || at == 0; at += 65535) {
    const size_t n = std::min<size_t>(65535, raw.size() - at);
    const bool last = at + n >= raw.size();
    z += char(last ? 1 : 0);
    z += char(n & 0xFF);
    z += char(n >> 8);
    z += char(~n & 0xFF);
    z += char((~n >> 8) & 0xFF);
    z += raw.substr(at, n);
    if (raw.empty()) break;
  }
  return z + be32((b << 16) | a);
}
std::string png(int w, int h, int value, const std::vector<std::pair<std::string, std::string>>& chunks = {},
                int depth = 8, uint32_t ihdr_w = 0) {
  std::string raw;
  for (int y = 0; y < h; ++y) {
    raw += '\0';
    for (int k = 0; k < 3 * w; ++k) {
      if (depth == 16) raw += char(value >> 8);
      raw += char(value & 0xFF);
    }
  }
  std::string out = "\x89PNG\r\n\x1a\n" +
                    png_chunk("IHDR", be32(ihdr_w ? ihdr_w : uint32_t(w)) + be32(ihdr_w ? ihdr_w : uint32_t(h)) +
                                          std::string{char(depth), 2, 0, 0, 0});
  for (const auto& [type, data] : chunks) out += png_chunk(type, data);
  return out + png_chunk("IDAT", zlib_stored(raw)) + png_chunk("IEND", "");
}
// A minimal RGB display ICC profile (a header and an empty tag table) named `name` in an iCCP chunk.
std::pair<std::string, std::string> iccp(const std::string& name) {
  std::string profile(132, '\0');
  profile.replace(0, 4, be32(132));
  profile.replace(8, 4, be32(0x04300000u));  // version 4.3
  profile.replace(12, 4, "mntr");
  profile.replace(16, 4, "RGB ");
  profile.replace(20, 4, "XYZ ");
  profile.replace(36, 4, "acsp");
  profile.replace(68, 12, be32(0x0000F6D6u) + be32(0x00010000u) + be32(0x0000D32Du));  // D50
  return {"iCCP", name + std::string(1, '\0') + std::string(1, '\0') + zlib_stored(profile)};
}
// A one-channel OpenEXR image named `channel` (written by OpenImageIO).
std::string exr_with_channels(const std::vector<std::string>& names) {
  const fs::path p = brdfbake::test::test_temp_root() / "channels.exr";
  auto out = OIIO::ImageOutput::create(p.string());
  OIIO::ImageSpec spec(16, 8, int(names.size()), OIIO::TypeDesc::FLOAT);
  spec.channelnames = names;
  spec.alpha_channel = -1;
  std::vector<float> px(16 * 8 * names.size(), 0.5f);
  if (!out || !out->open(p.string(), spec) || !out->write_image(OIIO::TypeDesc::FLOAT, px.data())) return "";
  out->close();
  std::ifstream in(p, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  fs::remove(p);
  return bytes.str();
}

void special_files(std::vector<Row>& rows) {
  const std::string e = rgbe(16, 8, 1.0);
  // Outputs that are devices, FIFOs or standard output: streamed (CSV), or refused, never replaced.
  // The devices are named through links in the row's folder ({d}/null -> /dev/null, {d}/so ->
  // /dev/stdout): what a path names is decided by what it leads to, and a build that still renames
  // over its output replaces the link in the row's folder, not the machine's device (run as root,
  // main's build of 2026-11-27 replaced /dev/null and /dev/stdout themselves with regular files).
  const std::string links = "ln -s /dev/null null && ln -s /dev/stdout so";
  rows.push_back(R("special_lut_exr_to_dev_null", "lut --size 4 --format exr -o {d}/null", 2)
                     .setup(links)
                     .says("character device")
                     .says("regular file")
                     .still_link("null"));
  rows.push_back(R("special_lut_csv_to_dev_null", "lut --size 2 --format csv -o {d}/null --quiet", 0)
                     .setup(links)
                     .lines(0)
                     .still_link("null"));
  rows.push_back(R("special_lut_exr_to_fifo", "lut --size 4 --format exr -o {d}/ff", 2)
                     .setup("mkfifo ff")
                     .says("FIFO")
                     .still_fifo("ff"));
  rows.push_back(R("special_lut_csv_to_fifo", "", 0)
                     .setup("mkfifo ff")
                     .script("timeout 20 cat ff > got.csv & {cli} lut --size 2 --format csv -o {d}/ff --quiet 2>{err}; "
                             "echo $? >{status}; wait")
                     .has("got.csv", "# kind: ggx")
                     .still_fifo("ff")
                     .lines(0));
  rows.push_back(R("special_lut_csv_to_dev_stdout_file", "", 0)
                     .setup(links)
                     .script("{cli} lut --size 2 --format csv -o {d}/so --quiet 2>{err} >{d}/out.csv")
                     .has("out.csv", "# kind: ggx")
                     .lines(0)
                     .still_link("so"));
  rows.push_back(R("special_lut_exr_to_dev_stdout", "", 2)
                     .setup(links)
                     .script("{cli} lut --size 4 --format exr -o {d}/so 2>{err} >{d}/out.exr")
                     .says("open file descriptor")
                     .says("regular file")
                     .still_link("so"));
  rows.push_back(R("special_eval_to_fifo", "", 0)
                     .setup("mkfifo ff")
                     .file("m.json", kMaterials)
                     .file("p.csv", kPairs)
                     .script("timeout 20 cat ff > got.csv & {cli} eval --material {d}/m.json -i {d}/p.csv -o {d}/ff "
                             "--quiet 2>{err}; echo $? >{status}; wait")
                     .has("got.csv", "r,g,b")
                     .still_fifo("ff")
                     .lines(0));
  rows.push_back(R("special_sh_json_to_dev_null",
                   "irradiance --env {d}/e.hdr --source-size 8 --cube 4 -o {d}/c.ktx2 --sh-json {d}/null", 2)
                     .setup(links)
                     .file("e.hdr", e)
                     .says("--sh-json")
                     .says("character device")
                     .no("c.ktx2")
                     .still_link("null"));
  rows.push_back(R("special_irradiance_json_to_fifo", "irradiance --env {d}/e.hdr --source-size 8 -o {d}/sh.json", 2)
                     .setup("mkfifo sh.json")
                     .file("e.hdr", e)
                     .says("FIFO")
                     .still_fifo("sh.json"));
  rows.push_back(
      R("special_prefilter_folder_to_dev_null", "prefilter --env {d}/e.hdr --size 8 --min-size 4 -o {d}/null", 2)
          .setup(links)
          .file("e.hdr", e)
          .says("character device")
          .still_link("null"));
  rows.push_back(R("special_bake_to_dev_null", "bake --lut-size 4 -o {d}/null --quiet", 2)
                     .setup(links)
                     .says("character device")
                     .still_link("null"));
  rows.push_back(R("special_run_to_dev_null", "run {d}/job.json -o {d}/null --quiet", 2)
                     .setup(links)
                     .file("job.json", job(kLut))
                     .says("character device")
                     .still_link("null"));
  rows.push_back(R("special_job_output_is_a_fifo", "run {d}/job.json -o {d}/out --quiet", 2)
                     .setup("mkdir out && mkfifo out/t.exr")
                     .file("job.json", job(kLut))
                     .says("tables[0].output")
                     .says("FIFO")
                     .still_fifo("out/t.exr"));
  // Inputs that are devices or FIFOs: streams bounded by the option's limit, decoders refuse them.
  rows.push_back(R("special_eval_input_dev_zero", "eval --material {d}/m.json -i /dev/zero -o {d}/f.csv", 2)
                     .file("m.json", kMaterials)
                     .says("longer than 4096 bytes")
                     .no("f.csv"));
  rows.push_back(
      R("special_eval_binary_input_dev_zero", "eval --material {d}/m.json --binary -i /dev/zero -o {d}/f.f32", 2)
          .file("m.json", kMaterials)
          .says("zero")
          .no("f.f32"));
  rows.push_back(R("special_eval_input_no_line_end", "eval --material {d}/m.json -i {d}/p.csv -o {d}/f.csv", 2)
                     .file("m.json", kMaterials)
                     .file("p.csv", std::string(100000, 'x'))
                     .says("line 1")
                     .no("f.csv"));
  rows.push_back(R("special_irradiance_env_dev_zero", "irradiance --env /dev/zero -o {d}/sh.json", 2)
                     .says("character device")
                     .no("sh.json"));
  rows.push_back(
      R("special_prefilter_env_dev_urandom", "prefilter --env /dev/urandom --size 8 --min-size 4 -o {d}/p.ktx2", 2)
          .says("character device")
          .no("p.ktx2"));
  rows.push_back(R("special_env_fifo", "prefilter --env {d}/e.hdr --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                     .setup("mkfifo e.hdr")
                     .says("FIFO")
                     .no("p.ktx2")
                     .still_fifo("e.hdr"));
  rows.push_back(R("special_env_ktx2_fifo", "prefilter --env {d}/e.ktx2 --size 8 --min-size 4 -o {d}/p.ktx2", 2)
                     .setup("mkfifo e.ktx2")
                     .says("FIFO")
                     .no("p.ktx2"));
  rows.push_back(R("special_env_face_dev_zero",
                   "prefilter --env /dev/zero,{d}/e.hdr,{d}/e.hdr,{d}/e.hdr,{d}/e.hdr,{d}/e.hdr --size 8 --min-size 4 "
                   "-o {d}/p.ktx2",
                   2)
                     .file("e.hdr", rgbe(8, 8, 1.0))
                     .says("character device")
                     .no("p.ktx2"));
  rows.push_back(R("special_bake_env_fifo", "bake --env {d}/e.exr --lut-size 4 -o {d}/out --quiet", 2)
                     .setup("mkfifo e.exr")
                     .says("FIFO")
                     .no("out"));
  rows.push_back(R("special_job_env_dev_zero", "run {d}/job.json -o {d}/out --quiet", 2)
                     .file("job.json", job(R"({"kind": "irradiance", "source_size": 8, "output": "sh.json"})",
                                           R"(, "environment": "/dev/zero")"))
                     .says("character device")
                     .no("out"));
  rows.push_back(R("special_job_file_dev_zero", "run /dev/zero -o {d}/out", 2).says("larger than 64 MiB").no("out"));
  rows.push_back(R("special_scene_dev_zero", "bake --scene /dev/zero --dry-run", 2).says("larger than 64 MiB"));
  rows.push_back(R("special_material_dev_zero", "eval --material /dev/zero -i {d}/p.csv -o {d}/f.csv", 2)
                     .file("p.csv", kPairs)
                     .says("larger than 64 MiB")
                     .no("f.csv"));
  rows.push_back(R("special_job_from_fifo", "", 0)
                     .setup("mkfifo jf")
                     .file("job.txt", job(kLut))
                     .script("timeout 20 sh -c 'cat job.txt > jf' & {cli} run {d}/jf -o {d}/out --quiet 2>{err}; echo "
                             "$? >{status}; wait")
                     .has("out/manifest.json", "t.exr")
                     .lines(0));
  rows.push_back(R("special_scene_glb_from_fifo", "", 0)
                     .setup("mkfifo s.glb")
                     .file("scene.glb", glb(kScene))
                     .script("timeout 20 sh -c 'cat scene.glb > s.glb' & {cli} bake --scene {d}/s.glb --dry-run "
                             "--quiet 2>{err} >/dev/null; echo $? >{status}; wait")
                     .lines(0));
  rows.push_back(R("special_token_file_dev_zero", "serve --data {d}/data --token-file /dev/zero", 2)
                     .says("--token-file")
                     .says("4 KiB")
                     .no("data"));
  rows.push_back(R("special_token_file_nul", "serve --data {d}/data --token-file {d}/token", 2)
                     .file("token", std::string("abcdefgh\0ijklmnopqrstuvwxyz\n", 28))
                     .says("control character")
                     .no("data"));
  rows.push_back(R("special_token_file_folder", "serve --data {d}/data --token-file {d}/dir", 2)
                     .file("dir/x", "")
                     .says("it is a folder")
                     .no("data"));
  rows.push_back(R("special_client_token_file_dev_zero",
                   "run {d}/job.json -o {d}/out --server http://127.0.0.1:9 --token-file /dev/zero", 2)
                     .file("job.json", job(kLut))
                     .says("--token-file")
                     .no("out"));
  // Rules the bake planner checks, checked once for every front end before anything is accepted
  // (issue 24): an engine target's chain rules on the one-table command, a builtin's name in a job.
  rows.push_back(
      R("planner_prefilter_target_size", "prefilter --env builtin:sun --target babylon --size 100 -o {d}/p.ktx2", 2)
          .says("power-of-two")
          .no("p.ktx2"));
  rows.push_back(R("planner_prefilter_target_schedule",
                   "prefilter --env builtin:sun --target filament --schedule linear --size 16 -o {d}/p.ktx2", 2)
                     .says("filament reads its levels with the 'filament' schedule")
                     .no("p.ktx2"));
  rows.push_back(
      R("planner_job_builtin_traversal", "run {d}/job.json -o {d}/out --dry-run", 2)
          .file(
              "job.json",
              R"({"environment": "builtin:../../etc/passwd", "tables": [{"kind": "irradiance", "output": "sh.json"}]})")
          .says("unknown builtin environment")
          .no("out"));
  // Numbers at the edge: parameters beyond the float range are the model's (clamped to 1 here),
  // not infinities that meet 0; a model that exceeds 1 says so.
  rows.push_back(R("edge_fresnel_empirical_1e308",
                   "fresnel --model empirical --bias 1e308 --scale 1e308 --power 1e308 --size 8 -o {d}/f.csv", 0)
                     .has("f.csv", "# error_bound_mixed: 0\n")
                     .has("f.csv", ",1\n")
                     .lacks("f.csv", ",0\n"));
  rows.push_back(R("edge_thin_film_above_one", "thin-film --base-f0 0.95,0.64,0.54 --size 16 -o {d}/t.csv", 0)
                     .says("reflectance above 1")
                     .has("t.csv", "# reflectance_above_1: reflectance above 1 in "));
  // An output that is the same file as an input (by device and inode: a hard link, a symbolic
  // link, another spelling) would destroy it: refused before anything is read or written.
  rows.push_back(R("special_eval_output_is_input", "eval --material {d}/m.json -i {d}/p.csv -o {d}/p.csv", 2)
                     .file("m.json", kMaterials)
                     .file("p.csv", kPairs)
                     .says("same file")
                     .says("--input")
                     .keeps("p.csv"));
  rows.push_back(R("special_eval_output_is_input_hard_link", "eval --material {d}/m.json -i {d}/p.csv -o {d}/q.csv", 2)
                     .setup("ln p.csv q.csv")
                     .file("m.json", kMaterials)
                     .file("p.csv", kPairs)
                     .says("same file")
                     .keeps("p.csv"));
  rows.push_back(
      R("special_eval_output_is_input_symlink", "eval --material {d}/m.json -i {d}/sub/../p.csv -o {d}/q.csv", 2)
          .setup("mkdir sub && ln -s p.csv q.csv")
          .file("m.json", kMaterials)
          .file("p.csv", kPairs)
          .says("same file")
          .keeps("p.csv"));
  rows.push_back(R("special_eval_output_is_material", "eval --material {d}/m.json -i {d}/p.csv -o {d}/m.json", 2)
                     .file("m.json", kMaterials)
                     .file("p.csv", kPairs)
                     .says("--material")
                     .keeps("m.json"));
  rows.push_back(R("special_tabulate_output_is_material",
                   "tabulate --material {d}/m.json --layout grid --res 4 --format csv -o {d}/m.json", 2)
                     .file("m.json", kMaterials)
                     .says("--material")
                     .keeps("m.json"));
  rows.push_back(R("special_sh_json_is_env",
                   "irradiance --env {d}/e.hdr --source-size 8 --cube 4 -o {d}/c.ktx2 --sh-json {d}/e.hdr", 2)
                     .file("e.hdr", e)
                     .says("--sh-json")
                     .says("--env")
                     .keeps("e.hdr")
                     .no("c.ktx2"));
  rows.push_back(
      R("special_prefilter_output_is_env", "prefilter --env {d}/e.ktx2 --size 4 --min-size 4 -o {d}/e.ktx2", 2)
          .file("e.ktx2", ktx2_cube(4, 1.0f))
          .says("same file")
          .keeps("e.ktx2"));
  rows.push_back(R("special_prefilter_output_is_env_face",
                   "prefilter --env {d}/f_{face}.ktx2 --size 4 --min-size 4 -o {d}/f_nx.ktx2", 2)
                     .file("f_px.ktx2", "a")
                     .file("f_nx.ktx2", "b")
                     .file("f_py.ktx2", "c")
                     .file("f_ny.ktx2", "d")
                     .file("f_pz.ktx2", "e")
                     .file("f_nz.ktx2", "f")
                     .says("same file")
                     .keeps("f_nx.ktx2"));
  rows.push_back(R("special_job_output_is_env", "run {d}/job.json -o {d} --quiet", 2)
                     .file("e.ktx2", ktx2_cube(4, 1.0f))
                     .file("job.json", job(R"({"kind": "prefilter", "size": 4, "min_size": 4, "output": "e.ktx2"})",
                                           R"(, "environment": "e.ktx2")"))
                     .says("tables[0].output")
                     .says("same file")
                     .keeps("e.ktx2")
                     .keeps("job.json"));
  rows.push_back(R("special_job_output_is_job_file", "run {d}/job.json -o {d} --quiet", 2)
                     .file("job.json", job(R"({"kind": "ggx", "size": 4, "format": "csv", "output": "job.json"})"))
                     .says("the job file")
                     .keeps("job.json"));
  rows.push_back(
      R("special_job_output_is_eval_input", "run {d}/job.json -o {d} --quiet", 2)
          .file("m.json", kMaterials)
          .file("p.csv", kPairs)
          .file("job.json", job(R"({"kind": "eval", "material": "m.json", "input": "p.csv", "output": "p.csv"})"))
          .says("tables[0].input")
          .keeps("p.csv"));
  // A stop ends a read that waits for a writer (a FIFO nobody opens): 128 + the signal, nothing left.
  rows.push_back(
      R("special_job_fifo_sigterm", "", 143)
          .setup("mkfifo jf")
          .script("{cli} run {d}/jf -o {d}/out 2>{err} & p=$!; sleep 0.7; kill -TERM $p; wait $p; echo $? >{status}")
          .says("interrupted by SIGTERM")
          .no("out")
          .still_fifo("jf"));
  rows.push_back(R("special_eval_input_fifo_sigterm", "", 143)
                     .setup("mkfifo pf")
                     .file("m.json", kMaterials)
                     .script("{cli} eval --material {d}/m.json -i {d}/pf -o {d}/f.csv 2>{err} & p=$!; sleep 1; kill "
                             "-TERM $p; wait $p; echo $? >{status}")
                     .says("interrupted by SIGTERM")
                     .no("f.csv"));
  rows.push_back(R("special_material_fifo_sigint", "", 130)
                     .setup("mkfifo mf")
                     .file("p.csv", kPairs)
                     .script("{cli} eval --material {d}/mf -i {d}/p.csv -o {d}/f.csv 2>{err} & p=$!; sleep 0.7; kill "
                             "-INT $p; wait $p; echo $? >{status}")
                     .says("interrupted by SIGINT")
                     .no("f.csv"));
  rows.push_back(R("special_scene_fifo_sighup", "", 129)
                     .setup("mkfifo s.gltf")
                     .script("{cli} bake --scene {d}/s.gltf -o {d}/out 2>{err} & p=$!; sleep 0.7; kill -HUP $p; wait "
                             "$p; echo $? >{status}")
                     .says("interrupted by SIGHUP")
                     .no("out"));
  // An environment FIFO is refused at once (decoders need a file): nothing to stop.
  rows.push_back(R("special_env_fifo_then_sigterm", "", 2)
                     .setup("mkfifo e.hdr")
                     .script("{cli} irradiance --env {d}/e.hdr -o {d}/sh.json 2>{err} & p=$!; sleep 0.7; kill -TERM $p "
                             "2>/dev/null; wait $p; echo $? >{status}")
                     .says("FIFO")
                     .no("sh.json"));
}

// -- Issue 24, collisions inside one job: the set of outputs is checked before anything is baked,
// naming both fields; never a silent overwrite, never the staging folder's name in a message.
void collisions(std::vector<Row>& rows) {
  struct C {
    const char* name;
    std::string tables;
    std::vector<std::string> words;
  };
  const std::string cube =
      R"({"kind": "irradiance", "source_size": 8, "cube_size": 4, "output": "c.ktx2", "sh_json": "a.json"})";
  const std::vector<C> cs = {
      {"collide_sh_json_and_output",
       cube + R"(, {"kind": "irradiance", "source_size": 8, "output": "a.json"})",
       {"tables[1].output", "tables[0].sh_json"}},
      {"collide_sh_json_and_output_reversed",
       R"({"kind": "irradiance", "source_size": 8, "output": "a.json"}, )" + cube,
       {"tables[1].sh_json", "tables[0].output"}},
      {"collide_sh_json_and_own_output",
       R"({"kind": "irradiance", "source_size": 8, "cube_size": 4, "output": "c.ktx2", "sh_json": "c.ktx2"})",
       {"tables[0].sh_json", "tables[0].output"}},
      {"collide_sh_json_normalised",
       cube + R"(, {"kind": "ggx", "size": 4, "format": "csv", "output": "./a.json"})",
       {"tables[1].output"}},
      {"collide_sh_json_and_lut",
       cube + R"(, {"kind": "ggx", "size": 4, "format": "csv", "output": "a.json"})",
       {"tables[1].output", "tables[0].sh_json"}},
      {"collide_two_sh_json",
       cube + R"(, {"kind": "irradiance", "source_size": 16, "cube_size": 4, "output": "d.ktx2", "sh_json": "a.json"})",
       {"tables[1].sh_json", "tables[0].sh_json"}},
      {"collide_file_inside_folder_output",
       R"({"kind": "prefilter", "size": 8, "min_size": 4, "output": "cube/"}, {"kind": "ggx", "size": 4, "output": "cube/t.exr"})",
       {"tables[1].output", "inside the folder", "tables[0].output"}},
      {"collide_folder_output_around_file",
       R"({"kind": "ggx", "size": 4, "output": "cube/t.exr"}, {"kind": "prefilter", "size": 8, "min_size": 4, "output": "cube"})",
       {"tables[0].output", "inside the folder"}},
      {"collide_under_a_file",
       R"({"kind": "ggx", "size": 4, "output": "a.exr"}, {"kind": "charlie", "size": 4, "output": "a.exr/b.exr"})",
       {"tables[1].output", "which is a file"}},
      {"collide_sh_json_under_a_file",
       R"({"kind": "ggx", "size": 4, "output": "a.exr"}, )" +
           std::string(
               R"({"kind": "irradiance", "source_size": 8, "cube_size": 4, "output": "c.ktx2", "sh_json": "a.exr/sh.json"})"),
       {"tables[1].sh_json", "which is a file"}},
  };
  for (const C& c : cs) {
    R row(c.name, "run {d}/job.json -o {d}/out --quiet", 2);
    row.file("job.json", job(c.tables)).no("out").never(".tmp-").never("out.tmp");
    for (const auto& w : c.words) row.says(w);
    rows.push_back(row);
    // the same document checked by --dry-run, before any folder exists
    R dry(std::string(c.name) + "_dry_run", "run {d}/job.json -o {d}/out --dry-run", 2);
    dry.file("job.json", job(c.tables)).no("out");
    for (const auto& w : c.words) dry.says(w);
    rows.push_back(dry);
  }
  // A folder of an output's path that is a file in the existing output folder: refused before the
  // bake (the commit used to move the first table in, then fail: a half-replaced folder).
  rows.push_back(
      R("collide_output_under_existing_file", "run {d}/job.json -o {d}/out --quiet", 1)
          .file("out/sub", "a file")
          .file("out/a.exr", "old")
          .file(
              "job.json",
              job(R"({"kind": "ggx", "size": 4, "output": "a.exr"}, {"kind": "ggx", "size": 8, "output": "sub/b.exr"})"))
          .says("tables[1].output")
          .says("not a folder")
          .keeps("out/a.exr")
          .keeps("out/sub")
          .never(".tmp-"));
  // On the command line: irradiance's own two outputs.
  rows.push_back(R("collide_cli_sh_json_is_output",
                   "irradiance --env {d}/e.hdr --source-size 8 --cube 4 -o {d}/c.ktx2 --sh-json {d}/c.ktx2", 2)
                     .file("e.hdr", rgbe(16, 8, 1.0))
                     .says("--sh-json")
                     .says("-o")
                     .no("c.ktx2"));
}

// -- Issue 34, class 1: every file a command writes is an output under every rule, the files written
// beside the output included (the preview's NAME.json, NAME_splitsum.exr, NAME_reference.exr, a
// report's JSON): none may be an input, a folder, or another output of the job; `view` and `report`
// too; and --keep-bakes, whose folders the sweep replaces, is checked before anything runs.
void sibling_outputs(std::vector<Row>& rows) {
  rows.push_back(R("sibling_preview_json_is_materials",
                   "preview --env builtin:sun --materials {d}/p.json -o {d}/p.png --no-reference", 2)  // the old name
                     .file("p.json", kMaterials)
                     .says("same file as --material (")  // named canonically
                     .says("p.json")
                     .keeps("p.json")
                     .no("p.png"));
  rows.push_back(R("sibling_preview_json_is_bake_manifest",
                   "preview --env builtin:sun --bake {d}/bk --target filament -o {d}/bk/manifest.png --no-reference", 2)
                     .file("bk/manifest.json", R"({"brdfbake_manifest": 1})")
                     .says("--bake")
                     .says("manifest.json")
                     .keeps("bk/manifest.json")
                     .no("bk/manifest.png"));
  rows.push_back(R("sibling_preview_folder_in_the_way", "preview --env builtin:sun -o {d}/q.png --no-reference", 2)
                     .setup("mkdir q.json")
                     .says("'{d}/q.json' is a folder")
                     .no("q.png"));
  const std::string preview_table =
      R"({"kind": "preview", "width": 192, "height": 96, "reference": false, "output": "p.png"})";
  for (const bool dry : {false, true}) {
    const std::string mode = dry ? " --dry-run" : " --quiet";
    const std::string suffix = dry ? "_dry_run" : "";
    rows.push_back(R("sibling_job_preview_json_is_a_table" + suffix, "run {d}/job.json -o {d}/out" + mode, 2)
                       .file("job.json",
                             job(preview_table + R"(, {"kind": "ggx", "size": 4, "format": "csv", "output": "p.json"})",
                                 R"(, "environment": "builtin:sun")"))
                       .says("tables[1].output")
                       .says("tables[0].output's p.json")
                       .no("out"));
    rows.push_back(
        R("sibling_job_preview_json_is_the_manifest" + suffix, "run {d}/job.json -o {d}/out" + mode, 2)
            .file(
                "job.json",
                job(R"({"kind": "preview", "width": 192, "height": 96, "reference": false, "output": "manifest.png"})",
                    R"(, "environment": "builtin:sun")"))
            .says("tables[0].output's manifest.json")
            .says("the job's manifest")
            .no("out"));
  }
  rows.push_back(R("sibling_view_its_own_input", "view {d}/s.png -o {d}/s.png", 2)
                     .file("s.png", "not a picture, and not to be replaced")
                     .says("same file")
                     .keeps("s.png"));
  rows.push_back(R("sibling_view_into_a_viewed_folder", "view {d}/bk -o {d}/bk/s.png", 2)
                     .file("bk/s.png", "a file of the folder drawn")
                     .says("same file")
                     .keeps("bk/s.png"));
  rows.push_back(R("sibling_report_json_folder_in_the_way", "report --kinds fresnel -o {d}/r.html", 2)
                     .setup("mkdir r.json")
                     .says("is a folder")
                     .no("r.html"));
  rows.push_back(R("sibling_report_keep_bakes_not_empty", "report --kinds bake --keep-bakes {d}/keep -o {d}/r.html", 2)
                     .file("keep/filament/default/mine.txt", "the user's own file")
                     .says("keep_bakes")
                     .says("not an empty folder")
                     .keeps("keep/filament/default/mine.txt")
                     .no("r.html"));
}

// -- Issue 34, class 7 (the smaller classes): what one front end refuses, the others refuse too; a
// kind's own parameter is not taken for a job's field of the same name; a name's control characters
// never split a one-line message or forge a warning line.
void smaller_classes(std::vector<Row>& rows) {
  rows.push_back(
      R("class7_newline_in_a_name_stays_one_line", "irradiance --env '{d}/a\nwarning: forged.hdr' -o {d}/x.json", 2)
          .says("a\\nwarning: forged.hdr")
          .no("x.json"));
  rows.push_back(
      R("class7_job_preview_materials_parameter", "run {d}/job.json -o {d}/out --dry-run", 0)
          .file("m.json", kMaterials)
          .file("job.json",
                job(R"({"kind": "preview", "materials": "m.json", "width": 192, "height": 96, "output": "p.png"})",
                    R"(, "environment": "builtin:sun")"))
          .no("out"));
  rows.push_back(R("class7_bake_dry_run_refuses_what_the_writer_would",
                   "bake --env builtin:sun --target babylon --chain-size 100 -o {d}/o --dry-run", 2)
                     .says("chain_size")
                     .says("power-of-two")
                     .no("o"));
  rows.push_back(R("class7_bake_dry_run_refuses_a_schedule_the_engine_does_not_read",
                   "bake --env builtin:sun --target filament --schedule linear -o {d}/o --dry-run", 2)
                     .says("schedule")
                     .no("o"));
  rows.push_back(R("class7_bake_engine_name_is_a_name",
                   "bake --env builtin:sun --target filament --engine-name "
                   "../x -o {d}/o --dry-run",
                   2)
                     .says("--engine-name")
                     .no("o"));
  R named("class7_bake_engine_name_and_sh_window",
          "bake --env builtin:sun --target filament --engine-name sky --sh-window none --cube-size 32 --lut-size 16 "
          "-o {d}/o --quiet",
          0);
  named.r.check_output = [](const fs::path& d) {
    EXPECT_TRUE(fs::exists(d / "o" / "sky_ibl.ktx"));
    EXPECT_TRUE(fs::exists(d / "o" / "sky_skybox.ktx"));
    std::ifstream in(d / "o" / "manifest.json");
    const auto m = nlohmann::json::parse(in);
    bool window_none = false;
    for (const auto& f : m["files"])
      if (f.value("kind", "") == "irradiance") window_none = f["parameters"].value("sh_window", "") == "none";
    EXPECT_TRUE(window_none) << m.dump();
  };
  rows.push_back(named);
  // A scene's bake --preview shows the scene's materials, not the default grid (issue 34, new user).
  R scene_preview("class7_bake_scene_preview_shows_the_scene",
                  "bake --scene {d}/s.gltf --env builtin:sun --cube-size 32 --lut-size 16 -o {d}/o --preview --quiet",
                  0);
  // a mirror (roughness 0): the reference of the sphere's 174,000 pixels is a lookup, not an
  // integral (7 s, against 20 s at roughness 0.5); a dielectric, so that the bake has both tables
  scene_preview.file("s.gltf", R"({"asset": {"version": "2.0"}, "materials": [{"name": "m", "pbrMetallicRoughness": )"
                               R"({"metallicFactor": 0, "roughnessFactor": 0}}]})");
  scene_preview.r.check_output = [](const fs::path& d) {
    std::ifstream in(d / "o" / "preview.json");
    const auto p = nlohmann::json::parse(in);
    ASSERT_EQ(p["spheres"].size(), 1u) << "the default grid has 72";
    EXPECT_EQ(p["spheres"][0].value("name", ""), "m");
  };
  rows.push_back(scene_preview);
  // Issue 35: a chain whose bound against the double reference is above the max_error asked says so
  // (its successive refinements agreed to max_error: that stopped the search, not the error).
  rows.push_back(R("class7_prefilter_missed_max_error_is_a_warning",
                   "prefilter --env builtin:sun --size 32 --min-size 4 --distribution charlie --max-error 0.01 "
                   "-o {d}/c.ktx2",
                   0)
                     .says("warning: charlie prefiltered chain: the chain's error bound")
                     .says("is above the chain_max_error 0.01 asked"));
  // Issue 35: a preview that bakes first keeps that bake when asked, and names its files where they are.
  R kept("class7_preview_keeps_its_first_bake",
         "preview --env builtin:sun --target filament --keep-bake {d}/kept -o {d}/p.png --width 192 --height 96 "
         "--no-reference --quiet",
         0);
  kept.r.check_output = [](const fs::path& d) {
    EXPECT_TRUE(fs::exists(d / "kept" / "manifest.json"));
    EXPECT_TRUE(fs::exists(d / "kept" / "preview_ibl.ktx"));
    std::ifstream in(d / "p.json");
    const auto p = nlohmann::json::parse(in);
    EXPECT_EQ(p["bake"].value("specular", ""), (d / "kept" / "preview_ibl.ktx").string()) << p["bake"].dump();
  };
  rows.push_back(kept);
  rows.push_back(
      R("class7_preview_keep_bake_must_be_new", "preview --env builtin:sun --keep-bake {d}/kept -o {d}/p.png", 2)
          .file("kept/mine.txt", "the user's own file")
          .says("--keep-bake")
          .says("not an empty folder")
          .keeps("kept/mine.txt")
          .no("p.png"));
  rows.push_back(R("class7_bake_preview_on_the_reference_device",
                   "bake --env builtin:sun --preview --device reference --cube-size 16 -o {d}/o", 2)
                     .says("scalar reference")
                     .no("o"));
}

// -- Issue 24, the lock and the output folder: locked by the folder's identity, every stop signal
// (SIGINT, SIGTERM, SIGHUP, SIGPIPE) cleans up as it unwinds.
void locks_and_signals(std::vector<Row>& rows) {
  rows.push_back(R("lock_through_symlink", "run {d}/job.json -o {d}/link --quiet", 1)
                     .setup("mkdir real && ln -s real link")
                     .file("job.json", job(kLut))
                     .lock("real")
                     .says("being written by"));
  rows.push_back(R("lock_held_through_symlink", "run {d}/job.json -o {d}/real --quiet", 1)
                     .setup("mkdir real && ln -s real link")
                     .file("job.json", job(kLut))
                     .lock("link")
                     .says("being written by"));
  rows.push_back(R("lock_through_symlinked_parent", "run {d}/job.json -o {d}/pl/out --quiet", 1)
                     .setup("mkdir p && ln -s p pl")
                     .file("job.json", job(kLut))
                     .lock("p/out")
                     .says("being written by")
                     .no("p/out"));
  rows.push_back(R("lock_through_dot_dot", "run {d}/job.json -o {d}/sub/../out --quiet", 1)
                     .setup("mkdir sub")
                     .file("job.json", job(kLut))
                     .lock("out")
                     .says("being written by")
                     .no("out"));
  rows.push_back(R("lock_prefilter_folder_through_symlink",
                   "prefilter --env {d}/e.hdr --size 8 --min-size 4 --quiet -o {d}/link/", 1)
                     .setup("mkdir real && ln -s real link")
                     .file("e.hdr", rgbe(16, 8, 1.0))
                     .lock("real")
                     .says("being written by"));
  // A job that waits on a FIFO (its eval input) while it holds the lock and its staging folder.
  const std::string waits = job(kLut + R"(, {"kind": "eval", "material": "m.json", "input": "pf", "output": "f.csv"})");
  for (const auto& [sig, code] : {std::pair<std::string, int>{"HUP", 129}, {"TERM", 143}, {"INT", 130}})
    rows.push_back(R("lock_sig" +
                         std::string(sig == "HUP"    ? "hup"
                                     : sig == "TERM" ? "term"
                                                     : "int") +
                         "_removes_lock_and_staging",
                     "", code)
                       .setup("mkfifo pf")
                       .file("m.json", kMaterials)
                       .file("job.json", waits)
                       .script("{cli} run {d}/job.json -o {d}/out 2>{err} & p=$!; sleep 1.5; kill -" + sig +
                               " $p; wait $p; echo $? >{status}")
                       .says("interrupted by SIG" + sig)
                       .no("out"));
  // SIGPIPE: the reader of standard error went away while the run held its lock and staging folder
  // (its warning met the closed pipe); the run stops, cleans up and ends with 141.
  rows.push_back(
      R("lock_sigpipe_removes_lock_and_staging", "", 141)
          .file("sun.hdr", rgbe(16, 8, 1.0e5))
          .file(
              "job.json",
              job(R"({"kind": "prefilter", "size": 8, "min_size": 4, "pixel": "f16", "clamp_f16": true, "output": "p.ktx2"})",
                  R"(, "environment": "sun.hdr")"))
          .script("( sleep 0.3; {cli} run {d}/job.json -o {d}/out 2>&1 >/dev/null; echo $? >{status} ) | true")
          .silent_ok()
          .no("out"));
  // eval writing to a pipe whose reader stopped: 141, not killed by the signal.
  std::string many = "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n";
  for (int k = 0; k < 200000; ++k) many += "0,0,1,0.5,0,0.8\n";
  rows.push_back(R("eval_sigpipe_stops_cleanly", "", 141)
                     .file("m.json", kMaterials)
                     .file("p.csv", many)
                     .script("( {cli} eval --material {d}/m.json -i {d}/p.csv -o - 2>{err}; echo $? >{status} ) | head "
                             "-c 10 >/dev/null")
                     .says("interrupted by SIGPIPE"));
}

// -- Issue 24, silent wrong values from images: colour encodings decoded (and said), images without
// colour refused naming their channels, header numbers range-checked before any arithmetic,
// libraries' messages inside the one-line error.
void image_values(std::vector<Row>& rows) {
  const std::string srgb_chunk = std::string(1, '\0');
  rows.push_back(R("image_png_srgb_decoded", "irradiance --env {d}/e.png --source-size 8 -o {d}/sh.json", 0)
                     .file("e.png", png(16, 8, 128, {{"sRGB", srgb_chunk}}))
                     .says("8-bit sRGB (its sRGB chunk) decoded to linear")
                     .lines(2));
  rows.push_back(R("image_png_untagged_decoded", "irradiance --env {d}/e.png --source-size 8 -o {d}/sh.json", 0)
                     .file("e.png", png(16, 8, 128))
                     .says("sRGB (no colour chunk")
                     .lines(2));
  rows.push_back(R("image_png_gamma_decoded", "prefilter --env {d}/e.png --size 4 --min-size 4 -o {d}/p.ktx2", 0)
                     .file("e.png", png(16, 8, 128, {{"gAMA", be32(45455)}}))
                     .says("gamma 2.2")
                     .has("p.ktx2", "gamma 2.2")
                     .lines(2));
  rows.push_back(R("image_png_linear_is_quiet", "irradiance --env {d}/e.png --source-size 8 --quiet -o {d}/sh.json", 0)
                     .file("e.png", png(16, 8, 128, {{"gAMA", be32(100000)}}))
                     .lines(0));
  rows.push_back(R("image_png_16_bit_untagged_said", "irradiance --env {d}/e.png --source-size 8 -o {d}/sh.json", 0)
                     .file("e.png", png(16, 8, 30000, {}, 16))
                     .says("read as linear")
                     .lines(2));
  rows.push_back(R("image_png_icc_unknown_refused", "irradiance --env {d}/e.png -o {d}/sh.json", 2)
                     .file("e.png", png(16, 8, 128, {iccp("Display P3")}))
                     .says("ICC profile 'Display P3'")
                     .no("sh.json"));
  rows.push_back(R("image_png_in_job_noted", "run {d}/job.json -o {d}/out --quiet", 0)
                     .file("e.png", png(16, 8, 128, {{"sRGB", srgb_chunk}}))
                     .file("job.json", job(R"({"kind": "irradiance", "source_size": 8, "output": "sh.json"})",
                                           R"(, "environment": "e.png")"))
                     .has("out/manifest.json", "decoded to linear")
                     .lines(0));
  const std::string good = png(16, 8, 128, {{"sRGB", srgb_chunk}});
  rows.push_back(R("image_png_truncated", "irradiance --env {d}/e.png -o {d}/sh.json", 2)
                     .file("e.png", good.substr(0, good.size() - 30))
                     .says("truncated")
                     .never("libpng")
                     .no("sh.json"));
  rows.push_back(R("image_png_truncated_in_header", "irradiance --env {d}/e.png -o {d}/sh.json", 2)
                     .file("e.png", good.substr(0, 20))
                     .says("e.png")
                     .never("libpng")
                     .no("sh.json"));
  {
    std::string bad_crc = good;
    bad_crc[30] = static_cast<char>(bad_crc[30] ^ 0x40);  // inside IHDR's data: its CRC no longer matches
    rows.push_back(R("image_png_bad_crc", "prefilter --env {d}/e.png --size 4 --min-size 4 -o {d}/p.ktx2", 2)
                       .file("e.png", bad_crc)
                       .says("e.png")
                       .never("libpng")
                       .no("p.ktx2"));
  }
  rows.push_back(R("image_png_header_promises_huge", "irradiance --env {d}/e.png -o {d}/sh.json", 2)
                     .file("e.png", png(4, 4, 128, {}, 8, 100000))
                     .says("e.png")
                     .never("libpng")
                     .no("sh.json")
                     .memory_cap_mib(512));
  rows.push_back(R("image_exr_alpha_only", "irradiance --env {d}/e.exr -o {d}/sh.json", 2)
                     .file("e.exr", exr_with_channels({"A"}))
                     .says("no colour channels")
                     .says("A")
                     .no("sh.json"));
  rows.push_back(R("image_exr_depth_only", "prefilter --env {d}/e.exr --size 4 --min-size 4 -o {d}/p.ktx2", 2)
                     .file("e.exr", exr_with_channels({"Z"}))
                     .says("no colour channels")
                     .says("Z")
                     .no("p.ktx2"));
  rows.push_back(R("image_exr_red_and_green_only", "irradiance --env {d}/e.exr -o {d}/sh.json", 2)
                     .file("e.exr", exr_with_channels({"R", "G"}))
                     .says("no colour channels")
                     .no("sh.json"));
  rows.push_back(R("image_exr_luminance_is_grey", "irradiance --env {d}/e.exr --quiet -o {d}/sh.json", 0)
                     .file("e.exr", exr_with_channels({"Y"}))
                     .has("sh.json", "irradiance_over_pi")
                     .lines(0));
  rows.push_back(R("image_exr_layer_rgb", "irradiance --env {d}/e.exr --quiet -o {d}/sh.json", 0)
                     .file("e.exr", exr_with_channels({"diffuse.B", "diffuse.G", "diffuse.R"}))
                     .lines(0));
  const std::string head = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n";
  const std::string px(4 * 128, '\x40');
  for (const auto& [name, line] :
       std::vector<std::pair<std::string, std::string>>{{"image_hdr_width_wraps_32_bits", "-Y 8 +X 4294967312"},
                                                        {"image_hdr_height_wraps_32_bits", "-Y 4294967304 +X 16"},
                                                        {"image_hdr_width_20_digits", "-Y 8 +X 99999999999999999999"},
                                                        {"image_hdr_width_int_max_plus_1", "-Y 1 +X 2147483648"},
                                                        {"image_hdr_zero_height", "-Y 0 +X 16"},
                                                        {"image_hdr_negative_width", "-Y 8 +X -16"}})
    rows.push_back(R(name, "irradiance --env {d}/e.hdr -o {d}/sh.json", 2)
                       .file("e.hdr", head + line + "\n" + px)
                       .says("resolution line")
                       .no("sh.json"));
  rows.push_back(R("image_hdr_exposure_said", "irradiance --env {d}/e.hdr --source-size 8 -o {d}/sh.json", 0)
                     .file("e.hdr", "#?RADIANCE\nEXPOSURE=2.5\n" + rgbe(16, 8, 1.0).substr(11))
                     .says("EXPOSURE (2.5)")
                     .lines(2));
  rows.push_back(R("image_hdr_header_without_end", "irradiance --env {d}/e.hdr -o {d}/sh.json", 2)
                     .file("e.hdr", "#?RADIANCE\n" + repeat("# comment\n", 10000))
                     .says("header")
                     .no("sh.json"));
}

// -- Issue 24, smaller: a kernel cache folder that cannot be written is said, and the run goes on.
void caches(std::vector<Row>& rows) {
  rows.push_back(
      R("cache_pocl_folder_unwritable", "lut --size 4 --quiet -o {d}/t.exr", 0)
          // PoCL's default folder under XDG_CACHE_HOME, whatever POCL_CACHE_DIR the suite
          // runs with (scripts/test.sh sets a private one); the private folder it falls back to,
          // $TMPDIR/brdfbake-pocl-cache-UID (kept between runs), in the row's folder (the command runs there)
          .env("env -u POCL_CACHE_DIR XDG_CACHE_HOME=/proc/brdfbake-hostile-none BRDFBAKE_CACHE_DIR={d}/kernels "
               "TMPDIR=$PWD")
          .allow_tmp("brdfbake-pocl-cache-")  // PoCL's own files in that cache
          .says("cannot be written")
          .says("POCL_CACHE_DIR")
          .never("no OpenCL device")
          .lines(2));
  rows.push_back(R("cache_brdfbake_folder_unwritable", "lut --size 4 --quiet -o {d}/t.exr", 0)
                     .env("BRDFBAKE_CACHE_DIR=/proc/brdfbake-hostile-none")
                     .says("BRDFBAKE_CACHE_DIR")
                     .lines(2));
}

// -- Generated: every schema parameter, out of range, not finite and of the wrong type, on the
// command line and in a job.
struct Command {
  const char* command;
  TableKind kind;
  std::vector<std::pair<std::string, std::string>> base;  // options the command needs (name, value)
  std::string ext;                                        // the output's extension
  std::vector<std::pair<std::string, std::string>> job;   // the table's other fields (name, JSON)
};

// Bad command-line values for a parameter: not finite, not a number, out of its range.
std::vector<std::pair<std::string, std::string>> bad_cli_values(const ParamDef& d) {
  std::vector<std::pair<std::string, std::string>> v;  // (label, value)
  auto num = [](double x) {
    char b[64];
    std::snprintf(b, sizeof b, "%.17g", x);
    return std::string(b);
  };
  switch (d.type) {
    case ParamType::Int:
    case ParamType::Number:
      v = {{"inf", "1e999"}, {"text", "abc"}};
      if (std::isfinite(d.hi))
        v.push_back({"above", num(d.hi + 1)});
      else if (std::isfinite(d.lo))
        v.push_back({"below", d.lo_open ? num(d.lo) : num(d.lo - 1)});
      else
        v.push_back({"nan", "nan"});
      break;
    case ParamType::Name:
      if (!d.choices.empty()) v = {{"unknown", "no-such-choice"}};
      break;
    case ParamType::Color:
      v = {{"two", "0.5,0.5"}, {"inf", "1e999,0,0"}};
      break;
    case ParamType::Range:
      v = {{"reversed", "2,1"}};
      break;
    case ParamType::IntList:
      v = {{"zero", "0"}, {"four", "1,2,3,4"}};
      break;
    default:
      break;
  }
  return v;
}

// Bad JSON values for a parameter in a job: a number a double cannot hold, the wrong JSON type.
std::vector<std::pair<std::string, std::string>> bad_job_values(const ParamDef& d) {
  switch (d.type) {
    case ParamType::Int:
    case ParamType::Number:
      return {{"inf", "1e999"}, {"text", "\"abc\""}};
    case ParamType::Name:
      return {{"number", "5"}};
    case ParamType::Color:
    case ParamType::Range:
    case ParamType::IntList:
      return {{"inf", "[1e999, 0, 0]"}, {"nested", "[[1]]"}};
    case ParamType::Flag:
      return {{"text", "\"yes\""}};
    case ParamType::Path:
      return {{"number", "5"}};
  }
  return {};
}

void generated(std::vector<Row>& rows) {
  const std::vector<Command> commands = {
      {"lut", TableKind::Ggx, {{"kind", "ggx"}}, ".exr", {}},
      {"lut", TableKind::Charlie, {{"kind", "charlie"}}, ".exr", {}},
      {"fresnel", TableKind::Fresnel, {{"model", "schlick"}}, ".exr", {{"model", "\"schlick\""}}},
      {"thin-film", TableKind::ThinFilm, {{"base-ior", "1.5"}}, ".exr", {{"base_ior", "1.5"}}},
      {"prefilter", TableKind::Prefilter, {{"env", "builtin:studio"}}, ".ktx2", {}},
      {"irradiance", TableKind::Irradiance, {{"env", "builtin:studio"}}, ".json", {}},
      {"eval",
       TableKind::Eval,
       {{"material", "{d}/m.json"}, {"input", "{d}/p.csv"}},
       ".csv",
       {{"material", "\"m.json\""}, {"input", "\"p.csv\""}}},
      {"tabulate",
       TableKind::Tabulate,
       {{"material", "{d}/m.json"}, {"layout", "grid"}},
       ".exr",
       {{"material", "\"m.json\""}, {"layout", "\"grid\""}}},
  };
  for (const Command& c : commands) {
    for (const ParamDef& d : brdfbake::table_schema(c.kind)) {
      const std::string base_name = std::string(c.command) + "_" + brdfbake::table_kind_name(c.kind) + "_" + d.name;
      // the command line and the job: what the command needs, without the parameter under test
      std::string base, fields;
      for (const auto& [option, value] : c.base)
        if (option != d.cli_name()) base += " --" + option + " " + value;
      for (const auto& [field, value] : c.job)
        if (field != d.name) fields += ", \"" + field + "\": " + value;
      for (const auto& [label, value] : bad_cli_values(d)) {
        R row("cli_" + base_name + "_" + label,
              std::string(c.command) + base + " --" + d.cli_name() + " '" + value + "' -o {d}/out" + c.ext, 2);
        row.file("m.json", kMaterials)
            .file("p.csv", kPairs)
            .says("--" + d.cli_name())
            .says("must be")
            .no("out" + c.ext);
        rows.push_back(row);
      }
      for (const auto& [label, value] : bad_job_values(d)) {
        const std::string table = R"({"kind": ")" + std::string(brdfbake::table_kind_name(c.kind)) + "\"" + fields +
                                  R"(, ")" + d.name + "\": " + value + "}";
        R row("job_" + base_name + "_" + label, "run {d}/job.json -o {d}/out", 2);
        row.file("job.json", job(table))
            .file("m.json", kMaterials)
            .file("p.csv", kPairs)
            .says("tables[0]." + d.name)
            .no("out");
        rows.push_back(row);
      }
    }
  }
  // bake's plan options
  for (const ParamDef& d : brdfbake::plan_schema())
    for (const auto& [label, value] : bad_cli_values(d)) {
      R row("cli_bake_" + d.name + "_" + label, "bake --" + d.cli_name() + " '" + value + "' -o {d}/out", 2);
      row.says("--" + d.cli_name()).says("must be").no("out");
      rows.push_back(row);
    }
}

std::vector<Row> all_rows() {
  std::vector<Row> rows;
  deep_json(rows);
  raw_exceptions(rows);
  numeric_outputs(rows);
  memory_before_validation(rows);
  knobs(rows);
  messages(rows);
  outputs(rows);
  eval_streams(rows);
  device_limits(rows);
  special_files(rows);
  collisions(rows);
  sibling_outputs(rows);
  smaller_classes(rows);
  locks_and_signals(rows);
  image_values(rows);
  caches(rows);
  generated(rows);
  return rows;
}

// ---- Running a row ----------------------------------------------------------------------------------

// A pid that no process has (for the temporaries of a "killed" run).
long dead_pid() {
  static const long pid = [] {
    for (long p = 4000000; p > 1000; --p)
      if (::kill(static_cast<pid_t>(p), 0) != 0 && errno == ESRCH) return p;
    return 0L;
  }();
  return pid;
}

std::string substitute(std::string s, const std::string& from, const std::string& to) {
  for (size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
    s.replace(at, from.size(), to);
  return s;
}

std::string expand(const std::string& s, const fs::path& dir) {
  std::string out = substitute(s, "{d}", dir.string());
  out = substitute(out, "{deadpid}", std::to_string(dead_pid()));
  return substitute(out, "{livepid}", std::to_string(::getpid()));
}

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

constexpr int kRowSeconds = 120;

struct RowRun {
  int code = -1;
  int signal = 0;
  std::string err;
};

// The binary under test: $BRDFBAKE_CLI_UNDER_TEST (to run the table against another build), else
// the one this suite was built with.
std::string cli() {
  const char* other = std::getenv("BRDFBAKE_CLI_UNDER_TEST");
  return other && *other ? other : BRDFBAKE_CLI;
}

RowRun run_row(const Row& row, const fs::path& dir) {
  const fs::path err = dir / ".stderr";
  const fs::path in = dir / ".stdin";
  const fs::path status_file = dir / ".status";
  std::ofstream(in, std::ios::binary) << row.input;
  // Every row is bounded: a run that takes minutes is a failure of the row (exit 124 from timeout).
  const std::string cap = row.memory_cap_kib > 0 ? "ulimit -v " + std::to_string(row.memory_cap_kib) + " && " : "";
  const std::string bounded = "timeout -k 5 " + std::to_string(kRowSeconds) + " " + cli();
  std::string cmd;
  if (row.script.empty()) {
    cmd = "cd " + dir.string() + " && " + cap + row.env + (row.env.empty() ? "" : " ") + bounded + " " +
          expand(row.args, dir) + " <" + in.string() + " 2>" + err.string() +
          (row.args.find(">/dev/full") == std::string::npos ? " >/dev/null" : "");
  } else {
    std::string script = substitute(row.script, "{cli}", bounded);
    script = substitute(script, "{err}", err.string());
    script = substitute(script, "{status}", status_file.string());
    script = substitute(script, "{in}", in.string());
    cmd = "cd " + dir.string() + " && " + cap + (row.env.empty() ? "" : "export " + row.env + " && ") + "{ " +
          expand(script, dir) + "; }";
  }
  const int status = std::system(cmd.c_str());
  RowRun r;
  if (status != -1 && WIFEXITED(status)) {
    r.code = WEXITSTATUS(status);
    if (fs::exists(status_file)) r.code = std::atoi(read_file(status_file).c_str());
    // the shell reports a killed child as 128 + signal; a run that stops on a signal by itself
    // exits with the same code and says so (the row's words: "interrupted by SIG...")
    if (r.code > 128 && r.code != row.code) r.signal = r.code - 128;
  }
  r.err = read_file(err);
  fs::remove(err);
  fs::remove(in);
  fs::remove(status_file);
  return r;
}

#ifdef BRDFBAKE_ASAN  // cmake/Sanitizers.cmake
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif

class Hostile : public ::testing::TestWithParam<Row> {};

// gtest prints a parameter that fails: the row's name and command, not its bytes.
void PrintTo(const Row& row, std::ostream* out) { *out << row.name << ": brdfbake " << row.args; }

TEST_P(Hostile, Row) {
  const Row& row = GetParam();
  if (!row.pending.empty()) GTEST_SKIP() << "expected to fail until " << row.pending;
  if (row.as_root_skip && ::geteuid() == 0) GTEST_SKIP() << "root reads files whatever their permissions";
  if (row.memory_cap_kib > 0 && kAddressSanitizer)
    GTEST_SKIP() << "an AddressSanitizer build reserves terabytes of shadow address space: ulimit -v cannot apply";
  const fs::path dir = brdfbake::test::test_temp_dir(row.name);
  for (const File& f : row.files) {
    const fs::path p = dir / expand(f.name, dir);
    fs::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << f.bytes;
  }
  if (row.as_root_skip)
    for (const File& f : row.files) fs::permissions(dir / f.name, fs::perms::none);
  if (!row.setup.empty()) {  // FIFOs, links: before the lock is taken and the command runs
    const std::string setup = "cd " + dir.string() + " && " + expand(row.setup, dir);
    ASSERT_EQ(std::system(setup.c_str()), 0) << setup;
  }

  std::optional<brdfbake::OutputLock> lock;
  std::thread releaser;
  if (!row.hold_lock.empty()) {
    lock.emplace((dir / row.hold_lock).string(), false);
    if (row.release_after_ms > 0)
      releaser = std::thread([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(row.release_after_ms));
        lock.reset();
      });
  }
  const RowRun r = run_row(row, dir);
  if (releaser.joinable()) releaser.join();
  lock.reset();

  const std::string what = row.name + ": brdfbake " + expand(row.args, dir) + "\n  stderr: " + r.err;
  EXPECT_EQ(r.signal, 0) << what;
  EXPECT_EQ(r.code, row.code) << what;
  for (const auto& w : row.words)
    EXPECT_NE(r.err.find(expand(w, dir)), std::string::npos) << "missing '" << w << "' in " << what;
  for (const char* never : {"json.exception", "terminate called", "Sanitizer", "runtime error:", "what():", "Assertion",
                            "basic_string", "std::", "Segmentation", "core dumped"})
    EXPECT_EQ(r.err.find(never), std::string::npos) << "'" << never << "' in " << what;
  for (const auto& w : row.never) EXPECT_EQ(r.err.find(w), std::string::npos) << "'" << w << "' in " << what;
  if (row.code != 0) {
    if (!row.silent_ok) {
      EXPECT_FALSE(r.err.empty()) << what;
    }
    int lines = 0;
    for (char c : r.err) lines += c == '\n';
    EXPECT_LE(lines, row.max_lines) << what;
    EXPECT_EQ(r.err.rfind("brdfbake", 0) == 0 || row.max_lines > 1 || (row.silent_ok && r.err.empty()), true) << what;
  } else if (row.max_lines == 0) {
    EXPECT_TRUE(r.err.empty()) << what;
  }
  for (const auto& a : row.absent) EXPECT_FALSE(fs::exists(dir / expand(a, dir))) << a << " exists after " << what;
  for (const auto& k : row.kept) {
    bool found = false;
    for (const File& f : row.files)
      if (f.name == k) {
        found = true;
        EXPECT_EQ(read_file(dir / k), f.bytes) << k << " changed by " << what;
      }
    EXPECT_TRUE(found) << k;
  }
  for (const auto& [f, text] : row.file_has)
    EXPECT_NE(read_file(dir / f).find(text), std::string::npos) << f << " lacks '" << text << "' after " << what;
  for (const auto& [f, text] : row.file_lacks)
    EXPECT_EQ(read_file(dir / f).find(text), std::string::npos) << f << " holds '" << text << "' after " << what;
  if (row.check_output && r.code == 0) {
    SCOPED_TRACE(what);
    row.check_output(dir);
  }
  // Special files stay what they were: the row's FIFOs, and the machine's /dev/null (a run as root
  // that renamed a file over it would have replaced the device), with no lock file beside it.
  for (const auto& f : row.still_fifo) {
    struct stat st {};
    EXPECT_TRUE(::stat((dir / f).c_str(), &st) == 0 && S_ISFIFO(st.st_mode))
        << f << " is no longer a FIFO after " << what;
  }
  for (const auto& f : row.still_link) {
    struct stat st {};
    EXPECT_TRUE(::lstat((dir / f).c_str(), &st) == 0 && S_ISLNK(st.st_mode)) << f << " was replaced by " << what;
  }
  {
    struct stat st {};
    EXPECT_TRUE(::stat("/dev/null", &st) == 0 && S_ISCHR(st.st_mode))
        << "/dev/null is no longer a device after " << what;
    EXPECT_FALSE(fs::exists("/dev/.null.lock")) << what;
  }
  // Nothing half-written is left: no temporary and no lock file, save a live process's.
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const std::string rel = it->path().lexically_relative(dir).string();  // links (to /dev/stdout) not followed
    bool allowed = false;
    for (const auto& a : row.allowed_tmp) allowed |= rel.rfind(expand(a, dir), 0) == 0;
    if (allowed) continue;
    EXPECT_EQ(name.find(".tmp-"), std::string::npos) << "left behind: " << rel << " by " << what;
    EXPECT_FALSE(name.size() > 5 && name.compare(name.size() - 5, 5, ".lock") == 0)
        << "left behind: " << rel << " by " << what;
  }
  if (!::testing::Test::HasFailure()) fs::remove_all(dir);
}

// gtest names: letters, digits and '_' ("thin-film" becomes "thin_film").
std::string row_name(const ::testing::TestParamInfo<Row>& info) {
  std::string n = info.param.name;
  for (char& c : n)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return n;
}

INSTANTIATE_TEST_SUITE_P(Table, Hostile, ::testing::ValuesIn(all_rows()), row_name);

// The table's size and the classes it covers (issue 17 asks for 200 rows at least).
TEST(HostileTable, HasEveryClassAndAtLeast200Rows) {
  const std::vector<Row> rows = all_rows();
  EXPECT_GE(rows.size(), 200u);
  std::vector<std::string> names;
  for (const Row& r : rows) {
    EXPECT_EQ(std::count(names.begin(), names.end(), r.name), 0) << "two rows named " << r.name;
    names.push_back(r.name);
  }
  auto count = [&](const std::string& part) {
    return std::count_if(rows.begin(), rows.end(),
                         [&](const Row& r) { return r.name.find(part) != std::string::npos; });
  };
  for (const char* part : {"deep_",  "1e999",     "flt_max",   "f16",         "promises", "folder",  "through_a_file",
                           "locked", "stale",     "eval_csv",  "eval_binary", "fp64",     "cli_",    "job_",
                           "bake_",  "glb",       "special_",  "collide_",    "sibling_", "class7_", "lock_",
                           "sig",    "image_png", "image_exr", "image_hdr",   "cache_"})
    EXPECT_GT(count(part), 0) << "no row for " << part;
}

}  // namespace
