// Path confinement for the server: every file a request makes the server read lies under the
// allow-listed input root, every file it writes under the data directory. A path that leaves its
// root ('..', an absolute path outside it, a symbolic link that points out of it) is refused with a
// one-line message naming the field; nothing is opened before the check (docs/SERVICE.md,
// "Security").
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "brdfbake/job.hpp"

namespace brdfbake::server {

// A file uploaded through POST /v1/uploads is named "upload:NAME" in requests; it is kept in
// DATA/uploads/ for kUploadMaxAgeSeconds, and the oldest go first beyond kUploadMaxTotalBytes.
inline constexpr const char* kUploadPrefix = "upload:";
inline constexpr double kUploadMaxAgeSeconds = 24 * 3600.0;
inline constexpr std::uint64_t kUploadMaxTotalBytes = std::uint64_t(1) << 30;

class Roots {
 public:
  // `input_root` may be empty: then no request may read a file (builtin environments only).
  // Both are made canonical; throws Error when a root does not exist.
  Roots(const std::string& input_root, const std::string& data_dir);

  const std::filesystem::path& input_root() const { return input_; }
  const std::filesystem::path& data_dir() const { return data_; }
  std::filesystem::path uploads_dir() const { return data_ / "uploads"; }

  // The canonical path of an existing input file named by a request: relative paths are relative to
  // the input root; absolute ones must lie inside it; "upload:NAME" is an upload (data_file in
  // uploads_dir()). Throws Error "<field>: ..." otherwise.
  std::string input_file(const std::string& path, const std::string& field) const;
  // An environment source: builtin:NAME as it is; a file, six comma-separated files or a path with
  // {face}: each file confined (the result names the six files when there were six).
  std::string environment(const std::string& spec, const std::string& field) const;
  // Every input path of a job document confined and rewritten to its canonical form, before the
  // job is parsed (validation opens material files): the job's and each table's environment, and
  // each table's input files (Path parameters that are not outputs). Fields of the wrong type or of
  // unknown kinds are left for parse_job to refuse. Messages name the field as parse_job does
  // ("<origin>: tables[0].material: ...").
  void confine_job_document(nlohmann::ordered_json& doc, const std::string& origin) const;

  // A file under `dir` (inside the data directory) named by a request: relative, no '..', no
  // symbolic link on the way, a regular file. Returns "" when it does not exist.
  std::string data_file(const std::filesystem::path& dir, const std::string& name) const;

  // A message as a client may read it, without the server's own folders: a path under the data
  // directory becomes the name inside its job's folder (the job and staging folders, the runner's
  // scratch folder and the writers' temporaries taken out: 'big.ktx2'), or inside the data
  // directory ('jobs.db'); a path under the input root becomes the path a request names it by.
  std::string public_text(const std::string& text) const;

  // Whether `p` (absolute, normal) is `root` or lies below it, component by component.
  static bool inside(const std::filesystem::path& p, const std::filesystem::path& root);

 private:
  std::filesystem::path input_;
  std::filesystem::path data_;
};

}  // namespace brdfbake::server
