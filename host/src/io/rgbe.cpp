// Radiance RGBE pictures: see rgbe.hpp for the format and the conventions chosen.
#include "io/rgbe.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>

#include "brdfbake/cancel.hpp"
#include "brdfbake/error.hpp"

namespace brdfbake::io {
namespace {

// New run-length encoding is defined for scanlines of 8 to 0x7fff pixels (shorter ones gain
// nothing, longer ones do not fit the 15-bit length).
constexpr int kMinRleLength = 8;
constexpr int kMaxRleLength = 0x7fff;
// A run byte holds at most 127 repeats (128 + n <= 255), a dump byte at most 128 literals.
constexpr int kMaxRun = 127;
constexpr int kMaxDump = 128;
// Runs shorter than this are cheaper as part of a dump (a run costs 2 bytes).
constexpr int kMinRun = 4;

// 2^(E - 136) for every exponent byte E (0 for E = 0: black).
const std::array<float, 256>& exponent_factors() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int e = 1; e < 256; ++e) t[static_cast<size_t>(e)] = std::ldexp(1.0f, e - 136);
    return t;
  }();
  return table;
}

struct Axis {
  char sign = 0;  // '+' or '-'
  char name = 0;  // 'X' or 'Y'
  int count = 0;
};

// The largest count a resolution line may state: larger ones are refused before any arithmetic
// (a count that does not fit 32 bits must not wrap into a small image).
constexpr long long kMaxAxisCount = 0x7fffffffLL;

// "-Y 512 +X 1024": two axes, each a sign, a letter and a positive count of at most kMaxAxisCount.
// Empty on success, else what is wrong.
std::string parse_resolution(const std::string& line, Axis& first, Axis& second) {
  size_t at = 0;
  auto skip_spaces = [&] {
    while (at < line.size() && (line[at] == ' ' || line[at] == '\t')) ++at;
  };
  auto axis = [&](Axis& a) -> std::string {
    skip_spaces();
    if (at + 2 > line.size()) return "expected a sign and an axis";
    a.sign = line[at];
    a.name = line[at + 1];
    at += 2;
    if ((a.sign != '+' && a.sign != '-') || (a.name != 'X' && a.name != 'Y')) return "expected +X, -X, +Y or -Y";
    skip_spaces();
    const size_t digits = at;
    long long n = 0;
    while (at < line.size() && std::isdigit(static_cast<unsigned char>(line[at]))) {
      n = n * 10 + (line[at] - '0');
      ++at;
      if (n > kMaxAxisCount)
        return "the count " + line.substr(digits, 20) + " is out of range (at most " + std::to_string(kMaxAxisCount) +
               ")";
    }
    if (at == digits) return "expected a count after " + std::string{a.sign, a.name};
    if (n < 1) return "the count of " + std::string{a.sign, a.name} + " must be at least 1";
    a.count = static_cast<int>(n);
    return "";
  };
  if (std::string e = axis(first); !e.empty()) return e;
  if (std::string e = axis(second); !e.empty()) return e;
  skip_spaces();
  if (at != line.size()) return "unexpected text after the second axis";
  if (first.name == second.name) return "both axes are " + std::string(1, first.name);
  return "";
}

// The header's lines, then the pixel data from data() on.
class Reader {
 public:
  explicit Reader(std::string_view bytes) : bytes_(bytes) {}

  // The next line without its '\n'; false at the end of the data.
  bool line(std::string& out) {
    if (pos_ >= bytes_.size()) return false;
    const size_t end = bytes_.find('\n', pos_);
    if (end == std::string_view::npos) return false;
    out.assign(bytes_.substr(pos_, end - pos_));
    if (!out.empty() && out.back() == '\r') out.pop_back();  // a header edited on Windows
    pos_ = end + 1;
    return true;
  }
  const uint8_t* data() const { return reinterpret_cast<const uint8_t*>(bytes_.data() + pos_); }
  const uint8_t* end() const { return reinterpret_cast<const uint8_t*>(bytes_.data() + bytes_.size()); }
  size_t remaining() const { return bytes_.size() - pos_; }
  size_t offset() const { return pos_; }

