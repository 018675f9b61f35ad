#include "server/web_routes.hpp"

#include <httplib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <sstream>
#include <vector>

#include "brdfbake/cancel.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/job.hpp"
#include "brdfbake/params.hpp"
#include "brdfbake/plan.hpp"
#include "brdfbake/scene.hpp"
#include "brdfbake/tables.hpp"
#include "brdfbake/view.hpp"
#include "io/atomic_file.hpp"
#include "io/json_input.hpp"
#include "server/confine.hpp"
#include "server/job_files.hpp"
#include "server/job_store.hpp"
#include "server/reply.hpp"

namespace brdfbake::server {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace {

// The page loads nothing from elsewhere: scripts, styles and fetches from this origin only; images
// also from blob: URLs (the pictures are fetched with the token and shown from memory).
constexpr const char* kContentSecurityPolicy =
    "default-src 'self'; img-src 'self' blob:; base-uri 'none'; form-action 'none'; frame-ancestors 'none'";

// The files in an input root the page offers, and how deep and how many it looks at: a listing is a
// convenience, bounded so that a large root costs a request little.
constexpr int kInputsMaxDepth = 4;
constexpr int kInputsMaxEntries = 5000;

std::string lower_extension(const fs::path& p) {
  std::string ext = p.extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

const char* asset_content_type(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".svg") return "image/svg+xml";
  return "application/octet-stream";
}

// A strong validator of an asset's bytes (FNV-1a, 64 bits): the page is revalidated on each load
// (Cache-Control: no-cache) and answered 304 while the binary is the same.
std::string asset_etag(const detail::WebAsset& a) {
  std::uint64_t h = 1469598103934665603ull;
  for (std::size_t i = 0; i < a.size; ++i) h = (h ^ a.data[i]) * 1099511628211ull;
  char buf[24];
  std::snprintf(buf, sizeof buf, "\"%016llx\"", static_cast<unsigned long long>(h));
  return buf;
}

const detail::WebAsset* find_asset(const std::string& route) {
  const std::string name = route == "/" ? "index.html" : route.substr(1);
  for (const auto& a : detail::web_assets())
    if (name == a.path) return &a;
  return nullptr;
}

// POST /v1/plan: what POST /v1/bake would submit, checked as a submission is (paths confined, the
// job validated), with each table's estimated peak memory; nothing is baked.
void post_plan(const WebContext& c, const httplib::Request& req, httplib::Response& res) {
  const std::string origin = "bake";
  try {
    const Plan plan = bake_plan(req.body, origin, *c.roots);
    json doc = json::parse(plan_to_json(plan));
    c.roots->confine_job_document(doc, origin);
    const Job job = parse_job(doc.dump(), origin);
    std::optional<PlanEstimate> estimate;
    std::string estimate_note;
    if (c.on_device) {
      // The measuring bakes are bounded (issue 34, class 2): they stop at their next step past
      // --table-timeout, and the plan is answered without its estimate.
      EstimateOptions eo;
      eo.on_device = c.on_device;
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(c.estimate_seconds);
      eo.stop_requested = [deadline] { return std::chrono::steady_clock::now() > deadline; };
      try {
        estimate = estimate_job(job, eo);
      } catch (const Cancelled&) {
        char m[160];
        std::snprintf(m, sizeof m, "no estimate: measuring took more than %g s (--table-timeout)", c.estimate_seconds);
        estimate_note = m;
      }
    }
    json tables = json::array();
    for (size_t i = 0; i < job.tables.size(); ++i) {
      const TableRequest& t = job.tables[i];
      json e;
      e["kind"] = table_kind_name(t.kind);
      e["output"] = t.output;
      e["estimated_bytes"] = estimate_table_bytes(t);
      if (estimate) {
        e["seconds"] = estimate->tables[i].seconds;
        e["bytes"] = estimate->tables[i].bytes;
        e["method"] = estimate->tables[i].method;
      }
      tables.push_back(e);
    }
    json o;
    o["job"] = doc;
    o["tables"] = tables;
    if (estimate) {
      json w;
      w["seconds"] = estimate->seconds;
      w["bytes"] = estimate->bytes;
      w["environment_seconds"] = estimate->environment_seconds;
      w["calibration_seconds"] = estimate->calibration_seconds;
      o["estimate"] = w;
    }
    if (!estimate_note.empty()) o["estimate_note"] = estimate_note;
    reply_json(res, 200, o);
  } catch (const Error& e) {
    reply_error(res, 400, c.roots->public_text(e.what()));  // no server path in a message
  }
}

// How many uploads are checked at once (each decodes its image under a share of --max-memory).
constexpr int kUploadChecksAtOnce = 2;

// POST /v1/uploads?name=FILE: a file from the page (the body, raw: --max-body applies, 413 before it is
// read), an environment (.hdr .exr .png .ktx2) or a scene (.gltf .glb), read through the readers
// and limits a bake uses before it is kept; stored as DATA/uploads/<random>-<name> and answered with
// the name requests give it ("upload:..."). Uploads older than kUploadMaxAgeSeconds go, then the
// oldest while they hold more than kUploadMaxTotalBytes.
void prune_uploads(const fs::path& dir, std::uint64_t incoming) {
  std::error_code ec;
  struct Entry {
    fs::path path;
    fs::file_time_type time;
    std::uint64_t bytes;
  };
  std::vector<Entry> entries;
  const auto now = fs::file_time_type::clock::now();
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (!e.is_regular_file(ec) || e.is_symlink(ec)) continue;  // a link is not the server's file to delete
    const auto t = e.last_write_time(ec);
    if (ec) continue;
    if (std::chrono::duration<double>(now - t).count() > kUploadMaxAgeSeconds) {
      fs::remove(e.path(), ec);
      continue;
    }
    entries.push_back({e.path(), t, static_cast<std::uint64_t>(e.file_size(ec))});
  }
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.time < b.time; });
  std::uint64_t total = incoming;
  for (const auto& e : entries) total += e.bytes;
  for (const auto& e : entries) {
    if (total <= kUploadMaxTotalBytes) break;
    fs::remove(e.path, ec);
    total -= e.bytes;
  }
}

