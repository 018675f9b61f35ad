// Files that are not regular files, as inputs and as outputs (docs/RELIABILITY.md, "Special files"):
// one policy every option follows, and the bounded, cancellable reads every reader uses.
//
// Inputs. A folder, a missing or an unreadable file is refused naming it. A FIFO or a character
// device (a pipe, `<(...)`, /dev/stdin) is read as a stream where the option reads a document or a
// stream of pairs (jobs, scenes, materials, sidecars, eval's input, a token file), bounded by that
// option's size limit; where a decoder needs a file it can seek and size (images, KTX2, MERL, GLB
// chunks past the limit) it is refused. A block device or a socket is always refused. Every read
// waits for data in polls of at most 100 ms and checks for a stop request (brdfbake/cancel.hpp) in
// between, so that SIGINT or SIGTERM ends a read from a FIFO nobody writes to.
//
// Outputs. A new name or a regular file is written to a temporary beside it and renamed over it.
// A FIFO, a character device, and standard output named as a file (/dev/stdout, /dev/fd/N,
// /proc/self/fd/N) are written in place where the output streams (CSV tables and eval's output:
// the outputs that take "-"), and refused elsewhere: the rename would replace the device node with
// a regular file. A block device or a socket is always refused.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace brdfbake::io {

enum class FileType { Missing, Regular, Folder, Fifo, CharDevice, BlockDevice, Socket, Other };

// A file's identity: (device, inode), the same for every name and link of one file.
struct FileId {
  std::uint64_t dev = 0, ino = 0;
  bool valid = false;
  bool operator==(const FileId& o) const { return valid && o.valid && dev == o.dev && ino == o.ino; }
};

// What `path` names, following symbolic links (Missing when it does not exist or cannot be
// examined). `id` and `size` are filled when given and the file exists.
FileType file_type(const std::string& path, FileId* id = nullptr, std::uint64_t* size = nullptr);
// "a FIFO (named pipe)", "a character device", "a block device", "a socket", "a folder", ...
const char* file_type_text(FileType type);

// Whether an option reads a non-regular file as a stream.
enum class Streams { No, Yes };

// Why `path` cannot be read as an input of that kind (without the path; empty when it can):
// "it is a folder", "no such file", "it is a character device; ... is read from a regular file".
// Never opens the file (a FIFO is not blocked on).
std::string input_problem(const std::string& path, Streams streams);

// Opens `path` for reading without blocking (a FIFO with no writer yet is waited for in the reads,
// where a stop request ends the wait) and checks what it is: throws Error "cannot read <what>
// '<path>': <reason>" for a folder, a missing or unreadable file, and a type the option does not
// take. Returns the descriptor (the caller closes it); *type is the opened file's type.
int open_input(const std::string& path, const std::string& what, Streams streams, FileType* type = nullptr,
               std::uint64_t* size = nullptr);

// Up to `n` bytes from `fd` into `dst`, fewer only at the end of the input; waits in polls of at
// most 100 ms, throwing Cancelled when a stop is requested. `name` is for the IoError of a failed read.
std::size_t read_fd(int fd, char* dst, std::size_t n, const std::string& name);

// The whole input: at most `max_bytes`. A regular file larger than that is refused from its size
// before anything is read; a stream when its max_bytes + 1st byte arrives. The Error reads
// "cannot read <what> '<path>': larger than <limit_text>" (limit_text: e.g. "64 MiB").
std::string read_input(const std::string& path, const std::string& what, std::uint64_t max_bytes,
                       const std::string& limit_text, Streams streams);
// The first `n` bytes (fewer when the file is shorter).
std::string read_input_head(const std::string& path, const std::string& what, std::size_t n, Streams streams);

// The secret on the first line of a token file (a bearer token): the file (a FIFO such as
// `<(pass show x)` is read as a stream) holds at most 4 KiB; trailing white space is removed; a
// line holding a NUL or another control character, or none at all, is refused. Errors read
// "<option>: cannot read '<path>': <reason>" or "<option>: the token ...".
std::string read_token_file(const std::string& path, const std::string& option);

// ---- Outputs ----------------------------------------------------------------------------------------

enum class OutputTarget {
  File,     // a new name, a regular file (or a folder, for the outputs that are folders)
  Stream,   // written in place: a FIFO, a character device, standard output as a file
  Refused,  // a block device, a socket, a name under /dev that does not exist
};
struct OutputTargetInfo {
  OutputTarget target = OutputTarget::File;
  std::string what;  // for Stream and Refused: "a character device", "standard output (/dev/stdout)"
};
OutputTargetInfo output_target(const std::string& path);

// Throws Error (bad input, exit 2) when `path` is a Refused target, or a Stream target and the
// output does not stream. `label` names the option or field ("-o", "tables[0].output").
void check_output_target(const std::string& path, bool streams, const std::string& label);

// Opens a Stream target for writing (a regular file behind /dev/stdout is appended to, as the
// shell's `>>` and `>` leave it). Throws IoError naming the path.
int open_output_stream(const std::string& path);
// Writes all of `bytes` to `fd` (EINTR retried); throws IoError "cannot write '<name>': ...".
void write_fd(int fd, const char* bytes, std::size_t n, const std::string& name);

}  // namespace brdfbake::io