 private:
  std::string_view bytes_;
  size_t pos_ = 0;
};

[[noreturn]] void truncated(int scanline) {
  throw Error("truncated: the data ends in scanline " + std::to_string(scanline));
}

// Decodes one scanline of `length` pixels from `in` (advanced past it, never beyond `end`) into
// `out` (length x 4 bytes). Returns whether it was new run-length encoded.
bool decode_scanline(const uint8_t*& in, const uint8_t* end, int length, int scanline, uint8_t* out) {
  const size_t n = static_cast<size_t>(length);
  if (length >= kMinRleLength && length <= kMaxRleLength && end - in >= 4 && in[0] == 2 && in[1] == 2 &&
      (in[2] & 0x80) == 0) {
    const int stated = in[2] << 8 | in[3];
    if (stated != length)
      throw Error("corrupt: scanline " + std::to_string(scanline) + " states length " + std::to_string(stated) +
                  ", expected " + std::to_string(length));
    in += 4;
    for (size_t c = 0; c < 4; ++c) {
      size_t i = 0;
      while (i < n) {
        if (in == end) truncated(scanline);
        const uint8_t code = *in++;
        if (code > 128) {
          const size_t run = code - 128u;
          if (in == end) truncated(scanline);
          if (i + run > n) throw Error("corrupt: a run overruns scanline " + std::to_string(scanline));
          const uint8_t value = *in++;
          for (size_t k = 0; k < run; ++k) out[4 * (i + k) + c] = value;
          i += run;
        } else {
          const size_t dump = code;
          if (i + dump > n) throw Error("corrupt: a dump overruns scanline " + std::to_string(scanline));
          if (size_t(end - in) < dump) truncated(scanline);
          for (size_t k = 0; k < dump; ++k) out[4 * (i + k) + c] = in[k];
          in += dump;
          i += dump;
        }
      }
    }
    return true;
  }
  // Flat pixels, with the old repeat pixel (1, 1, 1, count).
  size_t i = 0;
  int shift = 0;
  while (i < n) {
    if (end - in < 4) truncated(scanline);
    const uint8_t* p = in;
    in += 4;
    if (p[0] == 1 && p[1] == 1 && p[2] == 1) {
      if (i == 0) throw Error("corrupt: scanline " + std::to_string(scanline) + " starts with a repeat");
      if (shift > 16) throw Error("corrupt: too many consecutive repeats in scanline " + std::to_string(scanline));
      const size_t count = static_cast<size_t>(p[3]) << shift;
      if (i + count > n) throw Error("corrupt: a repeat overruns scanline " + std::to_string(scanline));
      for (size_t k = 0; k < count; ++k, ++i) std::copy(out + 4 * (i - 1), out + 4 * i, out + 4 * i);
      shift += 8;
    } else {
      std::copy(p, p + 4, out + 4 * i);
      ++i;
      shift = 0;
    }
  }
  return false;
}

void encode_component(const uint8_t* scanline, int length, size_t c, std::string& out) {
  auto at = [&](int i) { return scanline[4 * static_cast<size_t>(i) + c]; };
  int i = 0;
  while (i < length) {
    // The next run of kMinRun or more equal bytes, from j; everything before it is dumped.
    int j = i, run = 0;
    while (j < length) {
      run = 1;
      while (j + run < length && run < kMaxRun && at(j + run) == at(j)) ++run;
      if (run >= kMinRun) break;
      j += run;
    }
    while (i < j) {
      const int dump = std::min(kMaxDump, j - i);
      out.push_back(static_cast<char>(dump));
      for (int k = 0; k < dump; ++k) out.push_back(static_cast<char>(at(i + k)));
      i += dump;
    }
    if (j < length) {
      out.push_back(static_cast<char>(128 + run));
      out.push_back(static_cast<char>(at(j)));
      i = j + run;
    }
  }
}

}  // namespace

