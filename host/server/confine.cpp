#include "server/confine.hpp"

#include <sys/stat.h>

#include <vector>

#include "brdfbake/error.hpp"

namespace brdfbake::server {

namespace fs = std::filesystem;

namespace {

fs::path canonical_root(const std::string& dir, const char* what) {
  std::error_code ec;
  const fs::path p = fs::canonical(dir, ec);
  if (ec || !fs::is_directory(p, ec)) throw Error(std::string(what) + " '" + dir + "' is not an existing folder");
  return p;
}

bool has_dot_dot(const fs::path& p) {
  for (const auto& part : p)
    if (part == "..") return true;
  return false;
}

// A path as quoted in messages: at most 80 characters.
std::string quoted(const std::string& s) { return "'" + (s.size() <= 80 ? s : s.substr(0, 80) + "...") + "'"; }

}  // namespace

Roots::Roots(const std::string& input_root, const std::string& data_dir) {
  if (!input_root.empty()) input_ = canonical_root(input_root, "--input-root");
  data_ = canonical_root(data_dir, "--data");
}

bool Roots::inside(const fs::path& p, const fs::path& root) {
  auto a = p.begin(), b = root.begin();
  for (; b != root.end(); ++a, ++b)
    if (a == p.end() || *a != *b) return false;
  return true;
}

std::string Roots::input_file(const std::string& path, const std::string& field) const {
  if (path.empty()) throw Error(field + ": must not be empty");
  if (path.find('\0') != std::string::npos) throw Error(field + ": must not contain a NUL character");
  // A file the page uploaded (POST /v1/uploads): by the name the upload answered, in DATA/uploads/.
  if (path.rfind(kUploadPrefix, 0) == 0) {
    const std::string name = path.substr(std::char_traits<char>::length(kUploadPrefix));
    const std::string file = name.find('/') == std::string::npos ? data_file(uploads_dir(), name) : std::string();
    if (file.empty())
      throw Error(field + ": " + quoted(path) +
                  " is not an upload of this server (or it was removed: uploads are kept " +
                  std::to_string(int(kUploadMaxAgeSeconds / 3600)) + " hours)");
    return file;
  }
  if (input_.empty())
    throw Error(field + ": " + quoted(path) +
                ": this server reads no files (it was started without --input-root); use builtin: environments");
  const fs::path given(path);
  if (has_dot_dot(given)) throw Error(field + ": " + quoted(path) + " must stay inside the input root (no '..')");
  const fs::path joined = given.is_absolute() ? given.lexically_normal() : (input_ / given).lexically_normal();
  if (!inside(joined, input_)) throw Error(field + ": " + quoted(path) + " is outside the server's input root");
  std::error_code ec;
  const fs::path real = fs::canonical(joined, ec);
  if (ec) throw Error(field + ": " + quoted(path) + " not found under the server's input root");
  // A symbolic link on the way may point anywhere: what counts is where the path really leads.
  if (!inside(real, input_))
    throw Error(field + ": " + quoted(path) + " leads outside the server's input root (a symbolic link)");
  if (!fs::is_regular_file(real, ec)) throw Error(field + ": " + quoted(path) + " is not a file");
  return real.string();
}

std::string Roots::environment(const std::string& spec, const std::string& field) const {
  if (spec.rfind("builtin:", 0) == 0) return spec;
  if (spec.find(',') != std::string::npos) {
    std::vector<std::string> parts;
    size_t start = 0;
    for (;;) {
      const size_t comma = spec.find(',', start);
      parts.push_back(spec.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    if (parts.size() != 6)
      throw Error(field + ": six comma-separated face files are expected (got " + std::to_string(parts.size()) + ")");
    std::string out;
    for (size_t i = 0; i < parts.size(); ++i) out += (i ? "," : "") + input_file(parts[i], field);
    return out;
  }
  const size_t at = spec.find("{face}");
  if (at != std::string::npos) {
    std::string out;
    for (const char* face : {"px", "nx", "py", "ny", "pz", "nz"}) {
      std::string p = spec;
      for (size_t k = p.find("{face}"); k != std::string::npos; k = p.find("{face}", k)) p.replace(k, 6, face);
      out += (out.empty() ? "" : ",") + input_file(p, field);
    }
    return out;
  }
  return input_file(spec, field);
}

void Roots::confine_job_document(nlohmann::ordered_json& doc, const std::string& origin) const {
  if (!doc.is_object()) return;
  auto tables = doc.find("tables");
  if (tables != doc.end() && tables->is_array()) {
    for (size_t i = 0; i < tables->size(); ++i) {
      auto& t = (*tables)[i];
      if (!t.is_object()) continue;
      auto kind = t.find("kind");
      if (kind == t.end() || !kind->is_string()) continue;
      TableKind k;
      try {
        k = table_kind_from_name(kind->get<std::string>());
      } catch (const Error&) {
        continue;  // parse_job names the known kinds
      }
      const std::string where = origin + ": tables[" + std::to_string(i) + "]";
      if (table_kind_uses_environment(k)) {
        auto env = t.find("environment");
        if (env != t.end() && env->is_string()) *env = environment(env->get<std::string>(), where + ".environment");
      }
      for (const auto& d : table_schema(k)) {
        if (d.type != ParamType::Path || d.output_only) continue;
        auto v = t.find(d.name);
        if (v != t.end() && v->is_string()) *v = input_file(v->get<std::string>(), where + "." + d.name);
      }
    }
  }
  // The job's environment is confined even when no table reads it: a job names no path outside.
  auto env = doc.find("environment");
  if (env != doc.end() && env->is_string()) *env = environment(env->get<std::string>(), origin + ": environment");
}

namespace {

// ".big.exr.tmp-31149-a329520719de9ae8" (io's temporaries, staging folders) -> "big.exr"
std::string without_temporary(const std::string& name) {
  if (name.size() < 2 || name[0] != '.') return name;
  const size_t tmp = name.rfind(".tmp-");
  if (tmp == std::string::npos || tmp < 2) return name;
  return name.substr(1, tmp - 1);
}

bool ends_path(const std::string& s, size_t i) {
  const char c = s[i];
  if (c == '\'' || c == '"' || c == '\n' || c == ' ' || c == ',' || c == ';' || c == ')') return true;
  return c == ':' && (i + 1 == s.size() || s[i + 1] == ' ');
}

// Every path below `root` in `text` replaced by rename(the path relative to root).
template <class Rename>
void replace_paths(std::string& text, const fs::path& root, Rename rename) {
  if (root.empty()) return;
  const std::string prefix = root.string() + "/";
  for (size_t at = text.find(prefix); at != std::string::npos; at = text.find(prefix, at)) {
    size_t end = at + prefix.size();
    while (end < text.size() && !ends_path(text, end)) ++end;
    const std::string shown = rename(text.substr(at + prefix.size(), end - at - prefix.size()));
    text.replace(at, end - at, shown);
    at += shown.size();
  }
}

}  // namespace

std::string Roots::public_text(const std::string& text) const {
  std::string out = text;
  auto data = [](const std::string& rel) {
    std::vector<std::string> parts;
    for (const auto& p : fs::path(rel)) parts.push_back(p.string());
    size_t first = 0;
    // jobs/<id>/..., jobs/.<id>.tmp-<pid>-<n>/... (staging), tmp/.brdfbake-run-<pid>-<n>/... (scratch)
    if (parts.size() >= 2 && (parts[0] == "jobs" || parts[0] == "tmp")) first = 2;
    // uploads/NAME: the name a request gives it
    if (parts.size() == 2 && parts[0] == "uploads") return kUploadPrefix + without_temporary(parts[1]);
    // tmp/upload-NAME: an upload while it is checked (web_routes.cpp)
    if (parts.size() == 2 && parts[0] == "tmp" && parts[1].rfind("upload-", 0) == 0)
      return kUploadPrefix + without_temporary(parts[1].substr(7));
    std::string shown;
    for (size_t i = first; i < parts.size(); ++i)
      if (!parts[i].empty()) shown += (shown.empty() ? "" : "/") + without_temporary(parts[i]);
    return shown.empty() ? std::string("the job's folder") : shown;
  };
  auto input = [](const std::string& rel) { return rel; };
  // The more specific root first, when one lies inside the other.
  if (input_.string().size() > data_.string().size()) {
    replace_paths(out, input_, input);
    replace_paths(out, data_, data);
  } else {
    replace_paths(out, data_, data);
    replace_paths(out, input_, input);
  }
  return out;
}

std::string Roots::data_file(const fs::path& dir, const std::string& name) const {
  if (name.empty() || name.find('\0') != std::string::npos) return {};
  const fs::path given(name);
  if (given.is_absolute() || has_dot_dot(given)) return {};
  const fs::path p = (dir / given).lexically_normal();
  if (!inside(p, dir) || !inside(p, data_)) return {};
  // No symbolic link on the way from the data directory down (the server writes none).
  fs::path walk = data_;
  const fs::path rel = p.lexically_relative(data_);
  for (const auto& part : rel) {
    walk /= part;
    struct stat st {};
    if (::lstat(walk.c_str(), &st) != 0 || S_ISLNK(st.st_mode)) return {};
  }
  struct stat st {};
  if (::lstat(p.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return {};
  return p.string();
}

}  // namespace brdfbake::server
