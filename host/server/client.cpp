#include "server/client.hpp"

#include <httplib.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <thread>

#include "brdfbake/cancel.hpp"
#include "brdfbake/error_figures.hpp"
#include "io/json_input.hpp"
#include "io/special_files.hpp"
#include "io/staging_dir.hpp"
#include "job/job_json.hpp"

namespace brdfbake::server {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace {

std::string read_token(const RemoteOptions& o) {
  std::string token;
  if (!o.token_file.empty()) {
    try {
      token = io::read_token_file(o.token_file, "--token-file");  // bounded, printable (io/special_files.hpp)
    } catch (const Cancelled&) {
      throw;
    } catch (const Error& e) {
      throw RemoteError(e.what(), 2);
    }
  } else if (const char* env = std::getenv("BRDFBAKE_TOKEN")) {
    token = env;
  }
  while (!token.empty() && std::isspace(static_cast<unsigned char>(token.back()))) token.pop_back();
  return token;
}

std::string url_encode(const std::string& s) {
  std::string out;
  for (char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~') {
      out += static_cast<char>(c);
    } else {
      char buf[4];
      std::snprintf(buf, sizeof buf, "%%%02X", c);
      out += buf;
    }
  }
  return out;
}

// A server's answer as JSON, through the input policy (io/json_input.hpp: depth and size limits, no
// recursion); discarded (not an object) when it is not JSON a server of ours writes.
json parse_answer(const std::string& body) {
  try {
    return io::parse_json(body, "the server's answer");
  } catch (const Error&) {
    return json(json::value_t::discarded);
  }
}

// The server's one-line message from an error response, or the status.
std::string server_message(const httplib::Result& r) {
  const json body = parse_answer(r->body);
  if (body.is_object() && body.contains("error") && body["error"].is_string()) return body["error"].get<std::string>();
  return "HTTP " + std::to_string(r->status);
}

class Connection {
 public:
  Connection(const RemoteOptions& o) : url_(o.url), client_(o.url) {
    if (!client_.is_valid()) throw RemoteError("--server: '" + o.url + "' is not a URL (http://HOST:PORT)", 2);
    const std::string token = read_token(o);
    if (!token.empty()) client_.set_bearer_token_auth(token.c_str());
    client_.set_connection_timeout(10, 0);
    client_.set_read_timeout(90, 0);
    client_.set_write_timeout(30, 0);
    client_.set_keep_alive(true);
  }
  httplib::Client& operator*() { return client_; }
  httplib::Client* operator->() { return &client_; }
  // Throws for a request that got no answer.
  void check(const httplib::Result& r) const {
    if (!r) throw RemoteError("cannot reach the server at " + url_ + ": " + httplib::to_string(r.error()), 1);
  }

 private:
  std::string url_;
  httplib::Client client_;
};

}  // namespace

Manifest manifest_from_json(const std::string& text, const std::string& output_dir) {
  const json m = io::parse_json(text, "manifest.json");
  Manifest out;
  out.output_dir = output_dir;
  out.job_source = m.value("job", "");
  out.scene = m.value("scene", "");
  out.bakes = m.value("bakes", 0);
  out.seconds = m.value("seconds", 0.0);
  if (m.contains("files") && m["files"].is_array())
    for (const auto& f : m["files"]) {
      ManifestFile e;
      e.path = f.value("path", "");
      e.kind = table_kind_from_name(f.value("kind", "ggx"));
      e.device = f.value("device", "");
      e.environment = f.value("environment", "");
      // the error figure under its kind's name, or (an older server) error_bound
      const std::string figure = f.value("error_name", std::string(kLegacyErrorBoundName));
      if (f.contains(figure) && f[figure].is_number()) e.error_bound = f[figure].get<double>();
      e.error_bound_definition = f.value("error_measurement", f.value("error_bound_definition", ""));
      if (f.contains("materials") && f["materials"].is_array())
        for (const auto& mat : f["materials"])
          if (mat.is_string()) e.materials.push_back(mat.get<std::string>());
      e.bytes = f.value("bytes", std::uint64_t(0));
      e.seconds = f.value("seconds", 0.0);
      e.bake = f.value("bake", 0);
      out.files.push_back(std::move(e));
    }
  if (m.contains("engine") && m["engine"].is_object()) {  // an engine target's file set
    const json& e = m["engine"];
    out.target = e.value("target", "");
    if (e.contains("files") && e["files"].is_array())
      for (const auto& f : e["files"])
        if (f.is_string()) out.engine_files.push_back(f.get<std::string>());
    if (e.contains("delivered") && e["delivered"].is_object())
      for (const auto& [k, v] : e["delivered"].items())
        if (v.is_string()) out.engine_delivered.emplace_back(k, v.get<std::string>());
    out.engine_entries = detail::engine_entries_from_json(e);
  }
  for (const char* key : {"notes", "warnings"})
    if (m.contains(key) && m[key].is_array())
      for (const auto& n : m[key])
        if (n.is_string()) (std::string(key) == "notes" ? out.notes : out.warnings).push_back(n.get<std::string>());
  return out;
}

