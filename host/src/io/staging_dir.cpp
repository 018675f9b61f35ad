#include "io/staging_dir.hpp"

#include <unistd.h>

#include <random>

#include "brdfbake/error.hpp"
#include "brdfbake/output_lock.hpp"
#include "io/atomic_file.hpp"
#include "io/special_files.hpp"

namespace brdfbake::io {

bool is_new_or_empty_folder(const std::filesystem::path& folder) {
  std::error_code ec;
  const auto type = std::filesystem::symlink_status(folder, ec).type();
  if (type == std::filesystem::file_type::not_found) return true;
  return type == std::filesystem::file_type::directory && std::filesystem::is_empty(folder, ec) && !ec;
}

namespace fs = std::filesystem;

StagingDir::StagingDir(const fs::path& target) : target_(target) {
  fs::path parent = target.parent_path();
  if (parent.empty()) parent = ".";
  std::error_code ec;
  if (!fs::exists(parent, ec)) {
    // Create the missing parents, remembering them so that a failure removes them again.
    std::vector<fs::path> missing;
    for (fs::path p = parent; !p.empty() && !fs::exists(p, ec); p = p.parent_path()) missing.push_back(p);
    for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
      if (!fs::create_directory(*it, ec) && ec) throw_write_error(target.string(), ec.message());
      created_parents_.push_back(*it);
    }
  }
  if (const OutputTargetInfo info = output_target(target.string()); info.target != OutputTarget::File)
    throw Error("cannot write '" + target.string() + "': it is " + info.what +
                ", not a folder brdfbake can write into");
  if (fs::exists(target, ec) && !fs::is_directory(target, ec))
    throw_write_error(target.string(), "it exists and is not a folder");
  ::brdfbake::remove_stale_temporaries(target.string());
  std::mt19937_64 g{std::random_device{}()};
  for (int attempt = 0; attempt < 8; ++attempt) {
    const fs::path candidate =
        parent / (temp_name_prefix(target.filename().string(), ::getpid()) + std::to_string(g() % 1000000000ull));
    if (fs::create_directory(candidate, ec)) {
      path_ = candidate;
      return;
    }
    if (ec) throw_write_error(target.string(), ec.message());
  }
  throw_write_error(target.string(), "could not create a temporary folder beside it");
}

StagingDir::~StagingDir() {
  std::error_code ec;
  if (!path_.empty()) fs::remove_all(path_, ec);
  if (!committed_)
    for (auto it = created_parents_.rbegin(); it != created_parents_.rend(); ++it) fs::remove(*it, ec);
}

namespace {

// The files below `dir`, relative to it, `last` excluded. Throws IoError naming `target` when the
// temporary folder cannot be listed (removed while the run wrote it).
void list_files(const fs::path& dir, const fs::path& rel, const std::string& last, std::vector<fs::path>& out,
                const fs::path& target) {
  std::error_code ec;
  fs::directory_iterator it(dir, ec), end;
  for (; !ec && it != end; it.increment(ec)) {
    const fs::path r = rel / it->path().filename();
    std::error_code type_ec;
    if (it->is_directory(type_ec))
      list_files(it->path(), r, last, out, target);
    else if (r.string() != last)
      out.push_back(r);
  }
  if (ec)
    throw IoError("cannot write '" + target.string() + "': its temporary folder cannot be read (" + ec.message() +
                  "): was it removed while the run wrote it?");
}

}  // namespace

std::vector<MovedFile> files_to_move(const fs::path& staging, const fs::path& target, const std::string& last) {
  std::vector<fs::path> order;
  list_files(staging, {}, last, order, target);
  std::error_code ec;
  if (fs::exists(staging / last, ec)) order.push_back(last);
  std::vector<MovedFile> moved;
  for (const auto& f : order) {
    MovedFile m;
    m.rel = f;
    if (file_type((staging / f).string(), &m.id) == FileType::Missing)
      throw IoError("cannot write '" + target.string() + "': '" + (staging / f).string() +
                    "' disappeared from the temporary folder before it was moved in (was it removed?)");
    moved.push_back(m);
  }
  return moved;
}

// Every file moved must be in the target with its identity once the commit ends: a folder removed
// or replaced while the run wrote it (by another program: the lock only excludes brdfbake runs)
// would otherwise end in a success that lists files that are not there.
void check_moved_in(const fs::path& target, const std::vector<MovedFile>& moved) {
  for (const MovedFile& m : moved) {
    FileId id;
    const fs::path at = target / m.rel;
    if (file_type(at.string(), &id) == FileType::Missing)
      throw IoError("cannot write '" + target.string() + "': '" + at.string() +
                    "' is missing after the files were moved in: the folder was removed or replaced while this run "
                    "wrote it; run again");
    if (m.id.valid && !(id == m.id))
      throw IoError("cannot write '" + target.string() + "': '" + at.string() +
                    "' is not the file this run wrote: the folder was changed while this run wrote it; run again");
  }
}

void StagingDir::commit(const std::string& last) {
  std::error_code ec;
  const std::vector<MovedFile> moved = files_to_move(path_, target_, last);  // to check afterwards
  if (!fs::exists(target_, ec)) {
    fs::rename(path_, target_, ec);
    if (ec) throw_write_error(target_.string(), ec.message());
    path_.clear();
    committed_ = true;
    check_moved_in(target_, moved);
    return;
  }
  // Check the way is clear before moving anything: no folder where a file goes, and no device, FIFO
  // or socket a rename would replace.
  for (const MovedFile& m : moved) {
    const fs::path to = target_ / m.rel;
    if (fs::is_directory(to, ec)) throw_write_error(to.string(), "a folder of that name is in the way");
    if (const OutputTargetInfo info = output_target(to.string()); info.target != OutputTarget::File)
      throw Error("cannot write '" + to.string() + "': it is " + info.what + ", which the file would replace");
  }
  for (const MovedFile& m : moved) {
    const fs::path to = target_ / m.rel;
    if (!to.parent_path().empty()) fs::create_directories(to.parent_path(), ec);
    fs::rename(path_ / m.rel, to, ec);
    if (ec) throw_write_error(to.string(), ec.message());
  }
  committed_ = true;
  check_moved_in(target_, moved);
}

}  // namespace brdfbake::io
