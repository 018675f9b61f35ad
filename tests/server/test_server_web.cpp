// The web page's routes (host/server/web_routes.cpp, docs/SERVICE.md "The web page"), as a client
// sees them: the page's files served without the token, byte for byte the sources, with their
// content types and security headers; every API route the page calls refused without the token;
// the schemas as the command line prints them; the plan as `bake --dry-run --json` prints it; a
// file's picture as `brdfbake view` draws it. The browser test is tests/python/test_web_page.py.
#include <gtest/gtest.h>

#include <cmath>

#include "brdfbake/tables.hpp"
#include "server/server_process.hpp"
#include "support/cli_runner.hpp"

namespace brdfbake::test {
namespace {

const std::string kToken = "web-routes-token-0123456789";

class ServerWeb : public SharedServer<ServerWeb> {
 public:
  static constexpr const char* kFolder = "web";
  static std::vector<std::string> arguments(const fs::path& dir) {
    write_file(dir / "inputs" / "maps" / "sky.hdr", "not really an image: only listed");
    write_file(dir / "inputs" / "scene.gltf", "{}");
    write_file(dir / "inputs" / ".hidden" / "secret.hdr", "x");
    write_file(dir / "inputs" / "notes.txt", "x");
    write_file(dir / "outside" / "far.hdr", "x");
    fs::create_symlink(dir / "outside" / "far.hdr", dir / "inputs" / "link.hdr");
    write_file(dir / "token", kToken + "\n");
    return {"--data",       (dir / "data").string(),
            "--input-root", (dir / "inputs").string(),
            "--token-file", (dir / "token").string(),
            "--max-upload", "2M",
            "--max-memory", "512M"};
  }
};

TEST_F(ServerWeb, PageFilesAreServedWithoutTheTokenAsTheSourcesAre) {
  auto anonymous = server_->client();
  const fs::path web = fs::path(BRDFBAKE_SOURCE_DIR) / "host" / "server" / "web";
  struct Asset {
    const char* route;
    const char* file;
    const char* type;
  };
  for (const Asset& a : {Asset{"/", "index.html", "text/html; charset=utf-8"},
                         Asset{"/index.html", "index.html", "text/html; charset=utf-8"},
                         Asset{"/app.js", "app.js", "text/javascript; charset=utf-8"},
                         Asset{"/app.css", "app.css", "text/css; charset=utf-8"}}) {
    auto r = anonymous.Get(a.route);
    ASSERT_TRUE(r) << a.route;
    EXPECT_EQ(r->status, 200) << a.route;
    EXPECT_EQ(r->body, read_file(web / a.file)) << a.route;  // embedded at build time, byte for byte
    EXPECT_EQ(r->get_header_value("Content-Type"), a.type);
    const std::string csp = r->get_header_value("Content-Security-Policy");
    EXPECT_EQ(csp.rfind("default-src 'self';", 0), 0u) << csp;
    EXPECT_EQ(csp.find("http"), std::string::npos) << csp;  // nothing loaded from elsewhere
    EXPECT_EQ(r->get_header_value("X-Content-Type-Options"), "nosniff");
    EXPECT_EQ(r->get_header_value("Cache-Control"), "no-cache");
    // No data in the page: no token, no input, no job.
    EXPECT_EQ(r->body.find(kToken), std::string::npos);
    EXPECT_EQ(r->body.find("sky.hdr"), std::string::npos);
    // Revalidation: the same bytes answer 304.
    const std::string etag = r->get_header_value("ETag");
    ASSERT_FALSE(etag.empty());
    auto again = anonymous.Get(a.route, httplib::Headers{{"If-None-Match", etag}});
    ASSERT_TRUE(again);
    EXPECT_EQ(again->status, 304) << a.route;
    EXPECT_TRUE(again->body.empty());
  }
  // Only those: other methods and names need the token like the API, and unknown names are 404.
  EXPECT_EQ(anonymous.Post("/", "x", "text/plain")->status, 401);
  EXPECT_EQ(anonymous.Get("/app.js/x")->status, 401);
  EXPECT_EQ(anonymous.Get("/secret.html")->status, 401);
  EXPECT_EQ(server_->client(kToken).Get("/secret.html")->status, 404);
}

TEST_F(ServerWeb, EveryRouteThePageCallsNeedsTheToken) {
  auto anonymous = server_->client();
  for (const char* path : {"/v1/health", "/v1/kinds", "/v1/bake/options", "/v1/inputs", "/v1/devices", "/v1/jobs",
                           "/v1/jobs/j0/job", "/v1/jobs/j0/view/a.exr", "/v1/jobs/j0/files/a.exr"}) {
    auto r = anonymous.Get(path);
    ASSERT_TRUE(r) << path;
    EXPECT_EQ(r->status, 401) << path;
    EXPECT_EQ(body_json(r).value("error", ""),
              "missing or wrong bearer token (Authorization: Bearer ...; see --token-file)");
  }
  EXPECT_EQ(anonymous.Post("/v1/plan", "{}", "application/json")->status, 401);
  EXPECT_EQ(anonymous.Post("/v1/bake", "{}", "application/json")->status, 401);
  EXPECT_EQ(anonymous.Delete("/v1/jobs/j0")->status, 401);
}

TEST_F(ServerWeb, SchemasAreTheCommandLines) {
  auto c = server_->client(kToken);
  auto kinds = c.Get("/v1/kinds");
  ASSERT_TRUE(kinds);
  EXPECT_EQ(kinds->status, 200);
  EXPECT_EQ(kinds->get_header_value("Content-Type"), "application/json");
  const CliRun cli = run_cli("kinds --json");
  ASSERT_EQ(cli.code, 0) << cli.err;
  EXPECT_EQ(kinds->body, cli.out);  // the one serialisation, byte for byte
  auto options = c.Get("/v1/bake/options");
  ASSERT_TRUE(options);
  EXPECT_EQ(options->status, 200);
  const json o = body_json(options)["options"];
  ASSERT_TRUE(o.is_array());
  // Every option of `brdfbake bake --help` that the schema makes, with its type and range.
  const CliRun help = run_cli("bake --help");
  std::map<std::string, json> by_name;
  for (const auto& d : o) {
    by_name[d["name"]] = d;
    // A flag on by default is spelled --no-NAME on the command line.
    const std::string option = d["option"], negated = "--no-" + option.substr(2);
    EXPECT_TRUE(help.out.find(option + " ") != std::string::npos || help.out.find(negated + " ") != std::string::npos)
        << option;
  }
  ASSERT_TRUE(by_name.count("chain_size") && by_name.count("environment") && by_name.count("target"));
  EXPECT_EQ(by_name["chain_size"]["type"], "integer");
  EXPECT_EQ(by_name["chain_size"]["min"], 1);
  // Canonical names only (issue 34): the old ones are aliases of the options, as the CLI spells them.
  EXPECT_EQ(by_name.count("cube_size"), 0u);
  EXPECT_EQ(by_name.count("prefilter_max_error"), 0u);
  EXPECT_EQ(by_name["chain_size"]["aliases"], json::array({"--cube-size"}));
  EXPECT_EQ(by_name["chain_max_error"]["aliases"], json::array({"--prefilter-max-error"}));
  EXPECT_EQ(by_name["environment"]["default"], "builtin:studio");
  EXPECT_NE(std::find(by_name["target"]["choices"].begin(), by_name["target"]["choices"].end(), "filament"),
            by_name["target"]["choices"].end());
}

TEST_F(ServerWeb, InputsListsWhatARequestMayReadAndNothingElse) {
  auto r = server_->client(kToken).Get("/v1/inputs");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200);
  const json o = body_json(r);
  EXPECT_EQ(o["input_root"], true);
  std::vector<std::string> envs, scenes;
  for (const auto& e : o["environments"]) envs.push_back(e["path"]);
  for (const auto& e : o["scenes"]) scenes.push_back(e["path"]);
  // The builtins, then the root's files by relative path: no hidden folder, no link out of the root,
  // no file of another kind.
  EXPECT_EQ(envs, (std::vector<std::string>{"builtin:studio", "builtin:sun", "maps/sky.hdr"}));
  EXPECT_EQ(scenes, (std::vector<std::string>{"scene.gltf"}));
  EXPECT_EQ(o["environments"][2]["bytes"], 32);
}

TEST_F(ServerWeb, PlanIsTheDryRunOfTheCommandLine) {
  auto c = server_->client(kToken);
  // The body by the old name (an alias), the command line by the canonical one: the same plan.
  auto r = c.Post("/v1/plan", R"({"cube_size": 32, "target": "filament"})", "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const json plan = body_json(r);
  const CliRun cli = run_cli("bake --dry-run --json --chain-size 32 --target filament");
  ASSERT_EQ(cli.code, 0) << cli.err;
  const json want = json::parse(cli.out);
  EXPECT_EQ(plan["job"]["tables"], want["tables"]);
  ASSERT_EQ(plan["tables"].size(), want["tables"].size());
  for (const auto& t : plan["tables"]) EXPECT_GT(t["estimated_bytes"].get<double>(), 0);
  // Each table's time and bytes, measured on the server's device (estimate_job): the bake of the
  // same options writes those bytes (tables baked at their own size for the estimate: exactly; the
  // fit of larger ones is held to its bound in tests/host/test_job.cpp).
  double bytes = 0, seconds = 0;
  for (const auto& t : plan["tables"]) {
    EXPECT_GE(t["seconds"].get<double>(), 0.0);
    EXPECT_GT(t["bytes"].get<double>(), 0.0);
    bytes += t["bytes"].get<double>();
    seconds += t["seconds"].get<double>();
  }
  EXPECT_EQ(plan["estimate"]["bytes"].get<double>(), bytes);
  EXPECT_GE(plan["estimate"]["seconds"].get<double>(), seconds);
  const std::string id =
      body_json(c.Post("/v1/bake", R"({"cube_size": 32, "target": "filament"})", "application/json")).value("id", "");
  const json job = wait_job(c, id);
  ASSERT_EQ(job["state"], "done") << job.dump();
  const json& files = job["manifest"]["files"];
  ASSERT_EQ(files.size(), plan["tables"].size());
  int compared = 0;
  for (size_t i = 0; i < files.size(); ++i) {
    const json& t = plan["tables"][i];
    EXPECT_EQ(files[i]["path"], t["output"]);
    if (t["method"] == "measured") {
      EXPECT_EQ(files[i]["bytes"], t["bytes"]) << t.dump();
      ++compared;
    }
  }
  EXPECT_GT(compared, 0) << "the SH is always baked at its own size";
  // Each file's figure under its name as the command line prints it (the page shows these), and the
  // deprecated error_bounds the same text without its name.
  int bounds = 0;
  for (const auto& f : files) {
    const std::string name = f.value("error_name", "");
    ASSERT_FALSE(name.empty()) << f.dump();
    const json& figure = job["error_figures"][f["path"].get<std::string>()];
    EXPECT_EQ(figure.value("error_name", ""), name);
    if (f[name].is_number()) {
      EXPECT_EQ(figure.value(name, ""), error_bound_text(f[name].get<double>()));
      EXPECT_EQ(job["error_bounds"].value(f["path"].get<std::string>(), ""), error_bound_text(f[name].get<double>()));
      ++bounds;
    } else {
      EXPECT_TRUE(figure[name].is_null()) << figure.dump();
    }
  }
  EXPECT_GT(bounds, 0);
  EXPECT_EQ(job["error_bounds"].size(), size_t(bounds));
  // Each engine file's delivered error (filament: the two KTX1 cubes and sh.txt), as its entry records it.
  const json& entries = job["manifest"]["engine"]["file_entries"];
  ASSERT_EQ(entries.size(), 3u) << entries.dump();
  int measured = 0;
  for (const auto& e : entries) {
    const json& figure = job["error_figures"][e["path"].get<std::string>()];
    EXPECT_EQ(figure.value("error_name", ""), "error_rms_rel");
    for (const char* name : {"error_rms_rel", "error_max_rel"})
      if (e[name].is_number()) {
        EXPECT_EQ(figure.value(name, ""), error_bound_text(e[name].get<double>())) << e.dump();
        ++measured;
      } else {
        EXPECT_TRUE(figure[name].is_null()) << figure.dump();
      }
  }
  EXPECT_EQ(measured, 4) << "_ibl.ktx and _skybox.ktx, two figures each";
  EXPECT_EQ(job["error_figures"].size(), files.size() + entries.size());
  // The device's load over the last minute counts at least the job it just ran (the estimate's
  // bakes and the job, within the minute: at least half the job's seconds, the two clocks apart).
  const json devices = body_json(c.Get("/v1/devices"));
  ASSERT_FALSE(devices["devices"].empty());
  const double load = devices["devices"][0]["load"].get<double>();
  EXPECT_LE(load, 1.0);
  EXPECT_GE(load * 60.0, 0.5 * job["seconds"].get<double>()) << devices.dump();
  EXPECT_GT(load, 0.0);
  // Refusals are the submission's, one line naming the option.
  auto bad = c.Post("/v1/plan", R"({"cube_size": -1})", "application/json");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400);
  EXPECT_EQ(body_json(bad).value("error", ""), "bake: chain_size: must be an integer in 1..2048 (got -1)");
  // A name and its alias together: refused, one line (not a silent pick).
  auto both = c.Post("/v1/plan", R"({"chain_size": 32, "cube_size": 64})", "application/json");
  ASSERT_TRUE(both);
  EXPECT_EQ(both->status, 400);
  EXPECT_EQ(body_json(both).value("error", ""),
            "bake: chain_size: given together with its alias cube_size (the same option): give one");
  auto both_env = c.Post("/v1/bake", R"({"environment": "builtin:sun", "env": "builtin:sun"})", "application/json");
  ASSERT_TRUE(both_env);
  EXPECT_EQ(both_env->status, 400);
  EXPECT_EQ(body_json(both_env).value("error", ""),
            "bake: environment: given together with its alias env (the same option): give one");
  auto outside = c.Post("/v1/plan", R"({"environment": "../token"})", "application/json");
  ASSERT_TRUE(outside);
  EXPECT_EQ(outside->status, 400);
  EXPECT_EQ(body_json(outside).value("error", ""),
            "bake: environment: '../token' must stay inside the input root (no '..')");
}

TEST_F(ServerWeb, ViewIsTheContactSheetOfBrdfbakeView) {
  auto c = server_->client(kToken);
  const std::string id = submit(c, json::parse(R"({"brdfbake_job": 1, "tables": [
      {"kind": "ggx", "size": 16, "output": "dfg.exr"},
      {"kind": "fresnel", "model": "schlick", "f0": 0.04, "size": 8, "output": "f.csv"}]})"));
  ASSERT_FALSE(id.empty());
  ASSERT_EQ(wait_job(c, id).value("state", ""), "done");
  auto r = c.Get(("/v1/jobs/" + id + "/view/dfg.exr").c_str());
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(r->get_header_value("Content-Type"), "image/png");
  EXPECT_EQ(r->body.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  // The same sheet as `brdfbake view dfg.exr --title dfg.exr` in the job's folder: the file named as
  // the job names it, not by where the server keeps it.
  TempDir out("web-view");
  const fs::path folder = dir_->path / "data" / "jobs" / id;
  const CliRun cli = run_cli("view dfg.exr --title dfg.exr --quiet -o " + (out.path / "sheet.png").string(), {},
                             "cd '" + folder.string() + "' &&");
  ASSERT_EQ(cli.code, 0) << cli.err;
  EXPECT_TRUE(r->body == read_file(out.path / "sheet.png")) << "the server's picture differs from brdfbake view's";
  EXPECT_EQ(r->body.find(folder.string()), std::string::npos);
  // What view cannot show, names that leave the folder, and files that are not there.
  auto manifest = c.Get(("/v1/jobs/" + id + "/view/manifest.json").c_str());
  ASSERT_TRUE(manifest);
  EXPECT_EQ(manifest->status, 200);  // a manifest is every file it lists
  auto up = c.Get(("/v1/jobs/" + id + "/view/..%2Fjobs.db").c_str());
  ASSERT_TRUE(up);
  EXPECT_EQ(up->status, 400);
  EXPECT_EQ(c.Get(("/v1/jobs/" + id + "/view/none.exr").c_str())->status, 404);
  EXPECT_EQ(c.Get("/v1/jobs/jnone/view/dfg.exr")->status, 404);
  // The folder as one tar file: every file, byte for byte what GET .../files/NAME serves.
  auto tar = c.Get(("/v1/jobs/" + id + "/archive").c_str());
  ASSERT_TRUE(tar);
  ASSERT_EQ(tar->status, 200);
  EXPECT_EQ(tar->get_header_value("Content-Type"), "application/x-tar");
  std::vector<std::string> names;
  size_t at = 0;
  while (at + 512 <= tar->body.size() && tar->body[at] != '\0') {
    const std::string header = tar->body.substr(at, 512);
    EXPECT_EQ(header.substr(257, 6), std::string("ustar\0", 6));
    unsigned sum = 0;
    for (size_t i = 0; i < 512; ++i)
      sum += (i >= 148 && i < 156) ? unsigned(' ') : static_cast<unsigned char>(header[i]);
    EXPECT_EQ(sum, std::stoul(header.substr(148, 6), nullptr, 8));
    const std::string name = header.substr(0, header.find('\0'));
    const size_t size = std::stoul(header.substr(124, 11), nullptr, 8);
    names.push_back(name);
    auto file = c.Get(("/v1/jobs/" + id + "/files/" + name).c_str());
    ASSERT_TRUE(file);
    EXPECT_TRUE(tar->body.substr(at + 512, size) == file->body) << name;
    at += 512 + (size + 511) / 512 * 512;
  }
  EXPECT_EQ(names, (std::vector<std::string>{"dfg.exr", "f.csv", "manifest.json"}));
  EXPECT_EQ(tar->body.size(), at + 1024);  // two zero blocks end it
  EXPECT_EQ(tar->body.find_first_not_of('\0', at), std::string::npos);
  // The job document: what `brdfbake run` reads to make the same files.
  auto doc = c.Get(("/v1/jobs/" + id + "/job").c_str());
  ASSERT_TRUE(doc);
  EXPECT_EQ(doc->status, 200);
  EXPECT_EQ(body_json(doc)["tables"][0]["output"], "dfg.exr");
}

// POST /v1/uploads: a file from the page, checked by the readers a bake uses before it is kept,
// stored under the data folder with a generated name, named "upload:..." in requests; refusals are
// the API's one line.
TEST_F(ServerWeb, UploadsAreCheckedConfinedAndBaked) {
  auto c = server_->client(kToken);
  const auto upload = [&](const std::string& name, const std::string& body) {
    return c.Post("/v1/uploads?name=" + name, body, "application/octet-stream");
  };
  const auto error_of = [](const httplib::Result& r) {
    const std::string e = body_json(r).value("error", "");
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;                 // one line
    EXPECT_EQ(e.find(dir_->path.string()), std::string::npos) << e;  // no server folder
    return e;
  };
  // A 4 x 2 Radiance HDR, flat scanlines, every pixel 1.0 (mantissa 128, exponent 129).
  std::string hdr = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 4\n";
  for (int i = 0; i < 8; ++i) hdr += std::string("\x80\x80\x80\x81", 4);

  EXPECT_EQ(server_->client().Post("/v1/uploads?name=sky.hdr", hdr, "application/octet-stream")->status, 401);
  // Uploads have their own limit (--max-upload, 2 MiB here; 64 MiB by default), not --max-body's
  // 1 MiB (the 1k maps are 1.4-1.7 MB): 413 from Content-Length beyond it, saying the size and the option.
  auto big = upload("big.hdr", std::string((2 << 20) + 1, 'x'));
  ASSERT_TRUE(big);
  EXPECT_EQ(big->status, 413);
  const std::string big_error = body_json(big).value("error", "");
  EXPECT_NE(big_error.find(std::to_string((2 << 20) + 1) + " bytes"), std::string::npos) << big_error;
  EXPECT_NE(big_error.find("--max-upload"), std::string::npos) << big_error;
  auto over_body = upload("over_body.hdr", std::string((3 << 20) / 2, 'x'));  // 1.5 MB: over --max-body only
  ASSERT_TRUE(over_body);
  EXPECT_EQ(over_body->status, 400) << over_body->body;  // read, and refused as not an image
  // Issue 34, class 3: a small file that promises a huge image is checked under the server's budget
  // (a share of --max-memory 512M) and refused as the server's limit (507), before any pixel is allocated.
  {
    std::string huge = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8192 +X 16384\n";
    huge += std::string(4096, '\x01');
    auto r = upload("huge.hdr", huge);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 507) << r->body;
    EXPECT_NE(error_of(r).find("--max-memory"), std::string::npos) << r->body;
  }
  // Not an image: the reader's line, naming the upload, and nothing kept.
  auto bad = upload("broken.hdr", "not an image");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400);
  const std::string bad_error = error_of(bad);
  EXPECT_NE(bad_error.find("broken.hdr"), std::string::npos) << bad_error;
  // Names are labels, never paths; unknown kinds are refused.
  for (const char* name : {"..%2Fx.hdr", "a%2Fb.hdr", ".hidden.hdr", "notes.txt", ""}) {
    auto r = upload(name, hdr);
    ASSERT_TRUE(r) << name;
    EXPECT_EQ(r->status, 400) << name;
    EXPECT_EQ(error_of(r).rfind("upload: name: ", 0), 0u) << name;
  }
  int kept = 0;
  for (const auto& e : fs::directory_iterator(dir_->path / "data" / "uploads")) kept += e.is_regular_file();
  EXPECT_EQ(kept, 0) << "refused uploads leave no file";
  for (const auto& e : fs::directory_iterator(dir_->path / "data" / "tmp"))
    ADD_FAILURE() << "an upload's check left " << e.path();

  // A good one: stored byte for byte under a generated name, then baked by that name.
  auto ok = upload("sky.hdr", hdr);
  ASSERT_TRUE(ok);
  ASSERT_EQ(ok->status, 201) << ok->body;
  const json u = body_json(ok);
  const std::string name = u.value("name", "");
  ASSERT_EQ(name.rfind("upload:", 0), 0u) << name;
  EXPECT_EQ(name.substr(name.size() - 8), "-sky.hdr");
  EXPECT_EQ(u["kind"], "environment");
  EXPECT_EQ(u["bytes"], hdr.size());
  EXPECT_EQ(read_file(dir_->path / "data" / "uploads" / name.substr(7)), hdr);
  auto posted =
      c.Post("/v1/bake", json{{"environment", name}, {"cube_size", 16}, {"lut_size", 8}}.dump(), "application/json");
  ASSERT_TRUE(posted);
  ASSERT_EQ(posted->status, 202) << posted->body;
  const json bake = body_json(posted);
  const json job = wait_job(c, bake.value("id", ""));
  ASSERT_EQ(job["state"], "done") << job.dump();
  // A uniform white environment: the SH's L00 is 2 sqrt(pi) (the radiance's projection on Y00).
  auto sh = c.Get("/v1/jobs/" + bake.value("id", "") + "/files/irradiance_sh3.json");
  ASSERT_TRUE(sh);
  const json coefficients = json::parse(sh->body)["radiance"];
  EXPECT_NEAR(coefficients[0][0].get<double>(), 2 * std::sqrt(M_PI), 1e-3) << coefficients.dump();

  // Names that are not this server's uploads: refused by the bake like any path out of its roots.
  for (const char* env : {"upload:../token", "upload:nothing.hdr"}) {
    auto r = c.Post("/v1/bake", json{{"environment", env}}.dump(), "application/json");
    ASSERT_TRUE(r) << env;
    EXPECT_EQ(r->status, 400) << env;
    EXPECT_NE(error_of(r).find("is not an upload of this server"), std::string::npos) << env;
  }
  // A scene: read as a bake reads it, then planned by its name.
  auto scene = upload("chair.gltf", R"({"asset": {"version": "2.0"}, "materials": [{"name": "Velvet",
      "extensions": {"KHR_materials_sheen": {"sheenColorFactor": [1, 1, 1]}}}]})");
  ASSERT_TRUE(scene);
  ASSERT_EQ(scene->status, 201) << scene->body;
  EXPECT_EQ(body_json(scene)["kind"], "scene");
  auto plan = c.Post("/v1/plan", json{{"scene", body_json(scene)["name"]}}.dump(), "application/json");
  ASSERT_TRUE(plan);
  ASSERT_EQ(plan->status, 200) << plan->body;
  EXPECT_NE(plan->body.find("charlie"), std::string::npos) << "the sheen rule fired";
  auto bad_scene = upload("bad.glb", "glTF but not really");
  ASSERT_TRUE(bad_scene);
  EXPECT_EQ(bad_scene->status, 400);
  error_of(bad_scene);
}

}  // namespace
}  // namespace brdfbake::test