void post_upload(const WebContext& c, const httplib::Request& req, httplib::Response& res) {
  const std::string origin = "upload";
  const std::string name = req.has_param("name") ? req.get_param_value("name") : std::string();
  if (name.empty()) return reply_error(res, 400, origin + ": name: the file's name is required (?name=sky.hdr)");
  // Its name is a label and an extension, never a path: one component of plain characters.
  if (name.size() > 100 ||
      name.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789._-") !=
          std::string::npos ||
      name[0] == '.')
    return reply_error(res, 400,
                       origin + ": name: '" + name.substr(0, 60) +
                           "' must be a file name of letters, digits, '.', '_' and '-' (at most 100, not starting "
                           "with '.')");
  const std::string ext = lower_extension(fs::path(name));
  const bool scene = ext == ".gltf" || ext == ".glb";
  if (!scene && ext != ".hdr" && ext != ".exr" && ext != ".png" && ext != ".ktx2")
    return reply_error(res, 400,
                       origin + ": name: '" + name.substr(0, 60) +
                           "': an environment (.hdr .exr .png .ktx2) or a scene (.gltf .glb) is expected");
  if (req.body.empty()) return reply_error(res, 400, origin + ": the body is empty: it is the file's bytes");
  // At most kUploadChecksAtOnce checks at once, each under its share of --max-memory: a small file
  // may promise a huge image, and its check must not take the server's memory (issue 34, class 3).
  static std::atomic<int> checking{0};
  struct Slot {
    bool held;
    Slot() : held(checking.fetch_add(1) < kUploadChecksAtOnce) {}
    ~Slot() { checking.fetch_sub(1); }
  } slot;
  if (!slot.held) {
    res.set_header("Retry-After", "2");
    return reply_error(res, 503,
                       origin + ": the server is checking " + std::to_string(kUploadChecksAtOnce) +
                           " uploads already; retry in a moment");
  }
  const fs::path dir = c.roots->uploads_dir();
  std::error_code ec;
  fs::create_directory(dir, ec);
  // DATA/uploads is the server's own folder: old uploads in it are deleted, so never through a link.
  if (fs::symlink_status(dir, ec).type() != fs::file_type::directory)
    return reply_error(res, 500,
                       origin +
                           ": the server's uploads folder is not a folder of its own (a symbolic link?): "
                           "uploads are off until it is");
  prune_uploads(dir, req.body.size());
  static std::atomic<unsigned> counter{0};
  char stamp[40];
  std::snprintf(stamp, sizeof stamp, "%08x%04x-", static_cast<unsigned>(std::random_device{}()), (counter++) & 0xffffu);
  const std::string stored = stamp + name;
  const fs::path path = dir / stored;
  const std::string public_name = std::string(kUploadPrefix) + stored;
  // Checked under a name of DATA/tmp (emptied when the server starts) and moved into DATA/uploads
  // only once it passed: a kill during the check leaves no unchecked upload that jobs could name.
  const fs::path checking_path = c.tmp_dir / ("upload-" + stored);
  struct Remove {
    fs::path p;
    ~Remove() {
      std::error_code e;
      fs::remove(p, e);
    }
  } remove_checking{checking_path};
  try {
    io::write_file_atomically(checking_path.string(), req.body);
  } catch (const Error& e) {
    return reply_error(res, 507, origin + ": cannot store the upload: " + c.roots->public_text(e.what()));
  }
  const std::uint64_t budget = std::max<std::uint64_t>(
      64ull << 20, (c.max_memory ? c.max_memory : default_memory_budget()) / kUploadChecksAtOnce);
  try {
    if (scene) {
      const bool glb = req.body.size() >= 4 && req.body.compare(0, 4, "glTF") == 0;
      (void)(glb ? parse_glb(req.body, public_name, "") : parse_scene_json(req.body, public_name, ""));
    } else {
      EnvLoadOptions lo;
      lo.memory_budget = budget;
      (void)load_environment(checking_path.string(), lo);
    }
  } catch (const std::bad_alloc&) {
    return reply_error(res, 507,
                       origin +
                           ": the server ran out of memory checking the upload; retry later, or raise "
                           "--max-memory");
  } catch (const Error& e) {
    const std::string what = c.roots->public_text(e.what());
    if (what.find("above the memory budget") != std::string::npos)
      return reply_error(res, 507,
                         origin + ": '" + name + "' is larger decoded than the server checks an upload in (" +
                             std::to_string(budget >> 20) + " MiB, a share of --max-memory): " + what);
    return reply_error(res, 400, what);
  }
  fs::rename(checking_path, path, ec);
  if (ec) return reply_error(res, 507, origin + ": cannot store the upload: " + ec.message());
  json o;
  o["name"] = public_name;
  o["kind"] = scene ? "scene" : "environment";
  o["bytes"] = req.body.size();
  reply_json(res, 201, o);
}

