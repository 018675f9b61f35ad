// brdfbake eval --model M --material FILE [--name NAME] [-i IN] [-o OUT] [--binary] ...
//
// Streams (wi, wo) pairs through the device in chunks: memory stays constant whatever the input's
// size. CSV in: the header wi_x,wi_y,wi_z,wo_x,wo_y,wo_z, then six numbers a line ('#' lines and
// blank lines are skipped). CSV out: the header r,g,b, then f (without the cosine) a line, in the
// input's order. --binary: raw little-endian float32, 6 a pair in, 3 a pair out.
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "brdfbake/brdf.hpp"
#include "cli_common.hpp"

namespace brdfbake::cli {
namespace {

namespace fs = std::filesystem;

constexpr size_t kChunkPairs = size_t(1) << 16;
constexpr const char* kHeader = "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z";
constexpr const char* kFields[6] = {"wi_x", "wi_y", "wi_z", "wo_x", "wo_y", "wo_z"};

// The output: standard output, or a temporary beside the destination that is renamed over it once
// everything is written (a failed run leaves no file).
class Output {
 public:
  explicit Output(const std::string& path) : path_(path) {
    if (path_.empty() || path_ == "-") {
      file_ = stdout;
      return;
    }
    const fs::path p(path_);
    temp_ = (p.parent_path() / ("." + p.filename().string() + ".tmp-" + std::to_string(::getpid()))).string();
    file_ = std::fopen(temp_.c_str(), "wb");
    if (!file_) throw Error("cannot write '" + path_ + "': " + std::strerror(errno));
  }
  ~Output() {
    if (!temp_.empty() && file_) {
      std::fclose(file_);
      std::remove(temp_.c_str());
    }
  }
  Output(const Output&) = delete;
  Output& operator=(const Output&) = delete;

  void write(const void* data, size_t bytes) {
    if (bytes > 0 && std::fwrite(data, 1, bytes, file_) != bytes)
      throw Error("cannot write '" + (temp_.empty() ? std::string("standard output") : path_) + "': " +
                  std::strerror(errno));
  }
  void commit() {
    if (std::fflush(file_) != 0) throw Error("cannot write '" + path_ + "': " + std::strerror(errno));
    if (temp_.empty()) return;
    const bool ok = std::fclose(file_) == 0;
    file_ = nullptr;
    std::error_code ec;
    if (ok) fs::rename(temp_, path_, ec);
    if (!ok || ec) {
      std::remove(temp_.c_str());
      throw Error("cannot write '" + path_ + "': " + (ec ? ec.message() : std::string("close failed")));
    }
  }

 private:
  std::string path_, temp_;
  FILE* file_ = nullptr;
};

// The input: standard input or a file.
class Input {
 public:
  explicit Input(const std::string& path) : path_(path.empty() || path == "-" ? "standard input" : path) {
    if (path.empty() || path == "-") {
      file_ = stdin;
    } else {
      file_ = std::fopen(path.c_str(), "rb");
      if (!file_) throw Error("cannot read '" + path + "': " + std::strerror(errno));
      owned_ = true;
    }
  }
  ~Input() {
    if (owned_) std::fclose(file_);
  }
  Input(const Input&) = delete;
  Input& operator=(const Input&) = delete;
  FILE* file() const { return file_; }
  const std::string& name() const { return path_; }

  // The next line without its end-of-line; false at the end of the input.
  bool line(std::string& out) {
    out.clear();
    int c;
    bool any = false;
    while ((c = std::fgetc(file_)) != EOF) {
      any = true;
      if (c == '\n') break;
      out.push_back(static_cast<char>(c));
    }
    if (!out.empty() && out.back() == '\r') out.pop_back();
    return any;
  }

