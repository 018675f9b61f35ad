// brdfbake serve, tested as a client sees it: the API, its errors, its limits and security, and the
// faults it must survive (kill -9, a client hanging up, bad bodies, a failing job, a full disk).
// Every server listens on 127.0.0.1 with an ephemeral port; every wait is bounded.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sqlite3.h>
#include <sys/mount.h>
#include <sys/socket.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <set>

#include "brdfbake/job.hpp"
#include "server/server_process.hpp"
#include "support/cli_runner.hpp"
#include "support/tolerances.hpp"

namespace brdfbake::test {
namespace {

// A small job: a Schlick table (closed form) and a DFG table.
json small_job() {
  return json::parse(R"({"brdfbake_job": 1, "tables": [
      {"kind": "fresnel", "model": "schlick", "f0": 0.04, "size": 8, "output": "f.csv"},
      {"kind": "ggx", "size": 16, "output": "dfg.exr"}]})");
}

// A job that keeps the device busy for a while: prefiltered chains of builtin:studio (quadrature
// to 1%), about half a second a table at 128 on two cores.
json slow_job(int tables, int size = 128) {
  json j = json::parse(R"({"brdfbake_job": 1, "tables": []})");
  const char* dist[] = {"ggx", "charlie", "ggx"};
  for (int i = 0; i < tables; ++i)
    j["tables"].push_back({{"kind", "prefilter"},
                           {"distribution", dist[i % 3]},
                           {"size", size},
                           {"min_size", 8 << (i / 2)},
                           {"output", "p" + std::to_string(i) + ".ktx2"}});
  return j;
}

// Schlick: F = F0 + (1 - F0)(1 - cos)^5 at the cell centres cos = (i + 0.5) / N.
void expect_schlick_csv(const std::string& text, int n, double f0) {
  const auto rows = csv_rows(text);
  ASSERT_EQ(static_cast<int>(rows.size()), n);
  for (int i = 0; i < n; ++i) {
    const double c = (i + 0.5) / n, want = f0 + (1 - f0) * std::pow(1 - c, 5);
    ASSERT_GE(rows[size_t(i)].size(), 4u);
    for (int ch = 1; ch <= 3; ++ch) EXPECT_NEAR(rows[size_t(i)][size_t(ch)], want, kFresnelFp32) << "cell " << i;
  }
}

