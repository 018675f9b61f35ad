// Atomic file creation: every output is written to a temporary file in the destination's folder
// and renamed over the destination once complete, so a reader sees either the old file or the
// whole new one, and a failed write leaves nothing behind. There is no fsync: this protects
// against failures of the writer (exceptions, full disks, bad paths), not against power loss.
#pragma once

#include <string>
#include <string_view>

namespace brdfbake::io {

// A temporary file beside `destination`, named ".NAME.tmp-<pid>-<random>" (hidden, and in the same
// folder so that the final rename stays within one file system). The constructor creates it empty
// and exclusively; the destructor removes it unless commit() has renamed it over the destination.
class TempFile {
 public:
  // Throws Error("cannot write '<destination>': <OS reason>") when the folder does not take it
  // (missing folder, a path through a regular file, no permission, ...).
  explicit TempFile(std::string destination);
  ~TempFile();
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;

  const std::string& path() const { return temp_; }
  const std::string& destination() const { return destination_; }

  // Renames the temporary over the destination; throws Error naming the destination on failure.
  void commit();

 private:
  std::string destination_;
  std::string temp_;
  bool committed_ = false;
};

// Fills the temporary with `bytes` (errors name the destination). Commit separately.
void write_bytes(const TempFile& temp, std::string_view bytes);

// Writes `bytes` to `path` atomically.
void write_file_atomically(const std::string& path, std::string_view bytes);

// Throws the Error of a failed write: "cannot write '<path>': <reason>".
[[noreturn]] void throw_write_error(const std::string& path, const std::string& reason);

}  // namespace brdfbake::io
