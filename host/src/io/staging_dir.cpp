#include "io/staging_dir.hpp"

#include <unistd.h>

#include <random>

#include "brdfbake/output_lock.hpp"
#include "io/atomic_file.hpp"

namespace brdfbake::io {

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

// The files below `dir`, relative to it, `last` excluded.
void list_files(const fs::path& dir, const fs::path& rel, const std::string& last, std::vector<fs::path>& out) {
  for (const auto& e : fs::directory_iterator(dir)) {
    const fs::path r = rel / e.path().filename();
    if (e.is_directory()) list_files(e.path(), r, last, out);
    else if (r.string() != last) out.push_back(r);
  }
}

}  // namespace

void StagingDir::commit(const std::string& last) {
  std::error_code ec;
  if (!fs::exists(target_, ec)) {
    fs::rename(path_, target_, ec);
    if (ec) throw_write_error(target_.string(), ec.message());
    path_.clear();
    committed_ = true;
    return;
  }
  std::vector<fs::path> order;
  list_files(path_, {}, last, order);
  if (fs::exists(path_ / last, ec)) order.push_back(last);
  // Check the way is clear before moving anything.
  for (const auto& f : order)
    if (fs::is_directory(target_ / f, ec)) throw_write_error((target_ / f).string(), "a folder of that name is in the way");
  for (const auto& f : order) {
    const fs::path to = target_ / f;
    if (!to.parent_path().empty()) fs::create_directories(to.parent_path(), ec);
    fs::rename(path_ / f, to, ec);
    if (ec) throw_write_error(to.string(), ec.message());
  }
  committed_ = true;
}

}  // namespace brdfbake::io