void float_to_rgbe(const float rgb[3], uint8_t out[4]) {
  const double largest = std::max({double(rgb[0]), double(rgb[1]), double(rgb[2])});
  if (!(largest >= 1e-32)) {  // also NaN: callers have replaced those
    out[0] = out[1] = out[2] = out[3] = 0;
    return;
  }
  int e = 0;
  std::frexp(largest, &e);  // largest in [2^(e-1), 2^e)
  // channel * 2^(8 - e) is exact (a power of two) and below 256 for every channel <= largest.
  for (size_t c = 0; c < 3; ++c) {
    const double m = std::floor(std::max(0.0, double(rgb[c])) * std::ldexp(1.0, 8 - e));
    out[c] = static_cast<uint8_t>(std::min(255.0, m));
  }
  out[3] = static_cast<uint8_t>(e + 128);
}

void rgbe_to_float(const uint8_t rgbe[4], float out[3]) {
  const float f = exponent_factors()[rgbe[3]];
  for (size_t c = 0; c < 3; ++c) out[c] = static_cast<float>(rgbe[c]) * f;
}

bool is_rgbe(std::string_view bytes) { return bytes.size() >= 2 && bytes[0] == '#' && bytes[1] == '?'; }

std::uint64_t rgbe_file_bound(std::string_view head) {
  Reader in(head);
  std::string line;
  in.line(line);
  for (;;) {
    if (!in.line(line)) return head.size();  // no end of the header in `head`: decode_rgbe says what is wrong
    if (in.offset() > kRgbeMaxHeaderBytes) return head.size();
    if (line.empty()) break;
  }
  Axis first, second;
  if (!in.line(line) || !parse_resolution(line, first, second).empty()) return head.size();
  // Every scanline: a 4-byte run-length header, then each of its 4 components in at worst 2 bytes a
  // value (a dump of one byte); flat pixels take 4 bytes each.
  return in.offset() + uint64_t(first.count) * (4 + 8 * uint64_t(second.count));
}

