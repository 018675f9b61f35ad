// Outputs shared between runs (docs/RELIABILITY.md, "Outputs").
//
// OutputLock: an advisory lock on an output that several files make up (a job's folder, a cube written as a
// folder of images), so that two runs never write one output at once: the second fails at once
// naming the first (LockedError, exit 1), or waits for it (docs/RELIABILITY.md, "Outputs").
//
// The lock is flock(2) on ".NAME.lock" beside the output (the folder need not exist yet), a file
// holding the holder's pid for the message. flock locks belong to the open file: they end with the
// process however it ends (SIGKILL included), so a lock is never stale. The file is removed on
// release; a waiter that then finds the name taken by a new file starts again on that one.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace brdfbake {

class OutputLock {
 public:
  // Called once while waiting, with the holder's pid (0 when unknown), e.g. to print a note.
  using OnWait = std::function<void(long pid)>;

  // Locks `target` (a path; its parent folders are created when missing, and removed again when
  // the lock is released if they are still empty). Without `wait`, throws LockedError
  // ("'out' is being written by another brdfbake run (pid 1234); ...") when another process holds
  // it; with `wait`, polls until it is free, checking for cancellation (brdfbake/cancel.hpp)
  // between tries. Throws IoError when the lock file cannot be created.
  OutputLock(const std::string& target, bool wait, const OnWait& on_wait = {});
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  const std::string& lock_path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
  std::vector<std::string> created_parents_;
};

// ".NAME.lock" beside `target`.
std::string output_lock_path(const std::string& target);

// Removes the temporaries (files and folders ".NAME.tmp-<pid>-*", as every brdfbake writer names
// them) beside `target` whose process is gone: no process has that pid on this machine. Returns how
// many were removed; never throws. Call it holding the output's lock. A folder shared by several
// machines is not safe for this (a pid is only meaningful on its own host).
int remove_stale_temporaries(const std::string& target);

}  // namespace brdfbake