// Waits until a job is running (at most 30 s).
bool wait_running(httplib::Client& c, const std::string& id) {
  for (int i = 0; i < 1500; ++i) {
    auto r = c.Get(("/v1/jobs/" + id).c_str());
    if (r && body_json(r).value("state", "") == "running") return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

// One server for the API tests that need no special options.
class ServerApi : public SharedServer<ServerApi> {
 public:
  static constexpr const char* kFolder = "api";
  static std::vector<std::string> arguments(const fs::path& dir) {
    write_file(dir / "inputs" / "materials.json",
               R"({"materials": [{"name": "red", "model": "lambert", "baseColor": [0.8, 0.2, 0.1]}]})");
    write_file(dir / "inputs" / "pairs.csv", "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,1,0,0,1\n0.6,0,0.8,-0.6,0,0.8\n");
    // A Phong lobe of shininess 1e6: its slice peaks at 152 098, beyond binary16's 65504.
    write_file(dir / "inputs" / "sharp.json",
               R"({"materials": [{"name": "a", "model": "phong", "shininess": 1000000, "specularColor": [1, 1, 1]}]})");
    write_file(dir / "outside" / "secret.json", R"({"materials": []})");
    fs::create_symlink(dir / "outside" / "secret.json", dir / "inputs" / "link.json");
    return {"--data", (dir / "data").string(), "--input-root", (dir / "inputs").string(), "--max-body",
            "64K",    "--max-memory",          "256M"};
  }
};

TEST_F(ServerApi, HealthDevicesAndMetrics) {
  auto c = server_->client();
  auto h = c.Get("/v1/health");
  ASSERT_TRUE(h);
  EXPECT_EQ(h->status, 200);
  EXPECT_EQ(body_json(h).value("status", ""), "ok");
  auto d = c.Get("/v1/devices");
  ASSERT_TRUE(d);
  const json devices = body_json(d)["devices"];
  ASSERT_GE(devices.size(), 2u);  // the default device and the reference
  EXPECT_EQ(devices.back()["key"], "reference");
  // A job, so that the bake time histogram has a kind.
  const std::string id = submit(c, small_job());
  ASSERT_FALSE(id.empty());
  EXPECT_EQ(wait_job(c, id)["state"], "done");
  // Each OpenCL device's work rate (the choice of a job's device reads it), measured by its warm-up
  // or by the job; the reference is chosen only by name and has none.
  auto d2 = c.Get("/v1/devices");
  ASSERT_TRUE(d2);
  const json after = body_json(d2)["devices"];
  ASSERT_TRUE(after[0]["rate"].is_number()) << after.dump();
  EXPECT_GT(after[0]["rate"].get<double>(), 0.0);
  EXPECT_TRUE(after.back()["rate"].is_null()) << after.dump();
  auto m = c.Get("/metrics");
  ASSERT_TRUE(m);
  EXPECT_EQ(m->status, 200);
  EXPECT_EQ(m->get_header_value("Content-Type").rfind("text/plain; version=0.0.4", 0), 0u);
  for (const char* line :
       {"# TYPE brdfbake_jobs gauge", "brdfbake_jobs{state=\"done\"} ", "# TYPE brdfbake_queue_length gauge",
        "brdfbake_queue_length{device=\"reference\"} 0", "# TYPE brdfbake_bake_seconds histogram",
        "brdfbake_bake_seconds_bucket{kind=\"fresnel\",le=\"+Inf\"} ",
        "# TYPE brdfbake_device_busy_seconds_total counter"})
    EXPECT_NE(m->body.find(line), std::string::npos) << line << "\n" << m->body;
}

TEST_F(ServerApi, JobRunsAndServesItsFiles) {
  auto c = server_->client();
  auto r = c.Post("/v1/jobs", small_job().dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 202) << r->body;
  const std::string id = body_json(r)["id"];
  EXPECT_EQ(r->get_header_value("Location"), "/v1/jobs/" + id);
  const json s = wait_job(c, id);
  ASSERT_EQ(s["state"], "done") << s.dump();
  EXPECT_EQ(s["files"], json({"f.csv", "dfg.exr", "manifest.json"}));
  auto f = c.Get(("/v1/jobs/" + id + "/files/f.csv").c_str());
  ASSERT_TRUE(f);
  EXPECT_EQ(f->status, 200);
  EXPECT_EQ(f->get_header_value("Content-Type"), "text/csv; charset=utf-8");
  expect_schlick_csv(f->body, 8, 0.04);
  auto e = c.Get(("/v1/jobs/" + id + "/files/dfg.exr").c_str());
  ASSERT_TRUE(e);
  EXPECT_EQ(e->get_header_value("Content-Type"), "image/x-exr");
  EXPECT_EQ(static_cast<double>(e->body.size()), s["manifest"]["files"][1]["bytes"].get<double>());
  EXPECT_EQ(e->body.substr(0, 4), std::string("\x76\x2f\x31\x01", 4));  // the OpenEXR magic number
  auto m = c.Get(("/v1/jobs/" + id + "/files/manifest.json").c_str());
  ASSERT_TRUE(m);
  EXPECT_EQ(m->get_header_value("Content-Type"), "application/json");
  EXPECT_EQ(json::parse(m->body)["files"].size(), 2u);
  // The list has it; the same files as a local run of the same job, value for value.
  auto list = c.Get("/v1/jobs?state=done&limit=1000");
  ASSERT_TRUE(list);
  bool listed = false;
  const json jobs = body_json(list)["jobs"];
  for (const auto& j : jobs) listed |= j["id"] == id;
  EXPECT_TRUE(listed);
  TempDir local("api-local");
  Job job = parse_job(small_job().dump(), "job");
  job.output_dir = (local.path / "out").string();
  run_job(job);
  EXPECT_EQ(csv_rows(read_file(local.path / "out" / "f.csv")), csv_rows(f->body));
}

TEST_F(ServerApi, TableFastPathReturnsTheFile) {
  auto c = server_->client();
  const std::string body = R"({"kind": "fresnel", "model": "schlick", "f0": 0.5, "size": 16, "output": "s.csv"})";
  auto r = c.Post("/v1/tables", body, "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(r->get_header_value("Content-Type"), "text/csv; charset=utf-8");
  EXPECT_EQ(r->get_header_value("Content-Disposition"), "attachment; filename=\"s.csv\"; filename*=UTF-8''s.csv");
  expect_schlick_csv(r->body, 16, 0.5);
  // The same request again: the same bytes, from the result cache.
  auto again = c.Post("/v1/tables", body, "application/json");
  ASSERT_TRUE(again);
  EXPECT_EQ(again->get_header_value("X-Brdfbake-Cache"), "hit");
  EXPECT_EQ(again->body, r->body);
  // A DFG table by default name and format.
  auto dfg = c.Post("/v1/tables", R"({"kind": "ggx", "size": 32})", "application/json");
  ASSERT_TRUE(dfg);
  EXPECT_EQ(dfg->status, 200);
  EXPECT_EQ(dfg->get_header_value("Content-Disposition"),
            "attachment; filename=\"dfg_ggx_32.exr\"; filename*=UTF-8''dfg_ggx_32.exr");
  EXPECT_EQ(dfg->get_header_value("X-Brdfbake-Error-Name"), "error_bound_mixed");
  EXPECT_FALSE(dfg->get_header_value("X-Brdfbake-Error-Value").empty());
  // A bad one names the field as the table spells it.
  auto bad = c.Post("/v1/tables", R"({"kind": "ggx", "size": 0})", "application/json");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400);
  EXPECT_EQ(body_json(bad)["error"], "table.size: must be an integer in 1..16384 (got 0)");
}

// The value of a key a KTX2 file records ("brdfbake:error_bound"), or "".
std::string ktx2_value(const std::string& file, const std::string& key) {
  const std::string k = "brdfbake:" + key + std::string(1, '\0');
  const size_t at = file.find(k);
  if (at == std::string::npos) return "";
  const size_t end = file.find('\0', at + k.size());
  return end == std::string::npos ? "" : file.substr(at + k.size(), end - at - k.size());
}

TEST_F(ServerApi, TableErrorBoundHeaderIsWhatTheFileRecords) {
  // In binary16 the storage error (about 2^-12 relative) is added to the integration bound: the
  // header carries the delivered bound, the file's own text (rounded up, never below), not the
  // integration bound alone.
  auto c = server_->client();
  auto r =
      c.Post("/v1/tables", R"({"kind": "ggx", "size": 32, "pixel": "f16", "output": "dfg.ktx2"})", "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const std::string recorded = ktx2_value(r->body, "error_bound_mixed"),
                    integration = ktx2_value(r->body, "integration_error_bound");
  ASSERT_FALSE(recorded.empty());
  ASSERT_FALSE(integration.empty());
  // The figure under the name the file gives it (docs/CONVENTIONS.md, "Error figures").
  EXPECT_EQ(ktx2_value(r->body, "error_name"), "error_bound_mixed");
  EXPECT_EQ(r->get_header_value("X-Brdfbake-Error-Name"), "error_bound_mixed");
  EXPECT_EQ(r->get_header_value("X-Brdfbake-Error-Value"), recorded);
  EXPECT_GT(std::stod(r->get_header_value("X-Brdfbake-Error-Value")), std::stod(integration) + std::ldexp(1.0, -13))
      << "the storage error is part of the bound";
  // The deprecated alias (docs/SERVICE.md) says the same for one release.
  EXPECT_EQ(r->get_header_value("X-Brdfbake-Error-Bound"), recorded);
  // A format that adds nothing (float32 EXR) records the integration bound, rounded the same way.
  auto exr = c.Post("/v1/tables", R"({"kind": "ggx", "size": 32, "output": "dfg32.exr"})", "application/json");
  ASSERT_TRUE(exr);
  ASSERT_EQ(exr->status, 200) << exr->body;
  EXPECT_EQ(exr->get_header_value("X-Brdfbake-Error-Value"), integration);
}

// Each kind's figure under its own name, the same in the header as in the file and in a job's
// manifest (docs/CONVENTIONS.md, "Error figures"): a prefiltered chain's error_bound_rel, the
// irradiance SH's error_rms_rel, a DFG table's error_bound_mixed; a kind that measures none names
// its figure and sends no value.
TEST_F(ServerApi, TableErrorHeadersNameTheKindsFigure) {
  auto c = server_->client();
  struct Case {
    const char* body;
    const char* name;
  };
  const Case cases[] = {
      {R"({"kind": "ggx", "size": 16, "pixel": "f16", "output": "g.ktx2"})", "error_bound_mixed"},
      {R"({"kind": "prefilter", "environment": "builtin:sun", "size": 16, "min_size": 4, "output": "p.ktx2"})",
       "error_bound_rel"},
      {R"({"kind": "irradiance", "environment": "builtin:sun", "output": "sh.json"})", "error_rms_rel"},
  };
  for (const Case& k : cases) {
    SCOPED_TRACE(k.body);
    auto r = c.Post("/v1/tables", k.body, "application/json");
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    EXPECT_EQ(r->get_header_value("X-Brdfbake-Error-Name"), k.name);
    const std::string value = r->get_header_value("X-Brdfbake-Error-Value");
    ASSERT_FALSE(value.empty());
    EXPECT_EQ(r->get_header_value("X-Brdfbake-Error-Bound"), value);  // the deprecated alias
    // what the file itself records under that name
    if (std::string(k.body).find(".ktx2") != std::string::npos) {
      EXPECT_EQ(ktx2_value(r->body, "error_name"), k.name);
      EXPECT_EQ(ktx2_value(r->body, k.name), value);
    } else {
      const json sh = json::parse(r->body);
      ASSERT_TRUE(sh.contains("metadata")) << r->body.substr(0, 400);
      EXPECT_EQ(sh["metadata"].value("error_name", ""), k.name);
      EXPECT_EQ(sh["metadata"].value(k.name, ""), value);
    }
    // ... and a job's manifest, for the same table
    const json job =
        wait_job(c, body_json(c.Post("/v1/jobs", std::string(R"({"tables": [)") + k.body + "]}", "application/json"))
                        .value("id", ""));
    ASSERT_EQ(job["state"], "done") << job.dump();
    const json& f = job["manifest"]["files"][0];
    EXPECT_EQ(f["error_name"], k.name);
    ASSERT_TRUE(f[k.name].is_number()) << f.dump();
    EXPECT_EQ(error_bound_text(f[k.name].get<double>()), value);
    const json& figure = job["error_figures"][f["path"].get<std::string>()];
    EXPECT_EQ(figure["error_name"], k.name);
    EXPECT_EQ(figure[k.name], value);
  }
  // tabulate measures none: the name, no value
  auto none = c.Post(
      "/v1/tables",
      R"({"kind": "tabulate", "material": "sharp.json", "layout": "slice", "res": 16, "pixel": "f32", "output": "n.ktx2"})",
      "application/json");
  ASSERT_TRUE(none);
  ASSERT_EQ(none->status, 200) << none->body;
  EXPECT_EQ(none->get_header_value("X-Brdfbake-Error-Name"), "error_bound_mixed");
  EXPECT_FALSE(none->has_header("X-Brdfbake-Error-Value"));
  EXPECT_FALSE(none->has_header("X-Brdfbake-Error-Bound"));
}

// pixel astc4x4 (issue 24 item 9) reaches the server as every other front end: the chain comes back
// as ASTC HDR KTX2 (vkFormat VK_FORMAT_ASTC_4x4_SFLOAT_BLOCK = 1000066000 at byte 12) whose header
// bound is the file's (integration plus the measured compression error); a kind that is no chain
// is refused with 400 before anything is baked.
TEST_F(ServerApi, AstcChainsAndTheirBound) {
  auto c = server_->client();
  auto r = c.Post(
      "/v1/tables",
      R"({"kind": "prefilter", "environment": "builtin:sun", "size": 16, "min_size": 4, "pixel": "astc4x4", "output": "c.ktx2"})",
      "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  ASSERT_GE(r->body.size(), 16u);
  uint32_t vk_format = 0;
  std::memcpy(&vk_format, r->body.data() + 12, 4);
  EXPECT_EQ(vk_format, 1000066000u);
  const std::string recorded = ktx2_value(r->body, "error_bound_rel"), storage = ktx2_value(r->body, "storage_error");
  ASSERT_FALSE(recorded.empty());
  ASSERT_FALSE(storage.empty());
  EXPECT_EQ(r->get_header_value("X-Brdfbake-Error-Name"), "error_bound_rel");
  EXPECT_EQ(r->get_header_value("X-Brdfbake-Error-Value"), recorded);
  EXPECT_GE(std::stod(recorded), std::stod(storage));
  auto bad =
      c.Post("/v1/tables", R"({"kind": "ggx", "size": 8, "pixel": "astc4x4", "output": "d.ktx2"})", "application/json");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400) << bad->body;
  EXPECT_NE(bad->body.find("pixel"), std::string::npos) << bad->body;
}

TEST_F(ServerApi, ClampWarningsReachTheClient) {
  auto c = server_->client();
  // clamp_f16: the values beyond 65504 are clamped, recorded in the file and warned about, naming
  // the output as the request does (never the server's scratch folder).
  const std::string body =
      R"({"kind": "tabulate", "material": "sharp.json", "layout": "slice", "res": 64, "pixel": "f16", "clamp_f16": true, "output": "t.ktx2"})";
  auto r = c.Post("/v1/tables", body, "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_FALSE(ktx2_value(r->body, "f16_clamped").empty());
  ASSERT_EQ(r->get_header_value_count("X-Brdfbake-Warning"), 1u);
  const std::string warning = r->get_header_value("X-Brdfbake-Warning");
  EXPECT_EQ(warning.rfind("'t.ktx2': ", 0), 0u) << warning;
  EXPECT_NE(warning.find("clamped to 65504"), std::string::npos) << warning;
  // From the result cache: the same warning.
  auto again = c.Post("/v1/tables", body, "application/json");
  ASSERT_TRUE(again);
  EXPECT_EQ(again->get_header_value("X-Brdfbake-Cache"), "hit");
  EXPECT_EQ(again->get_header_value("X-Brdfbake-Warning"), warning);
  // Without clamp_f16: refused, the message naming the output and the option.
  auto refused = c.Post(
      "/v1/tables",
      R"({"kind": "tabulate", "material": "sharp.json", "layout": "slice", "res": 64, "pixel": "f16", "output": "t.ktx2"})",
      "application/json");
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->status, 400);
  const std::string message = body_json(refused).value("error", "");
  EXPECT_EQ(message.rfind("'t.ktx2': ", 0), 0u) << message;
  EXPECT_NE(message.find("clamp_f16"), std::string::npos) << message;
  // A table nothing was clamped in: no warning.
  auto plain = c.Post("/v1/tables", R"({"kind": "ggx", "size": 8})", "application/json");
  ASSERT_TRUE(plain);
  EXPECT_EQ(plain->get_header_value_count("X-Brdfbake-Warning"), 0u);
  // A job: its result lists the warning, naming the file inside the job's folder.
  const std::string id =
      submit(c, json::parse(R"({"tables": [{"kind": "tabulate", "material": "sharp.json", "layout": "slice",
                                                    "res": 64, "pixel": "f16", "clamp_f16": true, "output": "t.h"}]})"));
  ASSERT_FALSE(id.empty());
  const json s = wait_job(c, id);
  ASSERT_EQ(s["state"], "done") << s.dump();
  ASSERT_TRUE(s.contains("warnings")) << s.dump();
  ASSERT_EQ(s["warnings"].size(), 1u) << s.dump();
  const std::string w = s["warnings"][0];
  EXPECT_EQ(w.rfind("'t.h': ", 0), 0u) << w;
  EXPECT_NE(w.find("clamped to 65504"), std::string::npos) << w;
}

TEST_F(ServerApi, BadJobGetsTheCommandLinesMessage) {
  const json job = json::parse(R"({"tables": [{"kind": "ggx", "size": -1}]})");
  write_file(dir_->path / "job.json", job.dump());
  const CliRun local = run_cli("run " + (dir_->path / "job.json").string() + " -o " + (dir_->path / "never").string());
  EXPECT_EQ(local.code, 2);
  auto c = server_->client();
  const std::string source = (dir_->path / "job.json").string();
  auto r = c.Post(("/v1/jobs?source=" + source).c_str(), job.dump(), "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  const std::string message = body_json(r)["error"];
  EXPECT_EQ(message, source + ": tables[0].size: must be an integer in 1..16384 (got -1)");
  EXPECT_EQ(local.err, "brdfbake run: " + message + "\n");
  // Not JSON, truncated, nested too deep, not an object, an unknown field.
  for (const auto& [b, words] : std::vector<std::pair<std::string, std::string>>{
           {"{\"tables\": [", "malformed JSON"},
           {"tables", "malformed JSON"},
           {std::string(100, '[') + std::string(100, ']'), "nested deeper than 64"},
           {"[]", "a job is a JSON object"},
           {R"({"tables": [], "colour": 1})", "colour: unknown field"},
           {R"({"tables": [{"kind": "ggx", "sise": 8}]})", "tables[0].sise: unknown field"}}) {
    auto e = c.Post("/v1/jobs", b, "application/json");
    ASSERT_TRUE(e);
    EXPECT_EQ(e->status, 400) << b;
    EXPECT_NE(body_json(e).value("error", "").find(words), std::string::npos) << body_json(e).dump();
  }
}

TEST_F(ServerApi, NotFoundAndTooLarge) {
  auto c = server_->client();
  auto r = c.Get("/v1/jobs/jnosuchjob");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 404);
  EXPECT_EQ(body_json(r)["error"], "no job 'jnosuchjob'");
  r = c.Get("/v1/nothing");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 404);
  EXPECT_TRUE(body_json(r).contains("error"));
  const std::string id = submit(c, small_job());
  ASSERT_EQ(wait_job(c, id)["state"], "done");
  r = c.Get(("/v1/jobs/" + id + "/files/nothing.exr").c_str());
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 404);
  r = c.Get(("/v1/jobs/" + id + "/files/..%2F..%2Fjobs.db").c_str());
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  // --max-body 64K: a larger body is refused before it is parsed.
  r = c.Post("/v1/jobs", std::string(70 * 1024, ' '), "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 413);
  EXPECT_NE(body_json(r).value("error", "").find("--max-body"), std::string::npos);
  EXPECT_EQ(c.Get("/v1/health")->status, 200);
}

