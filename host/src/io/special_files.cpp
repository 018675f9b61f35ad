#include "io/special_files.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "brdfbake/cancel.hpp"
#include "brdfbake/error.hpp"

namespace brdfbake::io {

namespace {

namespace fs = std::filesystem;

// How long one wait for data (or for room to write) lasts before the stop flag is checked again.
constexpr int kPollMilliseconds = 100;
// Read in pieces of this size, checking for a stop request between them: a large file stops within one.
constexpr std::size_t kReadChunk = std::size_t(1) << 20;
// A token file: one line, a secret of a few dozen characters.
constexpr std::uint64_t kMaxTokenFileBytes = 4096;

FileType type_of(mode_t mode) {
  if (S_ISREG(mode)) return FileType::Regular;
  if (S_ISDIR(mode)) return FileType::Folder;
  if (S_ISFIFO(mode)) return FileType::Fifo;
  if (S_ISCHR(mode)) return FileType::CharDevice;
  if (S_ISBLK(mode)) return FileType::BlockDevice;
  if (S_ISSOCK(mode)) return FileType::Socket;
  return FileType::Other;
}

// Why a file of `type` is not an input of that kind ("" when it is).
std::string type_problem(FileType type, Streams streams) {
  switch (type) {
    case FileType::Regular:
    case FileType::Missing:
      return "";
    case FileType::Folder:
      return "it is a folder";
    case FileType::Fifo:
    case FileType::CharDevice:
      if (streams == Streams::Yes) return "";
      return std::string("it is ") + file_type_text(type) +
             ", not a regular file (this input is decoded from a file that can be sized and read again: save the "
             "stream to a file first)";
    default:
      return std::string("it is ") + file_type_text(type) + ", not a regular file";
  }
}

std::string os_text(int error) { return std::strerror(error); }

struct Fd {
  int fd = -1;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

// Whether `path`, or a symbolic link it leads through, names an open file descriptor
// (/dev/stdout -> /proc/self/fd/1, /dev/fd/N, /proc/<pid>/fd/N): standard output as a file.
bool names_a_descriptor(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::absolute(path, ec).lexically_normal();
  if (ec) return false;
  for (int hops = 0; hops < 40; ++hops) {
    const std::string s = p.string();
    if (s.rfind("/dev/fd/", 0) == 0) return true;
    if (s.rfind("/proc/", 0) == 0 && s.find("/fd/", 6) != std::string::npos) return true;
    struct stat st {};
    if (::lstat(s.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return false;
    const fs::path target = fs::read_symlink(p, ec);
    if (ec) return false;
    p = (target.is_absolute() ? target : p.parent_path() / target).lexically_normal();
  }
  return false;
}

}  // namespace

FileType file_type(const std::string& path, FileId* id, std::uint64_t* size) {
  struct stat st {};
  if (path.empty() || ::stat(path.c_str(), &st) != 0) return FileType::Missing;
  if (id) *id = FileId{static_cast<std::uint64_t>(st.st_dev), static_cast<std::uint64_t>(st.st_ino), true};
  if (size) *size = static_cast<std::uint64_t>(st.st_size);
  return type_of(st.st_mode);
}

const char* file_type_text(FileType type) {
  switch (type) {
    case FileType::Missing:
      return "missing";
    case FileType::Regular:
      return "a regular file";
    case FileType::Folder:
      return "a folder";
    case FileType::Fifo:
      return "a FIFO (named pipe)";
    case FileType::CharDevice:
      return "a character device";
    case FileType::BlockDevice:
      return "a block device";
    case FileType::Socket:
      return "a socket";
    case FileType::Other:
      return "not a regular file";
  }
  return "not a regular file";
}

std::string input_problem(const std::string& path, Streams streams) {
  if (path.empty()) return "no file given";
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int e = errno;
    return e == ENOENT || e == ENOTDIR ? "no such file" : os_text(e);
  }
  return type_problem(type_of(st.st_mode), streams);
}

int open_input(const std::string& path, const std::string& what, Streams streams, FileType* type, std::uint64_t* size) {
  if (path.empty()) throw Error("no " + what + " file given");
  const std::string head = "cannot read " + what + " '" + path + "': ";
  // What it is before opening it: a FIFO the option does not take is refused without blocking on it.
  if (const std::string problem = input_problem(path, streams); !problem.empty()) throw Error(head + problem);
  int fd = -1;
  for (;;) {
    // O_NONBLOCK: opening a FIFO does not wait for its writer (the reads do, in polls).
    fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd >= 0 || errno != EINTR) break;
    throw_if_cancelled();
  }
  if (fd < 0) {
    const int e = errno;
    throw Error(head + (e == ENOENT ? std::string("no such file") : os_text(e)));
  }
  // The opened file decides (the name may have changed since): its type again, and its size.
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const int e = errno;
    ::close(fd);
    throw IoError(head + os_text(e));
  }
  const FileType t = type_of(st.st_mode);
  if (const std::string problem = type_problem(t, streams); !problem.empty()) {
    ::close(fd);
    throw Error(head + problem);
  }
  if (type) *type = t;
  if (size) *size = t == FileType::Regular ? static_cast<std::uint64_t>(st.st_size) : 0;
  return fd;
}

std::size_t read_fd(int fd, char* dst, std::size_t n, const std::string& name) {
  std::size_t got = 0;
  while (got < n) {
    // Wait for data first: a FIFO that no writer has opened yet reads as its end (0 bytes) but
    // polls as neither readable nor hung up, so that it is waited for, in steps that check for a stop.
    pollfd p{fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, kPollMilliseconds);
    if (ready < 0 && errno != EINTR) throw IoError("cannot read '" + name + "': " + os_text(errno));
    if (ready <= 0) {
      throw_if_cancelled();
      continue;
    }
    const ssize_t r = ::read(fd, dst + got, n - got);
    if (r > 0) {
      got += static_cast<std::size_t>(r);
      continue;
    }
    if (r == 0) break;  // the end of the input
    const int e = errno;
    if (e == EINTR || e == EAGAIN || e == EWOULDBLOCK) {
      throw_if_cancelled();
      continue;
    }
    throw IoError("cannot read '" + name + "': " + os_text(e));
  }
  return got;
}

std::string read_input(const std::string& path, const std::string& what, std::uint64_t max_bytes,
                       const std::string& limit_text, Streams streams) {
  FileType type = FileType::Missing;
  std::uint64_t size = 0;
  Fd f;
  f.fd = open_input(path, what, streams, &type, &size);
  const std::string too_large = "cannot read " + what + " '" + path + "': larger than " + limit_text;
  if (type == FileType::Regular && size > max_bytes) throw Error(too_large);
  std::string out;
  if (type == FileType::Regular) out.reserve(static_cast<std::size_t>(size));
  for (;;) {
    throw_if_cancelled();
    const std::size_t at = out.size();
    // At most one byte past the limit: enough to know a stream is over it.
    const std::uint64_t room = max_bytes + 1 - at;
    const std::size_t want = static_cast<std::size_t>(std::min<std::uint64_t>(kReadChunk, room));
    out.resize(at + want);
    const std::size_t got = read_fd(f.fd, out.data() + at, want, path);
    out.resize(at + got);
    if (out.size() > max_bytes) throw Error(too_large);
    if (got < want) break;
  }
  return out;
}

std::string read_input_head(const std::string& path, const std::string& what, std::size_t n, Streams streams) {
  FileType type = FileType::Missing;
  std::uint64_t size = 0;
  Fd f;
  f.fd = open_input(path, what, streams, &type, &size);
  // Never more than the file holds: `n` may be a bound far above the file's size.
  if (type == FileType::Regular) n = static_cast<std::size_t>(std::min<std::uint64_t>(n, size));
  std::string out;
  while (out.size() < n) {
    throw_if_cancelled();
    const std::size_t at = out.size(), want = std::min(kReadChunk, n - at);
    out.resize(at + want);
    const std::size_t got = read_fd(f.fd, out.data() + at, want, path);
    out.resize(at + got);
    if (got < want) break;
  }
  return out;
}

std::string read_token_file(const std::string& path, const std::string& option) {
  std::string text;
  try {
    text = read_input(path, "token file", kMaxTokenFileBytes, "4 KiB (a token file holds one line)", Streams::Yes);
  } catch (const Cancelled&) {
    throw;
  } catch (const Error& e) {
    throw Error(option + ": " + e.what());
  }
  std::string token = text.substr(0, text.find('\n'));
  while (!token.empty() && (token.back() == '\r' || token.back() == ' ' || token.back() == '\t')) token.pop_back();
  for (const char c : token)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      throw Error(option + ": the token in '" + path +
                  "' holds a NUL or another control character: a token is one line of printable characters");
  return token;
}

// ---- Outputs ----------------------------------------------------------------------------------------

OutputTargetInfo output_target(const std::string& path) {
  OutputTargetInfo info;
  if (path == "-") {
    info.target = OutputTarget::Stream;
    info.what = "standard output";
    return info;
  }
  const bool descriptor = names_a_descriptor(path);
  const FileType type = file_type(path);
  switch (type) {
    case FileType::Fifo:
    case FileType::CharDevice:
      info.target = OutputTarget::Stream;
      info.what = file_type_text(type);
      return info;
    case FileType::BlockDevice:
    case FileType::Socket:
    case FileType::Other:
      info.target = OutputTarget::Refused;
      info.what = file_type_text(type);
      return info;
    case FileType::Regular:
      if (descriptor) {
        info.target = OutputTarget::Stream;
        info.what = "an open file descriptor (standard output or another stream)";
      }
      return info;
    case FileType::Folder:
      if (descriptor) {
        info.target = OutputTarget::Refused;
        info.what = "an open file descriptor of a folder";
      }
      return info;
    case FileType::Missing:
      break;
  }
  std::error_code ec;
  fs::path parent = fs::absolute(path, ec).lexically_normal().parent_path();
  if (!ec) parent = fs::weakly_canonical(parent, ec);  // /dev through a link is /dev
  if (descriptor) {
    info.target = OutputTarget::Refused;
    info.what = "a file descriptor that is not open";
  } else if (!ec && parent == "/dev") {
    // A new name directly in /dev would be a regular file among the device nodes (as root).
    info.target = OutputTarget::Refused;
    info.what = "a new name in /dev, where only devices live";
  }
  return info;
}

void check_output_target(const std::string& path, bool streams, const std::string& label) {
  const OutputTargetInfo info = output_target(path);
  if (info.target == OutputTarget::File) return;
  const std::string named = label + " '" + path + "'";
  if (info.target == OutputTarget::Refused)
    throw Error(named + ": it is " + info.what + ", not a file brdfbake can write");
  if (!streams)
    throw Error(named + ": it is " + info.what +
                "; this output is written to a temporary file renamed over its name, which would replace it: name a "
                "regular file (only CSV tables and eval's output are written to a stream)");
}

int open_output_stream(const std::string& path) {
  const bool regular = file_type(path) == FileType::Regular;  // behind /dev/stdout: the shell's file
  for (;;) {
    // O_NONBLOCK: a FIFO without a reader fails with ENXIO instead of blocking; wait for one in steps.
    const int fd = ::open(path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC | (regular ? O_APPEND : 0));
    if (fd >= 0) return fd;
    const int e = errno;
    if (e == ENXIO || e == EINTR) {
      throw_if_cancelled();
      ::usleep(kPollMilliseconds * 1000);
      continue;
    }
    throw IoError("cannot write '" + path + "': " + os_text(e));
  }
}

void write_fd(int fd, const char* bytes, std::size_t n, const std::string& name) {
  std::size_t done = 0;
  while (done < n) {
    const ssize_t w = ::write(fd, bytes + done, n - done);
    if (w > 0) {
      done += static_cast<std::size_t>(w);
      continue;
    }
    const int e = w < 0 ? errno : EIO;
    if (e == EINTR || e == EAGAIN || e == EWOULDBLOCK) {
      throw_if_cancelled();
      if (e != EINTR) {
        pollfd p{fd, POLLOUT, 0};
        ::poll(&p, 1, kPollMilliseconds);
        throw_if_cancelled();
      }
      continue;
    }
    throw IoError("cannot write '" + name + "': " + os_text(e));
  }
}

}  // namespace brdfbake::io