RgbeImage decode_rgbe(std::string_view bytes, const ImageLimits& limits) {
  if (!is_rgbe(bytes)) throw Error("not a Radiance picture (it does not start with '#?')");
  Reader in(bytes);
  std::string line;
  double exposure = 1.0;
  in.line(line);  // the "#?PROGRAM" line
  for (;;) {
    if (!in.line(line) || in.offset() > kRgbeMaxHeaderBytes)
      throw Error(in.offset() > kRgbeMaxHeaderBytes
                      ? "the header is longer than " + std::to_string(kRgbeMaxHeaderBytes >> 10) + " KiB"
                      : std::string("truncated: the header has no end (an empty line)"));
    if (line.empty()) break;
    if (line.rfind("EXPOSURE=", 0) == 0) {
      // Radiance multiplies: the values were scaled by every EXPOSURE. Kept for the note the
      // reader gives; a value that is not a positive finite number is left out.
      const double e = std::strtod(line.c_str() + 9, nullptr);
      if (std::isfinite(e) && e > 0.0) exposure *= e;
    }
    if (line.rfind("FORMAT=", 0) == 0) {
      std::string format = line.substr(7);
      while (!format.empty() && std::isspace(static_cast<unsigned char>(format.back()))) format.pop_back();
      if (format == "32-bit_rle_xyze")
        throw Error("FORMAT=32-bit_rle_xyze (CIE XYZ) is not supported; convert it to RGBE (ra_xyze -r)");
      if (format != "32-bit_rle_rgbe") throw Error("unknown pixel format FORMAT=" + format);
    }
  }
  if (!in.line(line)) throw Error("truncated: no resolution line after the header");
  Axis first, second;
  if (const std::string why = parse_resolution(line, first, second); !why.empty())
    throw Error("bad resolution line '" + line.substr(0, 40) + "': " + why + " (expected e.g. '-Y 512 +X 1024')");
  const Axis& x_axis = first.name == 'X' ? first : second;
  const Axis& y_axis = first.name == 'Y' ? first : second;
  const std::string problem = image_limits_problem(uint64_t(x_axis.count), uint64_t(y_axis.count), 3, 1, limits);
  if (!problem.empty()) throw Error(problem);
  // Every scanline takes at least one 4-byte record (a flat pixel or a run-length header), whatever
  // its encoding: a 4-line file that promises 16384 x 8192 pixels ends here, before 1.5 GiB exist.
  const uint64_t least = 4 * uint64_t(first.count);
  if (in.remaining() < least)
    throw Error("truncated: the header promises " + std::to_string(x_axis.count) + "x" + std::to_string(y_axis.count) +
                " pixels, at least " + std::to_string(least) + " bytes of scanlines, and " +
                std::to_string(in.remaining()) + " bytes follow it");

  RgbeImage image;
  image.width = x_axis.count;
  image.height = y_axis.count;
  image.orientation = std::string{first.sign, first.name, ' ', second.sign, second.name};
  image.exposure = std::isfinite(exposure) ? exposure : 1.0;
  image.rgb.resize(size_t(image.width) * size_t(image.height) * 3);
  // Where the k-th value along an axis lands: X runs left to right, Y points up (row 0 the top).
  auto place = [](const Axis& a, int k) {
    const bool reversed = (a.name == 'X') == (a.sign == '-');
    return reversed ? a.count - 1 - k : k;
  };
  // Pixel p of a scanline lands at first + p * step (in floats) of the image.
  const ptrdiff_t along = first.name == 'Y' ? 3 : 3 * ptrdiff_t(image.width);  // one step of the second axis
  const ptrdiff_t across = first.name == 'Y' ? 3 * ptrdiff_t(image.width) : 3;
  const bool second_reversed = place(second, 0) != 0;
  const ptrdiff_t step = second_reversed ? -along : along;
  std::vector<uint8_t> scanline(4 * size_t(second.count));
  const uint8_t* data = in.data();
  for (int k = 0; k < first.count; ++k) {
    if (k % 256 == 0) throw_if_cancelled();  // a 16k picture stops within a few milliseconds
    image.run_length_encoded |= decode_scanline(data, in.end(), second.count, k, scanline.data());
    float* out = image.rgb.data() + place(first, k) * across + (second_reversed ? (second.count - 1) * along : 0);
    for (size_t p = 0; p < size_t(second.count); ++p, out += step) rgbe_to_float(&scanline[4 * p], out);
  }
  return image;
}

std::string encode_rgbe(int width, int height, const float* rgb) {
  if (width < 1 || height < 1) throw Error("an RGBE picture needs at least one pixel");
  std::string out =
      "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " + std::to_string(height) + " +X " + std::to_string(width) + "\n";
  const bool rle = width >= kMinRleLength && width <= kMaxRleLength;
  out.reserve(out.size() + 4 * size_t(width) * size_t(height) + (rle ? 4 * size_t(height) : 0));
  std::vector<uint8_t> scanline(4 * size_t(width));
  for (int y = 0; y < height; ++y) {
    for (size_t x = 0; x < size_t(width); ++x) {
      const float* p = rgb + 3 * (size_t(y) * size_t(width) + x);
      for (size_t c = 0; c < 3; ++c)
        if (!(p[c] >= 0.0f && p[c] <= kRgbeMax))
          throw Error("RGBE holds no value " + std::to_string(p[c]) + " (pixel " + std::to_string(x) + ", " +
                      std::to_string(y) + ")");
      float_to_rgbe(p, &scanline[4 * x]);
    }
    if (!rle) {
      out.append(reinterpret_cast<const char*>(scanline.data()), scanline.size());
      continue;
    }
    out.push_back(2);
    out.push_back(2);
    out.push_back(static_cast<char>(width >> 8));
    out.push_back(static_cast<char>(width & 0xff));
    for (size_t c = 0; c < 4; ++c) encode_component(scanline.data(), width, c, out);
  }
  return out;
}

}  // namespace brdfbake::io