TEST_F(ServerApi, PathsStayInsideTheRoots) {
  auto c = server_->client();
  const std::string inputs = (dir_->path / "inputs").string();
  auto eval_job = [](const std::string& material) {
    return json{{"tables", {{{"kind", "eval"}, {"material", material}, {"input", "pairs.csv"}, {"output", "e.csv"}}}}};
  };
  // Inside the root: relative, or absolute; the Lambert value is base_color / pi.
  for (const std::string& m : {std::string("materials.json"), inputs + "/materials.json"}) {
    const std::string id = submit(c, eval_job(m));
    ASSERT_FALSE(id.empty()) << m;
    const json s = wait_job(c, id);
    ASSERT_EQ(s["state"], "done") << s.dump();
    const auto rows = csv_rows(c.Get(("/v1/jobs/" + id + "/files/e.csv").c_str())->body);
    ASSERT_EQ(rows.size(), 2u);
    for (const auto& row : rows) {
      ASSERT_EQ(row.size(), 3u);
      EXPECT_NEAR(row[0], 0.8 / M_PI, kBrdfFp32);
      EXPECT_NEAR(row[2], 0.1 / M_PI, kBrdfFp32);
    }
  }
  // Outside: '..', an absolute path elsewhere, a symbolic link that leads out, environments.
  const std::vector<std::pair<json, std::string>> refused = {
      {eval_job("../outside/secret.json"),
       "job: tables[0].material: '../outside/secret.json' must stay inside the input root (no '..')"},
      {eval_job("/etc/passwd"), "job: tables[0].material: '/etc/passwd' is outside the server's input root"},
      {eval_job("link.json"),
       "job: tables[0].material: 'link.json' leads outside the server's input root (a symbolic link)"},
      {eval_job("missing.json"), "job: tables[0].material: 'missing.json' not found under the server's input root"},
      {json{{"environment", "/etc/hosts"}, {"tables", json::array()}},
       "job: environment: '/etc/hosts' is outside the server's input root"},
      {json{{"tables", {{{"kind", "prefilter"}, {"environment", "../x_{face}.hdr"}}}}},
       "job: tables[0].environment: '../x_px.hdr' must stay inside the input root (no '..')"},
  };
  for (const auto& [job, message] : refused) {
    auto r = c.Post("/v1/jobs", job.dump(), "application/json");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 400) << job.dump();
    EXPECT_EQ(body_json(r).value("error", ""), message);
  }
  // A scene for /v1/bake, and the input of one table.
  auto r = c.Post("/v1/bake", R"({"scene": "/etc/passwd"})", "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  EXPECT_EQ(body_json(r)["error"], "bake: scene: '/etc/passwd' is outside the server's input root");
  r = c.Post("/v1/tables", R"({"kind": "tabulate", "layout": "albedo", "material": "../outside/secret.json"})",
             "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  EXPECT_EQ(body_json(r)["error"],
            "table.material: '../outside/secret.json' must stay inside the input root (no '..')");
  // Outputs are confined to the job's folder.
  r = c.Post("/v1/jobs", R"({"tables": [{"kind": "ggx", "size": 4, "output": "../../escape.exr"}]})",
             "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  EXPECT_NE(body_json(r).value("error", "").find("must stay inside the output folder"), std::string::npos);
}

TEST_F(ServerApi, MemoryEstimateRefusesBeforeAllocating) {
  auto c = server_->client();
  // An 8192^2 DFG table needs about 3.3 GiB, more than this server's --max-memory 256M: refused
  // before anything is queued or allocated, naming the table.
  auto r = c.Post("/v1/jobs", R"({"tables": [{"kind": "ggx", "size": 8192}]})", "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  EXPECT_EQ(body_json(r).value("error", ""),
            "job: tables[0] (ggx): needs about 3.3 GiB, more than the server allows a bake (256 MiB, --max-memory); "
            "nothing was started");
  r = c.Post("/v1/tables", R"({"kind": "ggx", "size": 8192})", "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  TableRequest t;
  t.kind = TableKind::Ggx;
  t.params = {{"size", 8192.0}};
  validate_table(t);
  // The estimate counts the host table, its device buffer and the writer's copy of 3 floats a texel.
  EXPECT_GE(estimate_table_bytes(t), 3ull * 8192ull * 8192ull * 3ull * 4ull);
}

TEST_F(ServerApi, ClientHangsUpMidDownload) {
  auto c = server_->client();
  json job = json::parse(R"({"tables": [{"kind": "prefilter", "size": 128, "pixel": "f32", "output": "big.ktx2"}]})");
  const std::string id = submit(c, job);
  const json s = wait_job(c, id);
  ASSERT_EQ(s["state"], "done") << s.dump();
  const auto size = s["manifest"]["files"][0]["bytes"].get<std::uint64_t>();
  ASSERT_GT(size, 1u << 20);
  // Read 16 KiB of it, then hang up, three times.
  for (int k = 0; k < 3; ++k) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<uint16_t>(server_->port()));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ASSERT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
    const std::string req = "GET /v1/jobs/" + id + "/files/big.ktx2 HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
    ASSERT_EQ(::send(fd, req.data(), req.size(), MSG_NOSIGNAL), static_cast<ssize_t>(req.size()));
    char buf[16384];
    size_t got = 0;
    while (got < sizeof buf) {
      const ssize_t n = ::recv(fd, buf, sizeof buf - got, 0);
      if (n <= 0) break;
      got += static_cast<size_t>(n);
    }
    EXPECT_EQ(got, sizeof buf);
    ::close(fd);
  }
  // The server is well, and the file whole.
  EXPECT_EQ(c.Get("/v1/health")->status, 200);
  auto whole = c.Get(("/v1/jobs/" + id + "/files/big.ktx2").c_str());
  ASSERT_TRUE(whole);
  EXPECT_EQ(whole->body.size(), size);
  EXPECT_EQ(whole->body.substr(0, 12), std::string("\xABKTX 20\xBB\r\n\x1A\n", 12));
}

