// The files of a request checked as a set before anything is baked (brdfbake/output_checks.hpp).
#include "brdfbake/output_checks.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <iterator>
#include <random>

#include "brdfbake/engines.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "families/family.hpp"
#include "io/special_files.hpp"

namespace brdfbake {

namespace {

namespace fs = std::filesystem;

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// A path as the outputs of one request are compared: lexically normal, without "./" or a trailing
// '/', and in lower case where the file system ignores case.
std::string normal(const std::string& path, bool ignore_case) {
  std::string n = fs::path(path).lexically_normal().generic_string();
  while (n.size() > 1 && n.back() == '/') n.pop_back();
  return ignore_case ? lower(n) : n;
}

// An environment kind's output that is a folder of images (not a container or the SH JSON): the
// rule of validate_table's formats.
bool is_folder_output(const TableRequest& t) {
  if (!table_kind_uses_environment(t.kind) || t.output.empty() || t.output == "-") return false;
  if (!t.format.empty()) return t.format != "ktx2" && t.format != "ktx" && t.format != "dds" && t.format != "json";
  const std::string ext = lower(fs::path(t.output).extension().string());
  return !(ext == ".json" || ext == ".ktx2" || ext == ".ktx" || ext == ".dds");
}

struct Named {
  std::string field;  // as messages name it
  std::string path;   // as given
  std::string key;    // normalised
  bool folder = false;
};

// Two outputs on one path, one inside another's folder output or under another's file: Error naming
// both fields ("tables[1].sh_json: 'a.json' is also tables[0].output").
void check_output_set(const std::vector<Named>& outputs, const std::string& prefix, bool ignore_case) {
  for (size_t i = 0; i < outputs.size(); ++i)
    for (size_t j = 0; j < outputs.size(); ++j) {
      if (i == j) continue;
      const Named& a = outputs[i];
      const Named& b = outputs[j];
      if (a.key == b.key && i > j) {
        const bool only_case =
            fs::path(a.path).lexically_normal() != fs::path(b.path).lexically_normal() && ignore_case;
        throw Error(prefix + a.field + ": '" + a.path + "' is also " + b.field +
                    (b.path != a.path ? " ('" + b.path + "')" : "") +
                    (only_case ? ", the same file on this file system (it ignores case)" : "") +
                    ": two outputs on one path, one would overwrite the other; give one another name");
      }
      if (a.key.size() > b.key.size() && a.key.compare(0, b.key.size(), b.key) == 0 && a.key[b.key.size()] == '/') {
        if (b.folder)
          throw Error(prefix + a.field + ": '" + a.path + "' is inside the folder " + b.field + " ('" + b.path +
                      "'), which that table writes as a whole: give it a path outside it");
        throw Error(prefix + a.field + ": '" + a.path + "' would be under " + b.field + " ('" + b.path +
                    "'), which is a file: give one of them another name");
      }
    }
}

// No output the same file as an input (device and inode: a hard link, a symbolic link, another
// spelling of the path). `outputs` hold the paths as they will be written.
void check_not_inputs(const std::vector<Named>& outputs, const std::vector<Named>& inputs, const std::string& prefix) {
  for (const Named& o : outputs) {
    io::FileId out_id;
    if (io::file_type(o.path, &out_id) != io::FileType::Regular) continue;
    for (const Named& in : inputs) {
      io::FileId in_id;
      if (io::file_type(in.path, &in_id) == io::FileType::Missing) continue;
      if (out_id == in_id)
        throw Error(prefix + o.field + ": '" + o.path + "' is the same file as " + in.field + " ('" + in.path +
                    "'): writing it would destroy the input; give the output another name");
    }
  }
}

std::string origin_of(const Job& job) { return job.source.empty() ? std::string("job") : job.source; }

std::string table_field(size_t i, const RequestFile& f) {
  return "tables[" + std::to_string(i) + "]." + f.field + (f.beside.empty() ? "" : "'s " + f.beside);
}

std::string named_field(const FieldNaming& naming, TableKind kind, const RequestFile& f) {
  return naming.field(kind, f.field) + (f.beside.empty() ? "" : "'s " + f.beside);
}

}  // namespace

std::vector<RequestFile> table_input_files(const TableRequest& t) {
  std::vector<RequestFile> out;
  if (table_kind_uses_environment(t.kind)) {
    std::vector<std::string> files;
    try {
      files = environment_files(t.environment);
    } catch (const Error&) {  // a bad list: the environment's own check names it
    }
    for (const auto& f : files) out.push_back({"environment", f, false, ""});
  }
  for (const auto& d : table_schema(t.kind))
    if (d.type == ParamType::Path && !d.output_only && t.find(d.name) && t.text(d.name) != "-")
      out.push_back({d.name, t.text(d.name), false, ""});
  for (auto& f : detail::family_of(t.kind).inputs_beside(t)) out.push_back(std::move(f));
  return out;
}

std::vector<RequestFile> table_output_files(const TableRequest& t) {
  std::vector<RequestFile> out;
  if (!t.output.empty() && t.output != "-") out.push_back({"output", t.output, is_folder_output(t), ""});
  for (const auto& d : table_schema(t.kind))
    if (d.type == ParamType::Path && d.output_only && t.find(d.name) && !t.text(d.name).empty())
      out.push_back({d.name, t.text(d.name), false, ""});
  if (!t.output.empty() && t.output != "-")
    for (auto& f : detail::family_of(t.kind).outputs_beside(t)) out.push_back(std::move(f));
  return out;
}

void check_table_files(const TableRequest& t, const FieldNaming& naming, bool output_streams) {
  std::vector<Named> outputs, inputs;
  for (const auto& f : table_output_files(t)) {
    const std::string field = named_field(naming, t.kind, f);
    io::check_output_target(f.path, f.field == "output" && f.beside.empty() && output_streams, field);
    if (!f.folder && io::file_type(f.path) == io::FileType::Folder)
      throw Error((naming.cli ? "" : naming.prefix + ": ") + field + ": '" + f.path +
                  "' is a folder, which the file cannot replace: give the output another name");
    outputs.push_back({field, f.path, normal(f.path, false), f.folder});
  }
  for (const auto& f : table_input_files(t))
    inputs.push_back({named_field(naming, t.kind, f), f.path, normal(f.path, false), false});
  check_output_set(outputs, naming.cli ? "" : naming.prefix + ": ", false);
  check_not_inputs(outputs, inputs, naming.cli ? "" : naming.prefix + ": ");
}

namespace {

std::vector<RequestFile> job_files_beside_tables(const Job& job, const std::string& engine_name) {
  std::vector<RequestFile> out;
  EngineTarget target = EngineTarget::Generic;
  try {
    target = engine_target_from_name(job.target);
  } catch (const Error&) {  // validate_job names a bad target
  }
  if (target != EngineTarget::Generic)
    for (std::string f : engine_settings(target).files) {
      f = f.substr(0, f.find(' '));                    // "NAME_charlie.ktx2 (with a Charlie chain)"
      if (f.find('<') != std::string::npos) continue;  // a pattern (the glTF faces): no table is named so
      const auto at = f.find("NAME");
      if (at != std::string::npos) {
        if (engine_name.empty()) continue;  // the folder's name, known when the job runs
        f.replace(at, 4, engine_name);
      }
      out.push_back({"target", f, false, "file " + f});
    }
  if (job.preview)
    for (const char* f : {"preview.png", "preview_splitsum.exr", "preview_reference.exr", "preview.json"})
      out.push_back({"preview", f, false, std::string("file ") + f});
  return out;
}

void check_outputs_of_job(const Job& job, bool ignore_case, const std::string& engine_name) {
  std::vector<Named> outputs;
  for (size_t i = 0; i < job.tables.size(); ++i)
    for (const auto& f : table_output_files(job.tables[i]))
      outputs.push_back({table_field(i, f), f.path, normal(f.path, ignore_case), f.folder});
  for (const auto& f : job_files_beside_tables(job, engine_name))
    outputs.push_back({f.field + "'s " + f.beside, f.path, normal(f.path, ignore_case), false});
  for (const Named& o : outputs)  // the outputs' own names are checked by validate_job; not what is beside them
    if (o.key == normal("manifest.json", ignore_case))
      throw Error(origin_of(job) + ": " + o.field + ": '" + o.path +
                  "' is the job's manifest, which the job writes last: give the output another name");
  check_output_set(outputs, origin_of(job) + ": ", ignore_case);
}

}  // namespace

void check_job_output_set(const Job& job, bool ignore_case) { check_outputs_of_job(job, ignore_case, job.engine_name); }

void check_job_files(const Job& job, const std::string& folder, const std::string& engine_name) {
  std::vector<Named> outputs, inputs;
  bool differ_in_case_only = false;
  for (size_t i = 0; i < job.tables.size(); ++i)
    for (const auto& f : table_output_files(job.tables[i])) {
      const std::string path = (fs::path(folder) / f.path).lexically_normal().string();
      if (const io::OutputTargetInfo info = io::output_target(path); info.target != io::OutputTarget::File)
        throw Error(origin_of(job) + ": " + table_field(i, f) + ": '" + path + "' is " + info.what +
                    ", which the file would replace: remove it or give the output another name");
      // A folder of the output's path that is a file in the existing folder: the commit could not
      // move it in, after the files before it were (found here, before anything is baked).
      fs::path at = folder;
      const fs::path rel = fs::path(f.path).lexically_normal();
      for (auto part = rel.begin(); part != rel.end() && std::next(part) != rel.end(); ++part) {
        at /= *part;
        const io::FileType type = io::file_type(at.string());
        if (type == io::FileType::Missing) break;
        if (type != io::FileType::Folder)
          throw IoError("cannot write '" + path + "' (" + origin_of(job) + ": " + table_field(i, f) + "): '" +
                        at.string() + "' is " + io::file_type_text(type) + ", not a folder");
      }
      outputs.push_back({table_field(i, f), path, normal(f.path, false), f.folder});
    }
  for (size_t i = 0; i < outputs.size() && !differ_in_case_only; ++i)
    for (size_t j = i + 1; j < outputs.size(); ++j)
      if (outputs[i].key != outputs[j].key && lower(outputs[i].key) == lower(outputs[j].key))
        differ_in_case_only = true;
  check_outputs_of_job(job, differ_in_case_only && folder_ignores_case(folder),
                       !engine_name.empty()       ? engine_name
                       : !job.engine_name.empty() ? job.engine_name
                                                  : fs::path(folder).lexically_normal().filename().string());
  // The job file itself is an input too: an output of that name would replace it.
  if (io::file_type(job.source) == io::FileType::Regular) inputs.push_back({"the job file", job.source, "", false});
  for (size_t i = 0; i < job.tables.size(); ++i)
    for (const auto& f : table_input_files(job.tables[i])) inputs.push_back({table_field(i, f), f.path, "", false});
  check_not_inputs(outputs, inputs, origin_of(job) + ": ");
}

void check_outputs_not_inputs(const std::vector<RequestFile>& outputs, const std::vector<RequestFile>& inputs) {
  std::vector<Named> out, in;
  for (const auto& f : outputs) {
    const std::string field = f.field + (f.beside.empty() ? "" : "'s " + f.beside);
    if (io::file_type(f.path) == io::FileType::Folder)
      throw Error(field + ": '" + f.path +
                  "' is a folder, which the file cannot replace: give the output another name");
    out.push_back({field, f.path, normal(f.path, false), false});
  }
  for (const auto& f : inputs) {
    if (io::file_type(f.path) != io::FileType::Folder) {
      in.push_back({f.field, f.path, "", false});
      continue;
    }
    std::error_code ec;
    fs::recursive_directory_iterator it(f.path, fs::directory_options::none, ec), end;
    for (size_t n = 0; !ec && it != end && n < 4096; it.increment(ec), ++n) {
      if (it.depth() > 1) it.disable_recursion_pending();
      if (it->is_regular_file(ec))
        in.push_back({f.field + "'s " + it->path().filename().string(), it->path().string(), "", false});
    }
  }
  check_output_set(out, "", false);
  check_not_inputs(out, in, "");
}

bool folder_ignores_case(const std::string& folder) {
  std::error_code ec;
  fs::path dir = fs::absolute(folder, ec);
  if (ec) return false;
  while (!dir.empty() && !fs::is_directory(dir, ec)) {
    if (dir == dir.parent_path()) return false;
    dir = dir.parent_path();
  }
  std::mt19937_64 g{std::random_device{}()};
  const std::string name =
      ".brdfbake-case-probe-" + std::to_string(::getpid()) + "-" + std::to_string(g() % 1000000000ull);
  const fs::path probe = dir / (name + "-a");
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) return false;  // cannot probe (no permission): names are compared as given
  ::close(fd);
  const bool same = fs::exists(dir / (name + "-A"), ec);
  ::unlink(probe.c_str());
  return same;
}

}  // namespace brdfbake
