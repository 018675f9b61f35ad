// A folder's worth of outputs written all or nothing: everything goes into a hidden temporary folder
// beside the target ("." NAME ".tmp-<pid>-<random>") and is moved into the target at the end.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "io/special_files.hpp"

namespace brdfbake::io {

// Whether `folder` may be taken whole by a command that replaces what it writes there (preview's
// --keep-bake, the bake sweep's --keep-bakes): it does not exist, or it is an empty folder (not a
// link to one, not a file). Symlinks are not followed.
bool is_new_or_empty_folder(const std::filesystem::path& folder);

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
  // manifest) after all the others; then checks that every file arrived (check_moved_in). A device,
  // a FIFO or a socket in the way is refused before anything moves.
  void commit(const std::string& last);

 private:
  std::filesystem::path target_;
  std::filesystem::path path_;
  std::vector<std::filesystem::path> created_parents_;
  bool committed_ = false;
};

// A file of a staging folder as it is moved in: its path relative to the folder, and its identity
// (io/special_files.hpp) to find it again in the target.
struct MovedFile {
  std::filesystem::path rel;
  FileId id;
};
// The files below `staging` (relative), `last` at the end; IoError naming `target` when the folder
// cannot be listed or a file vanishes meanwhile (removed while the run wrote it).
std::vector<MovedFile> files_to_move(const std::filesystem::path& staging, const std::filesystem::path& target,
                                     const std::string& last);
// Every file of `moved` is in `target` and is the file moved (its identity): else IoError naming the
// first that is not ("the folder was removed or replaced while this run wrote it").
void check_moved_in(const std::filesystem::path& target, const std::vector<MovedFile>& moved);

}  // namespace brdfbake::io