Manifest remote_run(const std::string& job_text, const std::string& source, const std::string& output_dir,
                    const RemoteOptions& o, const JobProgress& progress) {
  Connection c(o);
  const std::string path = "/v1/jobs?source=" + url_encode(source);
  // The output folder goes with the job: the server names an engine target's files after it, as a
  // local run does (it writes nothing there).
  std::string body = job_text;
  {
    json doc = io::parse_json(job_text, source);
    if (doc.is_object() && !output_dir.empty()) {
      doc["output_dir"] = output_dir;
      body = doc.dump();
    }
  }
  const httplib::Result posted = c->Post(path.c_str(), body, "application/json");
  c.check(posted);
  if (posted->status == 400) throw RemoteError(server_message(posted), 2);
  if (posted->status != 202)
    throw RemoteError("the server refused the job (" + std::to_string(posted->status) + "): " + server_message(posted),
                      1);
  const json accepted = parse_answer(posted->body);
  if (!accepted.is_object() || !accepted.contains("id") || !accepted["id"].is_string())
    throw RemoteError("the server's answer has no job id", 1);
  const std::string id = accepted["id"].get<std::string>();

  // Follow it: short long-polls, so that progress is shown while it runs.
  json status;
  for (;;) {
    const std::string q = "/v1/jobs/" + id + "?wait=" + std::to_string(o.poll_seconds);
    const httplib::Result r = c->Get(q.c_str());
    c.check(r);
    if (r->status != 200) throw RemoteError("job " + id + ": " + server_message(r), 1);
    status = parse_answer(r->body);
    if (!status.is_object()) throw RemoteError("job " + id + ": the server's answer is not JSON", 1);
    const std::string state = status.value("state", "");
    if (state == "done") break;
    if (state == "failed" || state == "cancelled") {
      // exit codes are 2 (bad input) or 1 (anything else), whatever the answer says
      const json& code = status.contains("exit_code") ? status["exit_code"] : json();
      throw RemoteError(status.contains("error") && status["error"].is_string() ? status["error"].get<std::string>()
                                                                                : "job " + id + " " + state,
                        code.is_number_integer() && code.get<long long>() == 2 ? 2 : 1);
    }
    if (progress && status.contains("progress")) {
      const json& p = status["progress"];
      progress({p.value("bake", 0), p.value("bakes", 0), p.value("what", ""), p.value("fraction", 0.0)});
    }
  }

  // Download everything into a temporary folder beside the output, then move it in.
  std::vector<std::string> files;
  for (const auto& f : status["files"])
    if (f.is_string()) files.push_back(f.get<std::string>());
  std::string target = output_dir;
  while (target.size() > 1 && target.back() == '/') target.pop_back();
  io::StagingDir staging{fs::path(target)};
  std::string manifest_text;
  for (const std::string& name : files) {
    const fs::path rel = fs::path(name).lexically_normal();
    if (rel.is_absolute() || rel.empty() || *rel.begin() == "..")
      throw RemoteError("job " + id + ": the server names a file outside the folder: '" + name + "'", 1);
    const fs::path local = staging.path() / rel;
    fs::create_directories(local.parent_path());
    std::ofstream out(local, std::ios::binary);
    std::string encoded;
    for (const auto& part : rel) encoded += (encoded.empty() ? "" : "/") + url_encode(part.string());
    const std::string q = "/v1/jobs/" + id + "/files/" + encoded;
    std::uint64_t got = 0;
    const auto r = c->Get(q.c_str(), [&](const char* data, size_t n) {
      out.write(data, static_cast<std::streamsize>(n));
      got += n;
      if (name == "manifest.json") manifest_text.append(data, n);
      return static_cast<bool>(out);
    });
    c.check(r);
    if (r->status != 200) throw RemoteError("job " + id + ": " + name + ": " + server_message(r), 1);
    out.close();
    if (!out) throw RemoteError("cannot write '" + (fs::path(target) / rel).string() + "'", 1);
    const std::string length = r->get_header_value("Content-Length");
    if (!length.empty() && std::to_string(got) != length)
      throw RemoteError("job " + id + ": " + name + ": the download was cut short (" + std::to_string(got) + " of " +
                            length + " bytes); nothing was written",
                        1);
  }
  staging.commit("manifest.json");
  return manifest_from_json(manifest_text, output_dir);
}

Manifest remote_run_file(const std::string& job_path, const std::string& output_dir_in, bool sanitize,
                         const RemoteOptions& o, const JobProgress& progress) {
  json doc = io::parse_json(io::read_text_file(job_path, "job"), job_path);
  if (!doc.is_object()) throw Error(job_path + ": a job is a JSON object with a \"tables\" array");
  std::string output_dir = output_dir_in;
  if (output_dir.empty() && doc.contains("output_dir") && doc["output_dir"].is_string())
    output_dir = doc["output_dir"].get<std::string>();
  if (output_dir.empty()) throw RemoteError("the job has no output_dir: give -o DIR", 2);
  if (sanitize) doc["sanitize"] = true;
  return remote_run(doc.dump(), job_path, output_dir, o, progress);
}

}  // namespace brdfbake::server
