#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <random>
#include <system_error>

#include "brdfbake/error.hpp"
#include "brdfbake/output_lock.hpp"
#include "io/special_files.hpp"

namespace brdfbake::io {
namespace {

namespace fs = std::filesystem;

std::string os_reason(int error) { return std::error_code(error, std::system_category()).message(); }

// 64 random bits as 16 hex digits. Uniqueness comes from O_EXCL; the randomness only makes a
// collision (and a retry) unlikely.
std::string random_suffix() {
  thread_local std::mt19937_64 generator{[] {
    std::random_device device;
    return (static_cast<uint64_t>(device()) << 32) ^ device();
  }()};
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(generator()));
  return text;
}

}  // namespace

void throw_write_error(const std::string& path, const std::string& reason) {
  throw IoError("cannot write '" + path + "': " + reason);
}

std::string temp_name_prefix(const std::string& target_name, long pid) {
  return "." + target_name + ".tmp-" + std::to_string(pid) + "-";
}

TempFile::TempFile(std::string destination) : destination_(std::move(destination)) {
  const fs::path target(destination_);
  const std::string name = target.filename().string();
  if (name.empty() || name == "." || name == "..") {
    throw_write_error(destination_, "not a file name");
  }
  // A device node, a FIFO or standard output named as a file would be replaced by the rename:
  // refused (bad input) before anything is created (io/special_files.hpp).
  if (const OutputTargetInfo info = output_target(destination_); info.target != OutputTarget::File)
    throw Error(
        "cannot write '" + destination_ + "': it is " + info.what +
        ", and this output is written to a temporary file renamed over its name, which would replace it: "
        "name a regular file" +
        (info.target == OutputTarget::Stream ? " (only CSV tables and eval's output are written to a stream)" : ""));
  ::brdfbake::remove_stale_temporaries(destination_);
  const std::string prefix = (target.parent_path() / temp_name_prefix(name, ::getpid())).string();
  // Retry only on a name collision with another writer's temporary.
  constexpr int kAttempts = 8;
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    std::string candidate = prefix + random_suffix();
    const int fd = ::open(candidate.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      temp_ = std::move(candidate);
      return;
    }
    if (errno != EEXIST) throw_write_error(destination_, os_reason(errno));
  }
  throw_write_error(destination_, "could not create a unique temporary file");
}

TempFile::~TempFile() {
  if (!committed_ && !temp_.empty()) ::unlink(temp_.c_str());
}

void TempFile::commit() {
  std::error_code error;
  fs::rename(temp_, destination_, error);
  if (error) throw_write_error(destination_, error.message());
  committed_ = true;
}

void write_bytes(const TempFile& temp, std::string_view bytes) {
  const std::string& path = temp.destination();
  const int fd = ::open(temp.path().c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
  if (fd < 0) throw_write_error(path, os_reason(errno));
  const char* cursor = bytes.data();
  size_t left = bytes.size();
  while (left > 0) {
    const ssize_t written = ::write(fd, cursor, left);
    if (written < 0) {
      if (errno == EINTR) continue;
      const int error = errno;
      ::close(fd);
      throw_write_error(path, os_reason(error));
    }
    cursor += written;
    left -= static_cast<size_t>(written);
  }
  if (::close(fd) != 0) throw_write_error(path, os_reason(errno));
}

OutputStream::OutputStream(const std::string& path) : path_(path) {
  if (path_ == "-") {
    file_ = stdout;
    return;
  }
  if (output_target(path_).target == OutputTarget::Stream) {  // a FIFO, a device, /dev/stdout: in place
    fd_ = open_output_stream(path_);
    return;
  }
  temp_ = std::make_unique<TempFile>(path_);
  file_ = std::fopen(temp_->path().c_str(), "wb");
  if (!file_) throw_write_error(path_, os_reason(errno));
}

OutputStream::~OutputStream() {
  if (temp_ && file_) std::fclose(file_);
  if (fd_ >= 0) ::close(fd_);
}

void OutputStream::write(const void* data, size_t bytes) {
  if (fd_ >= 0) {
    write_fd(fd_, static_cast<const char*>(data), bytes, path_);
    return;
  }
  if (bytes > 0 && std::fwrite(data, 1, bytes, file_) != bytes)
    throw_write_error(temp_ ? path_ : std::string("standard output"), os_reason(errno));
}

void OutputStream::commit() {
  if (fd_ >= 0) {
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) throw_write_error(path_, os_reason(errno));
    return;
  }
  if (std::fflush(file_) != 0) throw_write_error(temp_ ? path_ : std::string("standard output"), os_reason(errno));
  if (!temp_) return;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!closed) throw_write_error(path_, os_reason(errno));
  temp_->commit();
}

ParentFolders::ParentFolders(const std::string& path) {
  std::error_code ec;
  std::vector<fs::path> missing;
  for (fs::path p = fs::path(path).parent_path(); !p.empty() && !fs::exists(p, ec); p = p.parent_path())
    missing.push_back(p);
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (!fs::create_directory(*it, ec) && ec)
      throw_write_error(path, "cannot create the folder '" + it->string() + "': " + ec.message());
    created_.push_back(it->string());
  }
}

ParentFolders::~ParentFolders() {
  std::error_code ec;
  for (auto it = created_.rbegin(); it != created_.rend(); ++it) fs::remove(*it, ec);  // only if empty
}

void write_file_atomically(const std::string& path, std::string_view bytes) {
  TempFile temp(path);
  write_bytes(temp, bytes);
  temp.commit();
}

void write_file_or_stream(const std::string& path, std::string_view bytes) {
  if (output_target(path).target != OutputTarget::Stream) {
    write_file_atomically(path, bytes);
    return;
  }
  OutputStream out(path);
  out.write(bytes.data(), bytes.size());
  out.commit();
}

}  // namespace brdfbake::io

namespace brdfbake {

namespace fs = std::filesystem;

int remove_stale_temporaries(const std::string& target_in) {
  std::string target = target_in;
  while (target.size() > 1 && target.back() == '/') target.pop_back();
  const fs::path t(target);
  const std::string name = t.filename().string();
  if (name.empty() || name == "." || name == "..") return 0;
  fs::path dir = t.parent_path();
  if (dir.empty()) dir = ".";
  const std::string start = "." + name + ".tmp-";
  std::vector<fs::path> stale;  // collected first: the folder is not changed while it is listed
  std::error_code ec;
  fs::directory_iterator it(dir, ec), end;
  for (; !ec && it != end; it.increment(ec)) {
    const std::string entry = it->path().filename().string();
    if (entry.compare(0, start.size(), start) != 0) continue;
    // ".NAME.tmp-<pid>-<suffix>": the pid, digits up to the next '-'
    const size_t dash = entry.find('-', start.size());
    if (dash == std::string::npos || dash == start.size() || dash - start.size() > 9) continue;
    const std::string digits = entry.substr(start.size(), dash - start.size());
    if (digits.find_first_not_of("0123456789") != std::string::npos) continue;
    const long pid = std::stol(digits);
    if (pid <= 0 || pid == static_cast<long>(::getpid())) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // alive (or not ours to test)
    stale.push_back(it->path());
  }
  int removed = 0;
  for (const fs::path& p : stale) {
    std::error_code rm;
    if (fs::remove_all(p, rm) > 0 && !rm) ++removed;
  }
  return removed;
}

}  // namespace brdfbake