TEST_F(ServerApi, TruncatedBodyDoesNotHang) {
  // Content-Length promises 1000 bytes; 10 come, then the client closes.
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<uint16_t>(server_->port()));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  const std::string req =
      "POST /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\nContent-Length: "
      "1000\r\n\r\n{\"tables\":";
  ASSERT_EQ(::send(fd, req.data(), req.size(), MSG_NOSIGNAL), static_cast<ssize_t>(req.size()));
  ::shutdown(fd, SHUT_WR);
  char buf[4096];
  const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
  ::close(fd);
  // Either a 400 or a closed connection; never a job.
  if (n > 0) {
    EXPECT_EQ(std::string(buf, size_t(n)).rfind("HTTP/1.1 400", 0), 0u) << std::string(buf, size_t(n));
  }
  auto c = server_->client();
  EXPECT_EQ(c.Get("/v1/health")->status, 200);
}

TEST_F(ServerApi, JobFailingOnTheDeviceIsAFailedJob) {
  auto c = server_->client();
  // The reference backend cannot prefilter a 512 cube: accepted, then failed with its reason.
  const std::string id =
      submit(c, json::parse(R"({"device": "reference", "tables": [{"kind": "prefilter", "size": 512}]})"));
  ASSERT_FALSE(id.empty());
  const json s = wait_job(c, id);
  EXPECT_EQ(s["state"], "failed") << s.dump();
  EXPECT_NE(s.value("error", "").find("reference"), std::string::npos) << s.dump();
  EXPECT_EQ(s.value("exit_code", 0), 2) << "the request exceeds what the reference backend bakes: " << s.dump();
  auto f = c.Get(("/v1/jobs/" + id + "/files/manifest.json").c_str());
  ASSERT_TRUE(f);
  EXPECT_EQ(f->status, 404);  // a failed job has no files
  EXPECT_FALSE(fs::exists(dir_->path / "data" / "jobs" / id));
  // The device serves the next job.
  EXPECT_EQ(wait_job(c, submit(c, small_job()))["state"], "done");
}

