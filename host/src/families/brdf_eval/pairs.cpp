// The eval family's pairs as streams (pairs.hpp).
//
// Input: CSV with the header wi_x,wi_y,wi_z,wo_x,wo_y,wo_z, then six numbers a line ('#' lines and
// blank lines are skipped), or raw little-endian float32, 6 a pair (binary). Output: CSV with the
// header r,g,b, then f (without the cosine) a line in the input's order, or float32, 3 a pair.
#include "families/brdf_eval/pairs.hpp"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "brdfbake/cancel.hpp"
#include "brdfbake/error.hpp"
#include "io/special_files.hpp"

namespace brdfbake::detail {

namespace {

constexpr const char* kHeader = "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z";
constexpr const char* kFields[6] = {"wi_x", "wi_y", "wi_z", "wo_x", "wo_y", "wo_z"};

}  // namespace

// The input, read through its file descriptor with a buffer of our own. Every wait for data is a
// poll of at most 100 ms that checks for a stop request (brdfbake/cancel.hpp) in between: a stream
// whose writer has not closed it stops on SIGINT or SIGTERM however the signal falls (a flag checked
// before a blocking read() could miss it).
struct PairInput::Impl {
  explicit Impl(const std::string& path) : name_(path == "-" ? "standard input" : path) {
    if (path == "-") {
      fd_ = 0;
      return;
    }
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw Error("cannot read '" + path + "': it is a folder");
    // A FIFO or a device is a stream (its open does not wait for a writer: fill() does, cancellably);
    // a block device or a socket is refused (io/special_files.hpp).
    if (const std::string p = io::input_problem(path, io::Streams::Yes); !p.empty() && p != "no such file")
      throw Error("cannot read '" + path + "': " + p);
    fd_ = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd_ < 0) throw Error("cannot read '" + path + "': " + std::strerror(errno));
    owned_ = true;
  }
  ~Impl() {
    if (owned_) ::close(fd_);
  }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  const std::string& name() const { return name_; }

  // The next line without its end-of-line; false at the end. A line longer than 4096 bytes is
  // refused when its 4097th byte arrives (no pair needs that many): an input without line ends
  // (/dev/zero) is not read forever.
  bool line(std::string& out) {
    out.clear();
    bool any = false;
    ++lines_;
    for (;;) {
      if (at_ == size_ && !fill()) break;
      any = true;
      const char c = buffer_[at_++];
      if (c == '\n') break;
      if (out.size() >= kMaxLineBytes)
        throw Error(name_ + ": line " + std::to_string(lines_) + ": longer than " + std::to_string(kMaxLineBytes) +
                    " bytes (a pair takes six numbers)");
      out.push_back(c);
    }
    if (!out.empty() && out.back() == '\r') out.pop_back();
    return any;
  }

  // Up to `n` bytes into `dst`, fewer only at the end of the input.
  size_t read(unsigned char* dst, size_t n) {
    size_t got = 0;
    while (got < n) {
      if (at_ == size_ && !fill()) break;
      const size_t take = std::min(n - got, size_ - at_);
      std::memcpy(dst + got, buffer_.data() + at_, take);
      at_ += take;
      got += take;
    }
    return got;
  }

  // Refills the buffer; false at the end of the input. Throws Cancelled or IoError.
  bool fill() {
    at_ = size_ = 0;
    for (;;) {
      throw_if_cancelled();
      pollfd p{fd_, POLLIN, 0};
      const int ready = ::poll(&p, 1, 100);
      if (ready < 0 && errno != EINTR) throw IoError("cannot read '" + name_ + "': " + std::strerror(errno));
      if (ready <= 0) continue;  // a timeout or a signal: check for a stop request, wait again
      const ssize_t n = ::read(fd_, buffer_.data(), buffer_.size());
      if (n < 0) {
        if (errno == EINTR || errno == EAGAIN) continue;
        throw IoError("cannot read '" + name_ + "': " + std::strerror(errno));
      }
      size_ = static_cast<size_t>(n);
      return n > 0;
    }
  }

  static constexpr size_t kMaxLineBytes = 4096;
  std::string name_;
  int fd_ = -1;
  bool owned_ = false;
  long lines_ = 0;
  std::vector<char> buffer_ = std::vector<char>(size_t(1) << 16);
  size_t at_ = 0, size_ = 0;
};

PairInput::PairInput(const std::string& path) : impl_(std::make_unique<Impl>(path)) {}
PairInput::~PairInput() = default;
const std::string& PairInput::name() const { return impl_->name(); }

namespace {

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t");
  if (a == std::string::npos) return {};
  const auto b = s.find_last_not_of(" \t");
  return s.substr(a, b - a + 1);
}

// One CSV data line into 6 numbers; errors name the line and the field.
void parse_pair(const std::string& text, long line, const std::string& origin, double* out) {
  const std::string at = origin + ": line " + std::to_string(line) + ": ";
  size_t pos = 0;
  for (int f = 0; f < 6; ++f) {
    const size_t comma = text.find(',', pos);
    if (f < 5 && comma == std::string::npos)
      throw Error(at + "expected 6 fields (" + kHeader + "), got " + std::to_string(f + 1));
    const std::string field = trim(text.substr(pos, f < 5 ? comma - pos : std::string::npos));
    if (f == 5 && field.find(',') != std::string::npos)
      throw Error(at + "expected 6 fields (" + kHeader + "), got more");
    char* end = nullptr;
    const double v = std::strtod(field.c_str(), &end);
    if (field.empty() || end != field.c_str() + field.size())  // the whole field (a NUL byte ends strtod early)
      throw Error(at + "field " + kFields[f] + ": '" + field.substr(0, 40).c_str() + "' is not a number");
    if (!std::isfinite(v)) throw Error(at + "field " + kFields[f] + " is not finite ('" + field.substr(0, 40) + "')");
    out[f] = v;
    pos = comma + 1;
  }
  for (int d = 0; d < 2; ++d)
    if (out[3 * d] == 0.0 && out[3 * d + 1] == 0.0 && out[3 * d + 2] == 0.0)
      throw Error(at + (d == 0 ? "wi" : "wo") + " is the zero vector");
}

