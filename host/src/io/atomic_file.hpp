// Atomic file creation: every output is written to a temporary file in the destination's folder
// and renamed over the destination once complete, so a reader sees either the old file or the
// whole new one, and a failed write leaves nothing behind. There is no fsync: this protects
// against failures of the writer (exceptions, full disks, bad paths), not against power loss.
#pragma once

#include <cstdio>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace brdfbake::io {

// A temporary file beside `destination`, named ".NAME.tmp-<pid>-<random>" (hidden, and in the same
// folder so that the final rename stays within one file system). The constructor creates it empty
// and exclusively; the destructor removes it unless commit() has renamed it over the destination.
// The pid in the name is the marker remove_stale_temporaries reads: the constructor first removes
// the temporaries of `destination` left by processes that are gone (a run killed by SIGKILL).
class TempFile {
 public:
  // Throws Error("cannot write '<destination>': <OS reason>") when the folder does not take it
  // (missing folder, a path through a regular file, no permission, ...), and (bad input) when the
  // destination is a device, a FIFO or standard output named as a file: the rename would replace it.
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
// The same for an output that streams (a CSV table): a FIFO, a character device or standard output
// named as a file (/dev/stdout) is written in place (io/special_files.hpp), anything else atomically.
void write_file_or_stream(const std::string& path, std::string_view bytes);

// Creates the folders missing above `path` (a file to be written), and removes them again when
// destroyed unless keep() was called: a failed write leaves no empty folders behind.
class ParentFolders {
 public:
  explicit ParentFolders(const std::string& path);
  ~ParentFolders();
  ParentFolders(const ParentFolders&) = delete;
  ParentFolders& operator=(const ParentFolders&) = delete;
  void keep() { created_.clear(); }

 private:
  std::vector<std::string> created_;  // outermost first
};

// A stream written in pieces: standard output for "-", a FIFO, a character device or standard
// output named as a file (/dev/stdout) written in place, else a temporary beside `path` renamed
// over it by commit() (a failure, or destruction without commit, leaves no file).
class OutputStream {
 public:
  explicit OutputStream(const std::string& path);
  ~OutputStream();
  OutputStream(const OutputStream&) = delete;
  OutputStream& operator=(const OutputStream&) = delete;
  void write(const void* data, size_t bytes);
  void commit();

 private:
  std::string path_;
  std::unique_ptr<TempFile> temp_;
  std::FILE* file_ = nullptr;
  int fd_ = -1;  // a stream target written in place
};

// Throws the IoError of a failed write: "cannot write '<path>': <reason>" (exit code 1).
[[noreturn]] void throw_write_error(const std::string& path, const std::string& reason);

// ".NAME.tmp-<pid>-": the start of the name of every temporary of `target` (TempFile, StagingDir);
// brdfbake::remove_stale_temporaries (brdfbake/output_lock.hpp) reads the pid back.
std::string temp_name_prefix(const std::string& target_name, long pid);

}  // namespace brdfbake::io