TEST_F(ServerApi, DevicesRunConcurrently) {
  auto c = server_->client();
  // The reference is kept busy by a job of 40 converged reference DFG tables (sizes 64 to 103, so
  // that no two are one bake; a second or more each alone), cancelled only at the end: it cannot
  // finish within the test. A job on the OpenCL device submitted meanwhile finishes while it runs
  // (one queue per device); with one queue it would wait behind the reference job.
  json slow_doc = json::parse(R"({"device": "reference", "tables": []})");
  for (int i = 0; i < 40; ++i)
    slow_doc["tables"].push_back({{"kind", "ggx"}, {"size", 64 + i}, {"output", "t" + std::to_string(i) + ".exr"}});
  const std::string slow = submit(c, slow_doc);
  ASSERT_TRUE(wait_running(c, slow));
  const json q = wait_job(c, submit(c, small_job()));
  ASSERT_EQ(q["state"], "done") << q.dump();
  EXPECT_NE(q["device"], "reference");
  const json r = body_json(c.Get(("/v1/jobs/" + slow).c_str()));
  EXPECT_EQ(r["state"], "running") << "the device job finished while the reference job ran: " << r.dump();
  EXPECT_EQ(r["device"], "reference");
  // The reference job is cancelled before its next table.
  auto del = c.Delete(("/v1/jobs/" + slow).c_str());
  ASSERT_TRUE(del);
  EXPECT_EQ(del->status, 202);
  EXPECT_EQ(wait_job(c, slow)["state"], "cancelled");
}

TEST_F(ServerApi, CommandLineRunAndBakeThroughTheServer) {
  write_file(dir_->path / "cli.json", small_job().dump());
  const std::string out = (dir_->path / "cli-remote").string(), local = (dir_->path / "cli-local").string();
  const CliRun remote =
      run_cli("run " + (dir_->path / "cli.json").string() + " --server " + server_->url() + " -o " + out);
  ASSERT_EQ(remote.code, 0) << remote.err;
  EXPECT_NE(remote.out.find("wrote " + out + ": 2 files from 2 bakes"), std::string::npos) << remote.out;
  ASSERT_EQ(run_cli("run " + (dir_->path / "cli.json").string() + " --quiet -o " + local).code, 0);
  for (const char* f : {"f.csv", "dfg.exr", "manifest.json"}) EXPECT_TRUE(fs::exists(fs::path(out) / f)) << f;
  EXPECT_EQ(csv_rows(read_file(fs::path(out) / "f.csv")), csv_rows(read_file(fs::path(local) / "f.csv")));
  EXPECT_EQ(fs::file_size(fs::path(out) / "dfg.exr"), fs::file_size(fs::path(local) / "dfg.exr"));
  // bake --server: the plan printed here, baked there, files here.
  const std::string baked = (dir_->path / "bake-remote").string();
  const CliRun bake =
      run_cli("bake --server " + server_->url() + " --lut-size 16 --cube-size 32 --min-size 8 -o " + baked);
  ASSERT_EQ(bake.code, 0) << bake.err;
  EXPECT_NE(bake.out.find("3 tables:"), std::string::npos) << bake.out;
  for (const char* f : {"dfg_ggx_multiscatter_16.exr", "prefilter_ggx_32.ktx2", "irradiance_sh3.json", "manifest.json"})
    EXPECT_TRUE(fs::exists(fs::path(baked) / f)) << f;
  // A bad job: the local run's exit code and message.
  write_file(dir_->path / "bad.json", R"({"tables": [{"kind": "ggx", "size": -1}]})");
  const CliRun bad =
      run_cli("run " + (dir_->path / "bad.json").string() + " --server " + server_->url() + " -o " + out);
  EXPECT_EQ(bad.code, 2);
  EXPECT_EQ(bad.err, "brdfbake run: " + (dir_->path / "bad.json").string() +
                         ": tables[0].size: must be an integer in 1..16384 (got -1)\n");
  // No server there: a runtime failure, exit 1.
  const CliRun none = run_cli("run " + (dir_->path / "cli.json").string() + " --server http://127.0.0.1:1 -o " + out);
  EXPECT_EQ(none.code, 1);
  EXPECT_NE(none.err.find("cannot reach the server"), std::string::npos) << none.err;
}

// A folder output (a cube written as face images) and an engine target's files: the job's "files"
// names each file, so that a client downloads the folder as a local run writes it.
TEST_F(ServerApi, CommandLineRunDownloadsFolderOutputs) {
  const json job = json::parse(R"({"brdfbake_job": 1, "target": "filament", "tables": [
      {"kind": "prefilter", "size": 16, "output": "faces"},
      {"kind": "irradiance", "output": "sh.json"},
      {"kind": "ggx", "size": 8, "output": "dfg.exr"}]})");
  write_file(dir_->path / "folder.json", job.dump());
  // One folder name in two places: engine files are named after it.
  const std::string out = (dir_->path / "remote" / "ibl").string(), local = (dir_->path / "local" / "ibl").string();
  const CliRun remote =
      run_cli("run " + (dir_->path / "folder.json").string() + " --quiet --server " + server_->url() + " -o " + out);
  ASSERT_EQ(remote.code, 0) << remote.err;
  ASSERT_EQ(run_cli("run " + (dir_->path / "folder.json").string() + " --quiet -o " + local).code, 0);
  auto tree = [](const fs::path& root) {
    std::map<std::string, std::uintmax_t> files;
    for (const auto& e : fs::recursive_directory_iterator(root))
      if (e.is_regular_file()) files[e.path().lexically_relative(root).string()] = e.file_size();
    return files;
  };
  const auto got = tree(out), want = tree(local);
  EXPECT_GT(want.size(), 10u);  // six faces and level.json, the tables, the engine files, the manifest
  EXPECT_TRUE(want.count("faces/level0_px.exr"));
  std::vector<std::string> got_names, want_names;
  for (const auto& [name, size] : got) got_names.push_back(name);
  for (const auto& [name, size] : want) want_names.push_back(name);
  EXPECT_EQ(got_names, want_names);
  for (const char* f : {"faces/level0_px.exr", "faces/level.json", "dfg.exr"})
    EXPECT_EQ(read_file(fs::path(out) / f), read_file(fs::path(local) / f)) << f;
  // Asking for the folder itself says where its files are.
  auto c = server_->client();
  const json jobs = body_json(c.Get("/v1/jobs?limit=1"));
  const std::string id = jobs["jobs"][0]["id"];
  auto folder = c.Get(("/v1/jobs/" + id + "/files/faces").c_str());
  ASSERT_TRUE(folder);
  EXPECT_EQ(folder->status, 404);
  EXPECT_NE(body_json(folder).value("error", "").find("is a folder"), std::string::npos) << folder->body;
}

// bake --server --target: the engine's files are listed by the job, downloaded and in the summary,
// byte for byte the local bake's (issue 24, a new user's item 2: every file written is listed).
TEST_F(ServerApi, EngineFilesComeBackFromTheServer) {
  const std::string args = " --environment builtin:sun --target gltf --lut-size 16 --cube-size 16 --min-size 4";
  const std::string remote = (dir_->path / "gltf").string(), local = (dir_->path / "local" / "gltf").string();
  const CliRun bake = run_cli("bake --server " + server_->url() + args + " -o " + remote);
  ASSERT_EQ(bake.code, 0) << bake.err;
  ASSERT_EQ(run_cli("bake" + args + " --quiet -o " + local).code, 0);
  size_t pngs = 0;
  for (const auto& e : fs::directory_iterator(local)) {
    const std::string name = e.path().filename().string();
    if (name == "manifest.json") continue;
    SCOPED_TRACE(name);
    ASSERT_TRUE(fs::exists(fs::path(remote) / name));
    EXPECT_EQ(read_file(fs::path(remote) / name), read_file(e.path()));
    if (e.path().extension() == ".png")
      ++pngs;
    else
      EXPECT_NE(bake.out.find("  " + name + " "), std::string::npos) << bake.out;
  }
  EXPECT_NE(bake.out.find("gltf.gltf"), std::string::npos) << bake.out;
  EXPECT_NE(bake.out.find(std::to_string(pngs) + " PNGs: "), std::string::npos) << bake.out;
}

