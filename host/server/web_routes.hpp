// The web page of `brdfbake serve` (docs/SERVICE.md, "The web page"): GET / and its files, embedded
// in the binary at build time (host/server/web/, cmake/EmbedWebAssets.cmake), and the small JSON
// and picture routes the page needs beside the job API: the schemas (GET /v1/kinds, GET
// /v1/bake/options), the files a request may read (GET /v1/inputs), a file uploaded from the page
// (POST /v1/uploads), a bake's plan without baking, with each table's estimated time and bytes
// (POST /v1/plan), a job's document (GET /v1/jobs/ID/job), its folder as one tar file (GET
// /v1/jobs/ID/archive) and a picture of each file a job wrote, drawn by `brdfbake view`'s code
// (GET /v1/jobs/ID/view/NAME).
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace httplib {
class Server;
}

namespace brdfbake {
class Backend;
struct Plan;
}  // namespace brdfbake

namespace brdfbake::server {

class JobStore;
class Roots;

namespace detail {
struct WebAsset {
  const char* path;  // relative to host/server/web/
  const unsigned char* data;
  std::size_t size;
};
// Generated at build time (web_assets.cpp in the build tree).
const std::vector<WebAsset>& web_assets();
}  // namespace detail

// What the routes read: the job records and the roots (inputs under --input-root, outputs under
// DATA/jobs/<id>/, scratch files in DATA/tmp/).
struct WebContext {
  JobStore* store = nullptr;
  const Roots* roots = nullptr;
  std::filesystem::path jobs_dir, tmp_dir;
  std::uint64_t max_memory = 0;  // --max-memory: the checks of uploads share it
  double estimate_seconds = 30;  // POST /v1/plan measures for at most this long (--table-timeout)
  // Runs a dry run's measuring bakes on the device a selector names (the scheduler's run_now: a warm
  // device, before its queued jobs); empty: POST /v1/plan gives no time estimate.
  std::function<void(const std::string& selector, const std::function<void(Backend&)>& work)> on_device;
};

// The plan of a bake's options as POST /v1/bake and POST /v1/plan take them (a JSON object; "{}" or
// an empty body: the default bake): JSON values into the options' types, parse_bake_options, and a
// scene read under the input root (parsed from memory: no file it refers to is opened). Throws
// Error with the one line a 400 answers.
Plan bake_plan(const std::string& body, const std::string& origin, const Roots& roots);

// The page's own files, served without a token: they hold no data (the page asks for the token and
// sends it with every API call it makes).
bool web_public_route(const std::string& method, const std::string& path);

// Registers the page's files and its routes on `http`; the token check (the server's pre-routing
// handler) applies to every /v1/ route as to the rest of the API.
void register_web_routes(httplib::Server& http, const WebContext& context);

}  // namespace brdfbake::server
