// A folder's worth of outputs written all or nothing: everything goes into a hidden temporary folder
// beside the target ("." NAME ".tmp-<pid>-<random>") and is moved into the target at the end.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace brdfbake::io {

class StagingDir {
 public:
  // Creates the missing parents of `target` (removed again unless committed) and the temporary
  // folder. Throws Error "cannot write '<target>': ..." when that is not possible.
  explicit StagingDir(const std::filesystem::path& target);
  ~StagingDir();
  StagingDir(const StagingDir&) = delete;
  StagingDir& operator=(const StagingDir&) = delete;

  const std::filesystem::path& path() const { return path_; }

  // Moves what the temporary folder holds into the target: the whole folder when the target does
  // not exist yet, else entry by entry (sub-folders merged, existing files replaced), `last` (the
  // manifest) after all the others.
  void commit(const std::string& last);

 private:
  std::filesystem::path target_;
  std::filesystem::path path_;
  std::vector<std::filesystem::path> created_parents_;
  bool committed_ = false;
};

}  // namespace brdfbake::io