TEST(ServerLimits, QueueFullGets503AndCancelWorks) {
  TempDir dir("queue");
  ServerProcess server(dir.path, {"--data", (dir.path / "data").string(), "--max-queue", "1", "--no-warm-up"});
  ASSERT_TRUE(server.start()) << server.error();
  auto c = server.client();
  const std::string running = submit(c, slow_job(3));
  ASSERT_FALSE(running.empty());
  ASSERT_TRUE(wait_running(c, running));
  const std::string queued = submit(c, small_job());
  ASSERT_FALSE(queued.empty());
  auto full = c.Post("/v1/jobs", small_job().dump(), "application/json");
  ASSERT_TRUE(full);
  EXPECT_EQ(full->status, 503);
  EXPECT_GE(std::stoi(full->get_header_value("Retry-After")), 1);
  EXPECT_NE(body_json(full).value("error", "").find("--max-queue 1"), std::string::npos);
  // A slow job never blocks health, status or listing: each answers while it runs, and says so
  // (a reply that waited for the job would report it finished).
  auto health = c.Get("/v1/health");
  ASSERT_TRUE(health);
  EXPECT_EQ(health->status, 200);
  EXPECT_EQ(body_json(health)["running"], 1) << health->body;
  EXPECT_EQ(body_json(health)["queued"], 1) << health->body;
  auto status = c.Get(("/v1/jobs/" + running).c_str());
  ASSERT_TRUE(status);
  EXPECT_EQ(status->status, 200);
  EXPECT_EQ(body_json(status)["state"], "running") << status->body;
  auto list = c.Get("/v1/jobs");
  ASSERT_TRUE(list);
  EXPECT_EQ(list->status, 200);
  std::map<std::string, std::string> states;
  const json listing = body_json(list);
  for (const json& j : listing.value("jobs", json::array())) states[j.value("id", "")] = j.value("state", "");
  EXPECT_EQ(states[running], "running") << list->body;
  EXPECT_EQ(states[queued], "queued") << list->body;
  // The queued job is cancelled at once; the running one before its next table.
  auto del = c.Delete(("/v1/jobs/" + queued).c_str());
  ASSERT_TRUE(del);
  EXPECT_EQ(del->status, 200);
  EXPECT_EQ(body_json(c.Get(("/v1/jobs/" + queued).c_str()))["state"], "cancelled");
  del = c.Delete(("/v1/jobs/" + running).c_str());
  ASSERT_TRUE(del);
  EXPECT_EQ(del->status, 202);
  const json s = wait_job(c, running);
  EXPECT_EQ(s["state"], "cancelled") << s.dump();
  EXPECT_FALSE(fs::exists(dir.path / "data" / "jobs" / running));
  // Finished jobs are removed only when asked.
  del = c.Delete(("/v1/jobs/" + running).c_str());
  EXPECT_EQ(del->status, 409);
  del = c.Delete(("/v1/jobs/" + running + "?purge=1").c_str());
  EXPECT_EQ(del->status, 200);
  EXPECT_EQ(c.Get(("/v1/jobs/" + running).c_str())->status, 404);
  // A job past its own timeout fails before its next table, leaving nothing.
  auto timed = c.Post("/v1/jobs?timeout=0.05", slow_job(2).dump(), "application/json");
  ASSERT_TRUE(timed);
  ASSERT_EQ(timed->status, 202);
  const std::string timed_id = body_json(timed)["id"];
  const json t = wait_job(c, timed_id);
  EXPECT_EQ(t["state"], "failed") << t.dump();
  EXPECT_NE(t.value("error", "").find("timed out"), std::string::npos) << t.dump();
  EXPECT_FALSE(fs::exists(dir.path / "data" / "jobs" / timed_id));
  EXPECT_EQ(c.Post("/v1/jobs?timeout=-1", small_job().dump(), "application/json")->status, 400);
}

// Issue 34, class 2: every launch can be stopped. A preview's reference at the highest refinement
// (its first launch was sized for the default refinement: minutes of device work) stops within a
// launch or two of a DELETE; POST /v1/plan's measuring bakes stop at --table-timeout and the plan is
// answered without its estimate.
TEST(ServerLimits, EveryLaunchStopsWhenAsked) {
  TempDir dir("stops");
  ServerProcess server(dir.path, {"--data", (dir.path / "data").string(), "--no-warm-up", "--table-timeout", "0.05"});
  ASSERT_TRUE(server.start()) << server.error();
  auto c = server.client();
  using Clock = std::chrono::steady_clock;
  {
    const auto t0 = Clock::now();
    auto plan = c.Post("/v1/plan", R"({"environment": "builtin:studio", "cube_size": 1024})", "application/json");
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    ASSERT_TRUE(plan);
    ASSERT_EQ(plan->status, 200) << plan->body;
    const json p = body_json(plan);
    EXPECT_FALSE(p.contains("estimate")) << plan->body;
    EXPECT_NE(p.value("estimate_note", "").find("--table-timeout"), std::string::npos) << plan->body;
    EXPECT_LT(seconds, 8.0) << "the plan's measuring bakes ran past their deadline";
  }
  const json job = json::parse(R"({"brdfbake_job": 1, "environment": "builtin:studio", "tables": [
      {"kind": "preview", "target": "filament", "width": 384, "height": 192, "refinement": 64, "output": "p.png"}]})");
  auto posted = c.Post("/v1/jobs", job.dump(), "application/json");
  ASSERT_TRUE(posted);
  ASSERT_EQ(posted->status, 202) << posted->body;
  const std::string id = body_json(posted).value("id", "");
  std::string what;
  for (int i = 0; i < 3000 && what.find("reference") == std::string::npos; ++i) {
    const json j = body_json(c.Get(("/v1/jobs/" + id).c_str()));
    ASSERT_NE(j.value("state", ""), "done") << "the reference finished before it could be stopped: " << j.dump();
    if (j.contains("progress")) what = j["progress"].value("what", "");
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_NE(what.find("reference"), std::string::npos) << "never saw the reference render start";
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // well into its first launches
  const auto t0 = Clock::now();
  auto del = c.Delete(("/v1/jobs/" + id).c_str());
  ASSERT_TRUE(del);
  EXPECT_EQ(del->status, 202);
  const json s = wait_job(c, id, 120);
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  EXPECT_EQ(s.value("state", ""), "cancelled") << s.dump();
  EXPECT_LT(seconds, 5.0) << "the reference ran on after its DELETE";
}

