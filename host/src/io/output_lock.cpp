#include "brdfbake/output_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <thread>

#include "brdfbake/cancel.hpp"
#include "brdfbake/error.hpp"
#include "io/special_files.hpp"

namespace brdfbake {

namespace {

namespace fs = std::filesystem;

// The holder's pid as written in the lock file (0 when unknown: not yet written, or unreadable).
long read_pid(int fd) {
  char buf[32] = {0};
  const ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
  if (n <= 0) return 0;
  char* end = nullptr;
  const long pid = std::strtol(buf, &end, 10);
  return pid > 0 ? pid : 0;
}

std::string clean(std::string target) {
  while (target.size() > 1 && target.back() == '/') target.pop_back();
  return target;
}

// The output as the file system knows it: symbolic links of its existing part resolved (the output
// itself too, when it is a link to a folder), so that every name of one folder gives one lock.
fs::path resolved(const std::string& target) {
  std::error_code ec;
  fs::path abs = fs::absolute(target, ec);
  if (ec) return fs::path(target);
  fs::path r = fs::weakly_canonical(abs, ec);
  if (ec) return abs.lexically_normal();
  return r;
}

}  // namespace

std::string output_lock_path(const std::string& target_in) {
  const std::string target = clean(target_in);
  const fs::path t(target);
  if (t.filename().empty() || t.filename() == "." || t.filename() == "..")
    return (t.parent_path() / ("." + t.filename().string() + ".lock")).string();
  const fs::path r = resolved(target);
  return (r.parent_path() / ("." + r.filename().string() + ".lock")).string();
}

OutputLock::OutputLock(const std::string& target_in, bool wait, const OnWait& on_wait) {
  const std::string target = clean(target_in);
  if (fs::path(target).filename().empty() || fs::path(target).filename() == "." || fs::path(target).filename() == "..")
    throw Error("cannot lock '" + target + "': not a file or folder name");
  // A device or a FIFO is not a folder to write into (and its lock file would land beside it, in /dev).
  if (const io::OutputTargetInfo info = io::output_target(target); info.target != io::OutputTarget::File)
    throw Error("cannot write '" + target + "': it is " + info.what + ", not a folder brdfbake can write into");
  // Locked by the folder's identity, not its name: through a symbolic link, another name of the same
  // folder, or a relative path, two runs find the same lock file.
  const fs::path t = resolved(target);
  // The lock file lives in the output's parent folder: create the missing ones (removed again on release).
  std::error_code ec;
  std::vector<fs::path> missing;
  for (fs::path p = t.parent_path(); !p.empty() && !fs::exists(p, ec); p = p.parent_path()) missing.push_back(p);
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (!fs::create_directory(*it, ec) && ec)
      throw IoError("cannot write '" + target + "': cannot create the folder '" + it->string() + "': " + ec.message());
    created_parents_.push_back(it->string());
  }
  path_ = (t.parent_path() / ("." + t.filename().string() + ".lock")).string();
  bool noted = false;
  for (;;) {
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) {
      const int err = errno;
      for (auto it = created_parents_.rbegin(); it != created_parents_.rend(); ++it) fs::remove(*it, ec);
      throw IoError("cannot write '" + target + "': cannot create its lock file '" + path_ +
                    "': " + std::strerror(err));
    }
    if (::flock(fd_, LOCK_EX | LOCK_NB) == 0) {
      // The holder before us may have removed the file after we opened it: then this lock guards
      // nothing, and the name may already belong to a new file. Start again on the current one.
      struct stat held {
      }, named{};
      if (::fstat(fd_, &held) == 0 && ::stat(path_.c_str(), &named) == 0 && held.st_ino == named.st_ino &&
          held.st_dev == named.st_dev) {
        const std::string pid = std::to_string(::getpid()) + "\n";
        if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, pid.data(), pid.size(), 0) < 0) {
          // the pid is only for others' messages: a lock without it still excludes them
        }
        return;
      }
      ::close(fd_);
      fd_ = -1;
      continue;
    }
    const int err = errno;
    const long holder = read_pid(fd_);
    ::close(fd_);
    fd_ = -1;
    if (err != EWOULDBLOCK && err != EINTR) {
      for (auto it = created_parents_.rbegin(); it != created_parents_.rend(); ++it) fs::remove(*it, ec);
      throw IoError("cannot lock '" + target + "' (" + path_ + "): " + std::strerror(err));
    }
    const std::string who =
        holder > 0 ? "another brdfbake run (pid " + std::to_string(holder) + ")" : "another brdfbake run";
    if (!wait) {
      for (auto it = created_parents_.rbegin(); it != created_parents_.rend(); ++it) fs::remove(*it, ec);
      throw LockedError("'" + target + "' is being written by " + who +
                            "; wait for it to finish, pass --wait to queue behind it, or choose another output",
                        holder);
    }
    if (!noted && on_wait) on_wait(holder);
    noted = true;
    try {
      throw_if_cancelled();
    } catch (...) {
      for (auto it = created_parents_.rbegin(); it != created_parents_.rend(); ++it) fs::remove(*it, ec);
      throw;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

OutputLock::~OutputLock() {
  if (fd_ >= 0) {
    // Remove the name while still holding the lock, so that nobody locks this file after us.
    ::unlink(path_.c_str());
    ::close(fd_);
  }
  std::error_code ec;
  for (auto it = created_parents_.rbegin(); it != created_parents_.rend(); ++it) fs::remove(*it, ec);  // only if empty
}

}  // namespace brdfbake