// GET /v1/inputs: the environments and scenes under --input-root that a request may name (relative
// paths), and the builtin environments.
void get_inputs(const WebContext& c, httplib::Response& res) {
  json environments = json::array(), scenes = json::array();
  for (const auto& name : builtin_environment_names()) {
    json e;
    e["path"] = "builtin:" + name;
    environments.push_back(e);
  }
  bool truncated = false;
  const fs::path& root = c.roots->input_root();
  if (!root.empty()) {
    std::error_code ec;
    fs::recursive_directory_iterator it(root, fs::directory_options::skip_permission_denied, ec), end;
    std::vector<std::pair<std::string, std::uintmax_t>> env_files, scene_files;
    int seen = 0;
    for (; !ec && it != end; it.increment(ec)) {
      if (++seen > kInputsMaxEntries) {
        truncated = true;
        break;
      }
      if (it.depth() >= kInputsMaxDepth) it.disable_recursion_pending();
      const auto name = it->path().filename().string();
      if (!name.empty() && name[0] == '.') {
        it.disable_recursion_pending();
        continue;
      }
      std::error_code e2;
      if (!it->is_regular_file(e2) || it->is_symlink(e2)) continue;  // no link is followed out of the root
      const std::string ext = lower_extension(it->path());
      const std::string rel = it->path().lexically_relative(root).generic_string();
      const auto size = it->file_size(e2);
      if (ext == ".hdr" || ext == ".exr" || ext == ".ktx2" || ext == ".png")
        env_files.emplace_back(rel, size);
      else if (ext == ".gltf" || ext == ".glb")
        scene_files.emplace_back(rel, size);
    }
    std::sort(env_files.begin(), env_files.end());
    std::sort(scene_files.begin(), scene_files.end());
    for (const auto& [p, n] : env_files) environments.push_back(json{{"path", p}, {"bytes", n}});
    for (const auto& [p, n] : scene_files) scenes.push_back(json{{"path", p}, {"bytes", n}});
  }
  json o;
  o["input_root"] = !root.empty();
  o["environments"] = environments;
  o["scenes"] = scenes;
  if (truncated) o["truncated"] = true;
  reply_json(res, 200, o);
}