 private:
  std::string path_;
  FILE* file_ = nullptr;
  bool owned_ = false;
};

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t");
  if (a == std::string::npos) return {};
  const auto b = s.find_last_not_of(" \t");
  return s.substr(a, b - a + 1);
}

// Parses one CSV data line into 6 numbers; errors name the line and the field.
void parse_pair(const std::string& text, long line, const std::string& origin, double* out) {
  size_t pos = 0;
  for (int f = 0; f < 6; ++f) {
    const size_t comma = text.find(',', pos);
    if (f < 5 && comma == std::string::npos)
      throw Error(origin + ": line " + std::to_string(line) + ": expected 6 fields (" + kHeader + "), got " +
                  std::to_string(f + 1));
    const std::string field = trim(text.substr(pos, f < 5 ? comma - pos : std::string::npos));
    if (f == 5 && field.find(',') != std::string::npos)
      throw Error(origin + ": line " + std::to_string(line) + ": expected 6 fields (" + kHeader + "), got more");
    char* end = nullptr;
    const double v = std::strtod(field.c_str(), &end);
    if (field.empty() || *end != '\0')
      throw Error(origin + ": line " + std::to_string(line) + ": field " + kFields[f] + ": '" + field +
                  "' is not a number");
    if (!std::isfinite(v))
      throw Error(origin + ": line " + std::to_string(line) + ": field " + kFields[f] + " is not finite ('" + field + "')");
    out[f] = v;
    pos = comma + 1;
  }
  for (int d = 0; d < 2; ++d)
    if (out[3 * d] == 0.0 && out[3 * d + 1] == 0.0 && out[3 * d + 2] == 0.0)
      throw Error(origin + ": line " + std::to_string(line) + ": " + (d == 0 ? "wi" : "wo") + " is the zero vector");
}

// Evaluates a chunk, on the device or by the reference. The device is opened and the program built
// with the first chunk, after its lines have been checked.
struct Evaluator {
  std::string device_name;  // "reference": the scalar reference
  EvalOptions options;
  BrdfModel model;
  Material material;
  std::unique_ptr<BrdfEvaluator> device;
  double device_seconds = 0.0;

  void eval(const std::vector<double>& pairs, size_t count, std::vector<double>& out) {
    out.resize(3 * count);
    if (count == 0) return;
    if (!device && device_name != "reference") {
      Device d = Device::open(device_name);
      device = std::make_unique<BrdfEvaluator>(d, model, std::vector<Material>{material}, options);
    }
    if (device) {
      EvalTiming t;
      device->eval(pairs.data(), count, out.data(), &t);
      device_seconds += t.device_seconds;
    } else {
      eval_reference(model, material, pairs.data(), count, out.data());
    }
  }
};

}  // namespace