// Reads every pair of `in`, evaluates them in chunks and hands each chunk's f (3 a pair) to `sink`.
// Returns the number of pairs.
// The evaluator is made (the program built) with the first chunk, after its lines were checked.
}  // namespace

std::uint64_t stream_pairs(PairInput& input, bool binary, const std::function<PairEvaluator&()>& ev,
                           double* device_seconds, const std::function<void(const double* f, size_t count)>& sink,
                           std::uint64_t max_pairs) {
  PairInput::Impl& in = input.impl();
  std::vector<double> pairs, f;
  // the first chunk holds kChunkPairs, the next ones as many as the evaluator asks for (it is made
  // with the first chunk, after its lines were checked)
  size_t chunk = kChunkPairs;
  pairs.reserve(6 * chunk);
  std::uint64_t total = 0;
  auto evaluate = [&](size_t count) {
    if (total + count > max_pairs)
      throw Error(in.name() + ": more than " + std::to_string(max_pairs) +
                  " pairs: too many to hold in memory (brdfbake eval streams any number)");
    throw_if_cancelled();  // between chunks: a stream of any length stops within one chunk
    f.assign(3 * count, 0.0);
    if (count > 0) {
      EvalTiming t;
      ev().eval(pairs.data(), count, f.data(), &t);
      chunk = std::max<size_t>(1, ev().chunk_pairs());
      *device_seconds += t.device_seconds;
      // No NaN or Inf reaches an output (docs/RELIABILITY.md): the inputs were checked finite and
      // non-zero, so a non-finite f is a failure of the evaluation, refused with its pair.
      for (size_t k = 0; k < 3 * count; ++k)
        if (!std::isfinite(f[k]))
          throw RuntimeFailure(in.name() + ": pair " + std::to_string(total + k / 3) +
                               ": the BRDF value is not finite; the output was not written");
    }
    sink(f.data(), count);
    total += count;
  };
  if (binary) {
    constexpr size_t kPairBytes = 6 * sizeof(float);
    std::vector<unsigned char> bytes;
    std::vector<float> values;
    for (;;) {
      // short only at the end of the input
      bytes.resize(kPairBytes * chunk);
      const size_t got = in.read(bytes.data(), bytes.size());
      if (got % kPairBytes != 0)
        throw Error(in.name() + ": the input is not a whole number of pairs (6 float32 = 24 bytes each): " +
                    std::to_string(got % kPairBytes) + " bytes left after pair " +
                    std::to_string(total + got / kPairBytes));
      const size_t count = got / kPairBytes;
      values.resize(6 * count);
      if (got > 0) std::memcpy(values.data(), bytes.data(), got);
      pairs.assign(values.begin(), values.end());
      for (size_t i = 0; i < count; ++i)
        for (size_t d = 0; d < 2; ++d) {
          const double* v = &pairs[6 * i + 3 * d];
          if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]) ||
              (v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0))
            throw Error(in.name() + ": pair " + std::to_string(total + i) + " (byte " +
                        std::to_string(kPairBytes * (total + i)) + "): " + (d == 0 ? "wi" : "wo") +
                        " is zero or not finite");
        }
      if (count > 0 || total == 0) evaluate(count);
      if (got < bytes.size()) break;
    }
    return total;
  }
  std::string text;
  long line = 0;
  bool header = false;
  while (in.line(text)) {
    ++line;
    const std::string t = trim(text);
    if (t.empty() || t[0] == '#') continue;
    if (!header) {
      if (t != kHeader)
        throw Error(in.name() + ": line " + std::to_string(line) + ": expected the header " + kHeader + " (got '" +
                    t.substr(0, 80) + "')");
      header = true;
      continue;
    }
    double v[6];
    parse_pair(t, line, in.name(), v);
    pairs.insert(pairs.end(), v, v + 6);
    if (pairs.size() >= 6 * chunk) {
      evaluate(pairs.size() / 6);
      pairs.clear();
    }
  }
  if (!header) throw Error(in.name() + ": empty input (expected the header " + std::string(kHeader) + ")");
  evaluate(pairs.size() / 6);
  return total;
}

void format_results(const double* f, size_t count, bool binary, bool first, std::string& out) {
  out.clear();
  if (binary) {
    std::vector<float> v(f, f + 3 * count);
    out.assign(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(float));
    return;
  }
  if (first) out = "r,g,b\n";
  char buf[96];
  for (size_t i = 0; i < count; ++i) {
    const int n = std::snprintf(buf, sizeof buf, "%.9g,%.9g,%.9g\n", f[3 * i], f[3 * i + 1], f[3 * i + 2]);
    out.append(buf, static_cast<size_t>(n));
  }
}

}  // namespace brdfbake::detail