TEST(ServerSecurity, TokenRequiredAndNoOpenListenWithoutIt) {
  TempDir dir("token");
  const std::string token = "s3cret-token-0123456789";
  write_file(dir.path / "token", token + "\n");
  ServerProcess server(dir.path, {"--data", (dir.path / "data").string(), "--token-file", (dir.path / "token").string(),
                                  "--no-warm-up"});
  ASSERT_TRUE(server.start()) << server.error();
  auto anonymous = server.client();
  for (const char* path : {"/v1/health", "/v1/jobs", "/metrics", "/v1/devices"}) {
    auto r = anonymous.Get(path);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 401) << path;
    EXPECT_EQ(r->get_header_value("WWW-Authenticate"), "Bearer realm=\"brdfbake\"");
  }
  EXPECT_EQ(anonymous.Post("/v1/jobs", small_job().dump(), "application/json")->status, 401);
  EXPECT_EQ(server.client("wrong-token-0123456789").Get("/v1/health")->status, 401);
  auto ok = server.client(token);
  EXPECT_EQ(ok.Get("/v1/health")->status, 200);
  // The command line's client sends it.
  write_file(dir.path / "job.json", small_job().dump());
  const CliRun run = run_cli("run " + (dir.path / "job.json").string() + " --quiet --server " + server.url() +
                             " --token-file " + (dir.path / "token").string() + " -o " + (dir.path / "out").string());
  EXPECT_EQ(run.code, 0) << run.err;
  // Without a token, any address but loopback is refused before anything listens.
  const CliRun open = run_cli("serve --listen 0.0.0.0:0 --data " + (dir.path / "open").string());
  EXPECT_EQ(open.code, 2);
  EXPECT_NE(open.err.find("refusing to listen on '0.0.0.0'"), std::string::npos) << open.err;
}

// Issue 34, class 4: a token-less server on loopback is not driven by another origin's page (a
// cross-origin POST with a "simple" Content-Type needs no preflight) and not read under a foreign
// Host name (DNS rebinding); the page it serves itself, and the command line, still are.
TEST(ServerSecurity, OtherSitesCannotDriveIt) {
  TempDir dir("site");
  ServerProcess server(dir.path, {"--data", (dir.path / "data").string(), "--no-warm-up"});
  ASSERT_TRUE(server.start()) << server.error();
  auto c = server.client();
  const std::string own = server.url();  // http://127.0.0.1:PORT, this server's origin
  const std::string host = own.substr(std::string("http://").size());
  auto jobs_count = [&] { return body_json(c.Get("/v1/jobs"))["jobs"].size(); };
  const size_t before = jobs_count();
  for (const char* type : {"text/plain", "application/x-www-form-urlencoded", "application/json"}) {
    auto r = c.Post("/v1/jobs", {{"Origin", "http://evil.example"}, {"Sec-Fetch-Site", "cross-site"}},
                    small_job().dump(), type);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 403) << type;
    EXPECT_NE(body_json(r).value("error", "").find("another origin"), std::string::npos) << r->body;
  }
  auto del = c.Delete("/v1/jobs/abc", {{"Origin", "null"}});
  ASSERT_TRUE(del);
  EXPECT_EQ(del->status, 403);
  EXPECT_EQ(jobs_count(), before);  // nothing was submitted
  // A foreign Host name reads nothing, not even the page.
  for (const char* path : {"/v1/jobs", "/v1/inputs", "/", "/v1/health"}) {
    auto r = c.Get(path, {{"Host", "rebind.evil.example:" + host.substr(host.find(':') + 1)}});
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 403) << path;
  }
  // Its own page, and the command line (no Origin), do.
  auto own_page =
      c.Post("/v1/jobs", {{"Origin", own}, {"Sec-Fetch-Site", "same-origin"}}, small_job().dump(), "application/json");
  ASSERT_TRUE(own_page);
  EXPECT_EQ(own_page->status, 202) << own_page->body;
  EXPECT_EQ(c.Post("/v1/jobs", small_job().dump(), "application/json")->status, 202);
  EXPECT_EQ(c.Get("/v1/jobs", {{"Host", "localhost:1"}})->status, 200);
  // Allow-lists: --allowed-origins and --allowed-hosts let the named ones in.
  fs::create_directories(dir.path / "open");
  ServerProcess open(dir.path / "open", {"--data", (dir.path / "open-data").string(), "--no-warm-up",
                                         "--allowed-origins", "http://localhost:3000", "--allowed-hosts", "bake.lan"});
  ASSERT_TRUE(open.start()) << open.error();
  auto o = open.client();
  EXPECT_EQ(o.Post("/v1/jobs", {{"Origin", "http://localhost:3000"}}, small_job().dump(), "application/json")->status,
            202);
  EXPECT_EQ(o.Post("/v1/jobs", {{"Origin", "http://localhost:3001"}}, small_job().dump(), "application/json")->status,
            403);
  EXPECT_EQ(o.Get("/v1/jobs", {{"Host", "bake.lan"}})->status, 200);
  EXPECT_EQ(o.Get("/v1/jobs", {{"Host", "other.lan"}})->status, 403);
  const CliRun bad = run_cli("serve --data " + (dir.path / "bad").string() + " --allowed-origins evil.example");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("is not an origin"), std::string::npos) << bad.err;
}

// Issue 34, class 5: the server writes and deletes only inside --data. A preview table without a
// bake folder bakes its files first inside the job's own staging folder (not $TMPDIR, where a kill
// left them forever), and its JSON names those files without a server path; uploads' pruning never
// deletes through a DATA/uploads that is a link to another folder.
TEST(ServerSecurity, NothingOutsideDataIsWrittenOrDeleted) {
  TempDir dir("outside-data");
  const fs::path tmp = dir.path / "system-tmp";
  fs::create_directories(tmp);
  fs::create_directories(dir.path / "elsewhere");
  write_file(dir.path / "elsewhere" / "old.hdr", "someone else's file, two days old");
  fs::last_write_time(dir.path / "elsewhere" / "old.hdr", fs::file_time_type::clock::now() - std::chrono::hours(48));
  fs::create_directories(dir.path / "data");
  fs::create_directory_symlink(dir.path / "elsewhere", dir.path / "data" / "uploads");
  ServerProcess server(dir.path, {"--data", (dir.path / "data").string(), "--no-warm-up"},
                       [tmp] { ::setenv("TMPDIR", tmp.c_str(), 1); });
  ASSERT_TRUE(server.start()) << server.error();
  auto c = server.client();
  std::string hdr = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 4\n";
  for (int i = 0; i < 8; ++i) hdr += std::string("\x80\x80\x80\x81", 4);
  auto up = c.Post("/v1/uploads?name=sky.hdr", hdr, "application/octet-stream");
  ASSERT_TRUE(up);
  EXPECT_EQ(up->status, 500) << up->body;
  EXPECT_NE(body_json(up).value("error", "").find("not a folder of its own"), std::string::npos) << up->body;
  EXPECT_TRUE(fs::exists(dir.path / "elsewhere" / "old.hdr")) << "the prune deleted through the link";

  const json preview_job = json::parse(R"({"brdfbake_job": 1, "environment": "builtin:sun", "tables": [
      {"kind": "preview", "target": "filament", "width": 192, "height": 96, "reference": false, "output": "p.png"}]})");
  auto posted = c.Post("/v1/jobs", preview_job.dump(), "application/json");
  ASSERT_TRUE(posted);
  ASSERT_EQ(posted->status, 202) << posted->body;
  const std::string id = body_json(posted).value("id", "");
  // Watched while it runs (the first bake's folder is removed when the render ends).
  std::set<std::string> seen;
  std::string state;
  for (int i = 0; i < 24000 && state != "done" && state != "failed"; ++i) {
    for (const auto& e : fs::directory_iterator(tmp)) seen.insert(e.path().filename().string());
    if (i % 20 == 0) state = body_json(c.Get(("/v1/jobs/" + id).c_str())).value("state", "");
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_EQ(state, "done");
  for (const auto& name : seen) ADD_FAILURE() << "written outside --data: " << name;
  auto p = c.Get(("/v1/jobs/" + id + "/files/p.json").c_str());
  ASSERT_TRUE(p);
  ASSERT_EQ(p->status, 200);
  EXPECT_EQ(p->body.find(dir.path.string()), std::string::npos) << "p.json names a server path";
  const json bake = json::parse(p->body)["bake"];
  EXPECT_NE(bake.value("folder", "").find("baked first"), std::string::npos) << bake.dump();
  for (const char* key : {"specular", "dfg", "diffuse"}) {
    EXPECT_EQ(bake.value(key, "/").find('/'), std::string::npos) << key << ": " << bake.dump();
    EXPECT_EQ(bake.value(key, "").find(dir.path.string()), std::string::npos) << bake.dump();
  }
  for (const auto& e : fs::recursive_directory_iterator(dir.path / "data" / "jobs" / id))
    EXPECT_EQ(e.path().filename().string().find("brdfbake-preview"), std::string::npos) << e.path();
}