int cmd_eval(int argc, char** argv) {
  cxxopts::Options options("brdfbake eval", "Evaluate a BRDF at (wi, wo) pairs, streaming");
  options.add_options()
      ("model", "disney | gltf | gltf-correlated | lambert | phong | blinn-phong | cook-torrance | blinn-phong-from-pbr (default: the material's own)", cxxopts::value<std::string>())
      ("material", "material file: our JSON, or a .gltf", cxxopts::value<std::string>())
      ("name", "the material to use when the file holds several", cxxopts::value<std::string>()->default_value(""))
      ("i,input", "pairs: CSV with the header wi_x,wi_y,wi_z,wo_x,wo_y,wo_z, or float32 with --binary (default: standard input)", cxxopts::value<std::string>()->default_value("-"))
      ("o,output", "f as r,g,b rows, or float32 with --binary (default: standard output)", cxxopts::value<std::string>()->default_value("-"))
      ("binary", "raw little-endian float32: 6 a pair in, 3 a pair out")
      ("fast-math", "build the kernels with -cl-fast-relaxed-math");
  add_common_options(options);
  const auto r = parse(options, argc, argv);
  if (help_or_stray(options, r)) return 0;
  if (!r.count("material")) throw UsageError("missing --material FILE");
  std::optional<BrdfModel> chosen;
  if (r.count("model")) chosen = brdf_model_from_name(r["model"].as<std::string>());
  const std::string material_path = r["material"].as<std::string>();
  const auto materials = read_materials(material_path);
  if (!r.count("name") && materials.size() > 1)
    throw UsageError(material_path + " holds " + std::to_string(materials.size()) +
                     " materials; choose one with --name (" + [&] {
                       std::string names;
                       for (const auto& m : materials) names += (names.empty() ? "'" : ", '") + m.name + "'";
                       return names;
                     }() + ")");
  const NamedMaterial& nm = find_material(materials, r["name"].as<std::string>(), material_path);
  const BrdfModel model = resolve_model(chosen, nm);
  EvalOptions eo;
  eo.precision = precision_from_name(r["precision"].as<std::string>());
  eo.fast_math = r.count("fast-math") > 0;
  const bool binary = r.count("binary") > 0;
  const bool quiet = r.count("quiet") > 0;
  const std::string device_name = r["device"].as<std::string>();

  Evaluator ev{device_name, eo, model, nm.params, nullptr, 0.0};

  Input in(r["input"].as<std::string>());
  Output out(r["output"].as<std::string>());
  std::vector<double> pairs, f;
  pairs.reserve(6 * kChunkPairs);
  size_t total = 0;
  if (binary) {
    constexpr size_t kPairBytes = 6 * sizeof(float);
    std::vector<unsigned char> bytes(kPairBytes * kChunkPairs);
    std::vector<float> values, result;
    for (;;) {
      // fread returns short only at the end of the input (or on an error)
      const size_t got = std::fread(bytes.data(), 1, bytes.size(), in.file());
      if (std::ferror(in.file())) throw Error("cannot read '" + in.name() + "': " + std::strerror(errno));
      if (got % kPairBytes != 0)
        throw Error(in.name() + ": the input is not a whole number of pairs (6 float32 = 24 bytes each): " +
                    std::to_string(got % kPairBytes) + " bytes left after pair " + std::to_string(total + got / kPairBytes));
      const size_t count = got / kPairBytes;
      values.resize(6 * count);
      std::memcpy(values.data(), bytes.data(), got);
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
      ev.eval(pairs, count, f);
      result.assign(f.begin(), f.end());
      out.write(result.data(), result.size() * sizeof(float));
      total += count;
      if (got < bytes.size()) break;
    }
  } else {
    std::string text;
    long line = 0;
    bool header = false;
    std::string rows;
    bool header_written = false;
    auto flush = [&] {
      if (!header_written) {  // written with the first rows: a bad first chunk leaves no output
        const char* out_header = "r,g,b\n";
        out.write(out_header, std::strlen(out_header));
        header_written = true;
      }
      const size_t count = pairs.size() / 6;
      ev.eval(pairs, count, f);
      rows.clear();
      char buf[96];
      for (size_t i = 0; i < count; ++i) {
        const int n = std::snprintf(buf, sizeof buf, "%.9g,%.9g,%.9g\n", f[3 * i], f[3 * i + 1], f[3 * i + 2]);
        rows.append(buf, static_cast<size_t>(n));
      }
      out.write(rows.data(), rows.size());
      total += count;
      pairs.clear();
    };
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
      if (pairs.size() == 6 * kChunkPairs) flush();
    }
    if (std::ferror(in.file())) throw Error("cannot read '" + in.name() + "': " + std::strerror(errno));
    if (!header) throw Error(in.name() + ": empty input (expected the header " + std::string(kHeader) + ")");
    flush();
  }
  out.commit();
  if (!quiet)
    std::fprintf(stderr, "%zu pairs, %s, material '%s', %s, %s (device %.3f s)\n", total, brdf_model_name(model),
                 nm.name.c_str(), precision_name(eo.precision), device_name == "reference" ? "reference" : "device",
                 ev.device_seconds);
  return 0;
}

}  // namespace brdfbake::cli