// GET /v1/jobs/ID/view/NAME: the file's contact sheet (`brdfbake view NAME`) as a PNG.
void get_view(const WebContext& c, const httplib::Request& req, httplib::Response& res) {
  const std::string id = req.matches[1], name = req.matches[2];
  const JobFile file = find_job_file(*c.store, *c.roots, c.jobs_dir, id, name, "shown");
  if (file.path.empty()) return reply_error(res, file.status, file.error);
  const std::string& path = file.path;
  static std::atomic<unsigned> counter{0};
  const fs::path png = c.tmp_dir / ("view-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + ".png");
  std::string bytes;
  try {
    ViewOptions options;
    options.title = name;
    options.relative_to = (c.jobs_dir / id).string();
    const ContactSheet sheet = render_contact_sheet({path}, options);
    write_contact_sheet(sheet, png.string());
    std::ifstream in(png, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    bytes = s.str();
  } catch (const Error& e) {
    std::error_code ec;
    fs::remove(png, ec);
    // Name the file as the job's folder does, not by the server's path.
    std::string m = e.what();
    for (size_t at = m.find(path); at != std::string::npos; at = m.find(path, at)) m.replace(at, path.size(), name);
    return reply_error(res, 422, c.roots->public_text(m));
  }
  std::error_code ec;
  fs::remove(png, ec);
  res.set_header("Cache-Control", "private, max-age=86400");  // a done job's files never change
  res.set_header("X-Content-Type-Options", "nosniff");
  res.set_content(bytes, "image/png");
}

// ---- GET /v1/jobs/ID/archive: the job's folder as one tar file ---------------------------------

// One file of the archive: its ustar header, then its bytes padded to 512.
struct TarMember {
  std::string name;  // inside the job's folder
  std::string path;  // on disk
  std::uint64_t size = 0;
  std::string header;
};

// The ustar header of a regular file (POSIX.1-1988): names up to 100 characters, or a prefix of up
// to 155 and a name of up to 100 split at a '/'. Returns "" for a name that does not fit.
std::string tar_header(const std::string& name, std::uint64_t size, std::int64_t mtime) {
  std::string h(512, '\0');
  std::string prefix, base = name;
  if (name.size() > 100) {
    const size_t slash = name.rfind('/', 155);
    if (slash == std::string::npos || name.size() - slash - 1 > 100 || slash == 0) return "";
    prefix = name.substr(0, slash);
    base = name.substr(slash + 1);
  }
  auto put = [&h](size_t at, const std::string& v) { h.replace(at, v.size(), v); };
  auto octal = [](std::uint64_t v, int digits) {
    char buf[24];
    std::snprintf(buf, sizeof buf, "%0*llo", digits, static_cast<unsigned long long>(v));
    return std::string(buf);
  };
  put(0, base);
  put(100, octal(0644, 7));
  put(108, octal(0, 7));
  put(116, octal(0, 7));
  put(124, octal(size, 11));
  put(136, octal(static_cast<std::uint64_t>(std::max<std::int64_t>(mtime, 0)), 11));
  put(148, std::string(8, ' '));
  h[156] = '0';
  put(257, std::string("ustar\0", 6));  // magic, then version "00"
  put(263, "00");
  put(345, prefix);
  unsigned sum = 0;
  for (char ch : h) sum += static_cast<unsigned char>(ch);
  put(148, octal(sum, 6));
  h[154] = '\0';
  h[155] = ' ';
  return h;
}

constexpr std::uint64_t padded(std::uint64_t n) { return (n + 511) / 512 * 512; }

void get_archive(const WebContext& c, const httplib::Request& req, httplib::Response& res) {
  const std::string id = req.matches[1];
  const auto r = c.store->get(id, false);
  if (!r) return reply_error(res, 404, "no job '" + id.substr(0, 40) + "'");
  if (r->state != JobState::Done)
    return reply_error(res, r->state == JobState::Queued || r->state == JobState::Running ? 409 : 404,
                       "job " + id + " is " + job_state_name(r->state) + ": its files are served once it is done");
  // Every regular file of the folder (no symbolic link is followed), by name: a done job's folder
  // no longer changes (docs/SERVICE.md, "Persistence").
  const fs::path folder = c.jobs_dir / id;
  auto members = std::make_shared<std::vector<TarMember>>();
  std::error_code ec;
  for (fs::recursive_directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code e2;
    if (it->is_symlink(e2) || !it->is_regular_file(e2)) continue;
    TarMember m;
    m.name = it->path().lexically_relative(folder).generic_string();
    m.path = it->path().string();
    m.size = it->file_size(e2);
    struct stat st {};
    const std::int64_t mtime = ::stat(m.path.c_str(), &st) == 0 ? static_cast<std::int64_t>(st.st_mtime) : 0;
    m.header = tar_header(m.name, m.size, mtime);
    if (m.header.empty())
      return reply_error(res, 500,
                         "job " + id + ": '" + m.name.substr(0, 80) + "' is too long a name for a tar archive");
    members->push_back(std::move(m));
  }
  std::sort(members->begin(), members->end(), [](const TarMember& a, const TarMember& b) { return a.name < b.name; });
  std::uint64_t total = 1024;  // two zero blocks end the archive
  for (const auto& m : *members) total += 512 + padded(m.size);
  res.set_header("Content-Disposition", content_disposition(id + ".tar"));
  res.set_header("X-Content-Type-Options", "nosniff");
  // Sequential writes: each call sends the next piece (a header, a chunk of a file, padding).
  res.set_content_provider(
      static_cast<size_t>(total), "application/x-tar",
      [members](size_t offset, size_t length, httplib::DataSink& sink) {
        std::uint64_t at = 0;
        for (const auto& m : *members) {
          if (offset < at + 512)
            return sink.write(m.header.data() + (offset - at), std::min<size_t>(length, at + 512 - offset));
          at += 512;
          if (offset < at + m.size) {
            std::ifstream in(m.path, std::ios::binary);
            char buf[1 << 16];
            const size_t n = static_cast<size_t>(std::min<std::uint64_t>({length, sizeof buf, at + m.size - offset}));
            in.seekg(static_cast<std::streamoff>(offset - at));
            if (!in.read(buf, static_cast<std::streamsize>(n))) return false;  // never a short file sent as whole
            return sink.write(buf, n);
          }
          at += m.size;
          const std::uint64_t pad = padded(m.size) - m.size;
          if (offset < at + pad) {
            static const char zeros[512] = {};
            return sink.write(zeros, std::min<size_t>(length, static_cast<size_t>(at + pad - offset)));
          }
          at += pad;
        }
        static const char zeros[1024] = {};
        return sink.write(zeros, std::min<size_t>(length, static_cast<size_t>(1024 - (offset - at))));
      });
}

}  // namespace

bool web_public_route(const std::string& method, const std::string& path) {
  if (method != "GET" && method != "HEAD") return false;
  return path == "/" || (path.find('/', 1) == std::string::npos && find_asset(path) != nullptr);
}

void register_web_routes(httplib::Server& http, const WebContext& context) {
  const WebContext c = context;
  for (const auto& a : detail::web_assets()) {
    const std::string route = std::string("/") + a.path;
    const std::string etag = asset_etag(a);
    const detail::WebAsset* asset = &a;
    auto serve = [asset, etag](const httplib::Request& req, httplib::Response& res) {
      res.set_header("Cache-Control", "no-cache");
      res.set_header("ETag", etag);
      res.set_header("Content-Security-Policy", kContentSecurityPolicy);
      res.set_header("X-Content-Type-Options", "nosniff");
      res.set_header("Referrer-Policy", "no-referrer");
      if (req.get_header_value("If-None-Match") == etag) {
        res.status = 304;
        return;
      }
      res.set_content(reinterpret_cast<const char*>(asset->data), asset->size, asset_content_type(asset->path));
    };
    http.Get(route, serve);
    if (route == "/index.html") http.Get("/", serve);
  }
  http.Get("/v1/kinds", [](const httplib::Request&, httplib::Response& res) {
    res.set_content(table_kinds_json(2) + "\n", "application/json");
  });
  http.Get("/v1/bake/options", [](const httplib::Request&, httplib::Response& res) {
    json o;
    o["options"] = json::parse(schema_json(bake_option_schema()));
    reply_json(res, 200, o);
  });
  http.Get("/v1/inputs", [c](const httplib::Request&, httplib::Response& res) { get_inputs(c, res); });
  http.Post("/v1/plan", [c](const httplib::Request& req, httplib::Response& res) { post_plan(c, req, res); });
  http.Post("/v1/uploads", [c](const httplib::Request& req, httplib::Response& res) { post_upload(c, req, res); });
  http.Get(R"(/v1/jobs/([A-Za-z0-9_-]+)/job)", [c](const httplib::Request& req, httplib::Response& res) {
    const std::string id = req.matches[1];
    const auto r = c.store->get(id);
    if (!r) return reply_error(res, 404, "no job '" + id.substr(0, 40) + "'");
    reply_json(res, 200, json::parse(r->job, nullptr, false));
  });
  http.Get(R"(/v1/jobs/([A-Za-z0-9_-]+)/archive)",
           [c](const httplib::Request& req, httplib::Response& res) { get_archive(c, req, res); });
  http.Get(R"(/v1/jobs/([A-Za-z0-9_-]+)/view/(.+))",
           [c](const httplib::Request& req, httplib::Response& res) { get_view(c, req, res); });
}

Plan bake_plan(const std::string& body_text, const std::string& origin, const Roots& roots) {
  const json body = io::parse_json(body_text.empty() ? std::string("{}") : body_text, origin);
  if (!body.is_object()) throw Error(origin + ": the request is a JSON object of bake options (docs/SERVICE.md)");
  // JSON values as the options' types take them; their checks, names and messages are the parser's,
  // shared with the command line and Python.
  Params given;
  for (auto it = body.begin(); it != body.end(); ++it) {
    const std::string& key = it.key();  // an alias (env, cube_size) is the parser's to rename
    ParamValue v;
    if (it->is_boolean())
      v = it->get<bool>();
    else if (it->is_number())
      v = it->get<double>();
    else if (it->is_string())
      v = it->get<std::string>();
    else if (it->is_array() && std::all_of(it->begin(), it->end(), [](const json& x) { return x.is_number(); }))
      v = it->get<std::vector<double>>();
    else
      throw Error(origin + ": " + key.substr(0, 60) +
                  ": must be a number, a string, a boolean or a list of numbers (got " + io::json_excerpt(*it) + ")");
    given.push_back({key, v});
  }
  OptionNaming naming;
  naming.prefix = origin;
  const BakeOptions options = parse_bake_options(given, naming);
  Plan plan;
  if (options.scene.empty()) {
    plan = plan_default(options.plan);
  } else {
    const std::string path = roots.input_file(options.scene, origin + ": scene");
    const std::string bytes = io::read_text_file(path, "scene");
    // Parsed from memory with no base folder: the server looks at no file the scene refers to.
    const bool glb = bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0;
    const Scene s = glb ? parse_glb(bytes, options.scene, "") : parse_scene_json(bytes, options.scene, "");
    plan = plan_scene(s, options.plan);
  }
  plan.job.preview = options.preview;  // as plan_bake does
  return plan;
}

}  // namespace brdfbake::server