TEST(ServerFaults, KillMinusNineThenRestart) {
  TempDir dir("kill9");
  const std::vector<std::string> args = {"--data", (dir.path / "data").string(), "--no-warm-up"};
  std::string done_id, running_id, done_bytes;
  {
    ServerProcess server(dir.path, args);
    ASSERT_TRUE(server.start()) << server.error();
    auto c = server.client();
    done_id = submit(c, small_job());
    ASSERT_EQ(wait_job(c, done_id)["state"], "done");
    done_bytes = c.Get(("/v1/jobs/" + done_id + "/files/dfg.exr").c_str())->body;
    running_id = submit(c, slow_job(2));
    ASSERT_TRUE(wait_running(c, running_id));
    // While it runs, none of its files is served.
    EXPECT_EQ(c.Get(("/v1/jobs/" + running_id + "/files/manifest.json").c_str())->status, 409);
    server.signal(SIGKILL);
    EXPECT_EQ(server.wait_exit(10), -1);
  }
  ServerProcess again(dir.path, args);
  ASSERT_TRUE(again.start()) << again.error();
  auto c = again.client();
  // The finished job and its file, byte for byte.
  EXPECT_EQ(body_json(c.Get(("/v1/jobs/" + done_id).c_str()))["state"], "done");
  EXPECT_EQ(c.Get(("/v1/jobs/" + done_id + "/files/dfg.exr").c_str())->body, done_bytes);
  // The interrupted job was re-queued (docs/SERVICE.md) and runs to the end.
  const json s = wait_job(c, running_id, 120);
  EXPECT_EQ(s["state"], "done") << s.dump();
  EXPECT_EQ(s["attempts"], 2);
  EXPECT_NE(read_file(dir.path / "server.out").find("re-queued 1 job(s)"), std::string::npos);
  // No staging folder is left.
  for (const auto& e : fs::directory_iterator(dir.path / "data" / "jobs"))
    EXPECT_NE(e.path().filename().string()[0], '.') << e.path();
}

TEST(ServerFaults, SigtermStopsWithinItsGraceAndRequeues) {
  TempDir dir("sigterm");
  const std::vector<std::string> args = {"--data", (dir.path / "data").string(), "--no-warm-up", "--shutdown-grace",
                                         "0.2"};
  std::string id;
  {
    ServerProcess server(dir.path, args);
    ASSERT_TRUE(server.start()) << server.error();
    auto c = server.client();
    id = submit(c, slow_job(2));
    ASSERT_TRUE(wait_running(c, id));
    const auto t0 = std::chrono::steady_clock::now();
    server.signal(SIGTERM);
    // Bounded: the grace, then the rest of the table being baked, then 5 s at most.
    EXPECT_EQ(server.wait_exit(30), 0) << server.stderr_text();
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 30.0);
  }
  ServerProcess again(dir.path, args);
  ASSERT_TRUE(again.start()) << again.error();
  auto c = again.client();
  const json s = wait_job(c, id, 120);
  EXPECT_EQ(s["state"], "done") << s.dump();
}

// A full disk under the data directory: a small tmpfs when this process may mount one (root), else
// a file size limit on the server (writes past it fail with EFBIG).
TEST(ServerFaults, FullDiskFailsTheJobNotTheDatabase) {
  TempDir dir("fulldisk");
  const fs::path data = dir.path / "data";
  fs::create_directories(data);
  // BRDFBAKE_TEST_NO_MOUNT=1 takes the second way where mounting works too (to test it).
  const bool try_mount = !std::getenv("BRDFBAKE_TEST_NO_MOUNT");
  const bool mounted = try_mount && ::mount("tmpfs", data.c_str(), "tmpfs", 0, "size=3m") == 0;
  std::function<void()> limit;
  if (!mounted)
    limit = [] {
      ::signal(SIGXFSZ, SIG_IGN);
      rlimit r{3u << 20, 3u << 20};
      ::setrlimit(RLIMIT_FSIZE, &r);
    };
  struct Unmount {
    fs::path p;
    bool on;
    ~Unmount() {
      if (on) ::umount2(p.c_str(), MNT_DETACH);
    }
  } unmount{data, mounted};
  {
    ServerProcess server(dir.path, {"--data", data.string(), "--no-warm-up"}, limit);
    ASSERT_TRUE(server.start()) << server.error();
    auto c = server.client();
    // A 6.3 MiB chain of float texels does not fit in 3 MiB.
    const std::string id = submit(
        c, json::parse(R"({"tables": [{"kind": "prefilter", "size": 256, "pixel": "f32", "output": "big.ktx2"}]})"));
    ASSERT_FALSE(id.empty());
    const json s = wait_job(c, id);
    EXPECT_EQ(s["state"], "failed") << s.dump();
    const std::string error = s.value("error", "");
    EXPECT_TRUE(error.find("No space left on device") != std::string::npos ||
                error.find("File too large") != std::string::npos)
        << error;
    // The server failed, not the request: exit code 1 (not 2, bad input), and the message names
    // the file as the job does, not the server's folders.
    EXPECT_EQ(s.value("exit_code", 0), 1) << s.dump();
    EXPECT_EQ(error.find(dir.path.string()), std::string::npos) << error;
    EXPECT_NE(error.find("'big.ktx2'"), std::string::npos) << error;
    EXPECT_FALSE(fs::exists(data / "jobs" / id));
    // The same through POST /v1/tables: 507 Insufficient Storage, not 400.
    auto t = c.Post("/v1/tables", R"({"kind": "prefilter", "size": 256, "pixel": "f32", "output": "big.ktx2"})",
                    "application/json");
    ASSERT_TRUE(t);
    EXPECT_EQ(t->status, 507) << t->body;
    EXPECT_EQ(t->body.find(dir.path.string()), std::string::npos) << t->body;
    // The space was given back: the next job runs.
    EXPECT_EQ(wait_job(c, submit(c, small_job()))["state"], "done");
    if (mounted) {
      // A disk so full that the job database cannot record a submission: 507, no server path.
      {
        std::ofstream filler(data / "filler", std::ios::binary);
        const std::string block(1 << 16, '\0');
        for (int i = 0; i < 64 && filler; ++i) filler.write(block.data(), static_cast<std::streamsize>(block.size()));
      }
      auto full = c.Post("/v1/jobs", small_job().dump(), "application/json");
      ASSERT_TRUE(full);
      EXPECT_EQ(full->status, 507) << full->body;
      EXPECT_EQ(full->body.find(dir.path.string()), std::string::npos) << full->body;
      fs::remove(data / "filler");
    }
    server.signal(SIGTERM);
    EXPECT_EQ(server.wait_exit(30), 0);
  }
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open_v2((data / "jobs.db").c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(db, "PRAGMA integrity_check", -1, &st, nullptr), SQLITE_OK);
  ASSERT_EQ(sqlite3_step(st), SQLITE_ROW);
  EXPECT_STREQ(reinterpret_cast<const char*>(sqlite3_column_text(st, 0)), "ok");
  sqlite3_finalize(st);
  sqlite3_close(db);
}

}  // namespace
}  // namespace brdfbake::test
