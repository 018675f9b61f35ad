// Checked reads of a bake folder (bake_read.hpp).
#include "engines/bake_read.hpp"

#include <cmath>
#include <filesystem>
#include <sstream>

#include "brdfbake/error.hpp"
#include "io/json_input.hpp"
#include "text.hpp"

namespace brdfbake::detail::bake_read {

namespace {

const char* type_name(const json& v) {
  if (v.is_object()) return "an object";
  if (v.is_array()) return "an array";
  if (v.is_string()) return "a string";
  if (v.is_boolean()) return "a boolean";
  if (v.is_null()) return "null";
  return "a number";
}

std::string range_text(double lo, double hi) { return "[" + fmt_number(lo) + ", " + fmt_number(hi) + "]"; }

}  // namespace

Field::Field(const json& value, std::string file, std::string path)
    : value_(&value), file_(std::move(file)), path_(std::move(path)) {}

std::string Field::where() const { return "'" + file_ + "'" + (path_.empty() ? std::string() : ": " + path_); }

void Field::fail(const std::string& problem) const { throw Error(where() + ": " + problem); }

Field Field::at(const std::string& key) const {
  if (std::optional<Field> f = find(key)) return *f;
  Field(*value_, file_, path_.empty() ? key : path_ + "." + key).fail("missing");
}

std::optional<Field> Field::find(const std::string& key) const {
  if (!value_->is_object()) fail(std::string("expected an object, not ") + type_name(*value_));
  const auto it = value_->find(key);
  if (it == value_->end()) return std::nullopt;
  return Field(*it, file_, path_.empty() ? key : path_ + "." + key);
}

std::vector<Field> Field::elements() const {
  if (!value_->is_array()) fail(std::string("expected an array, not ") + type_name(*value_));
  std::vector<Field> out;
  for (std::size_t i = 0; i < value_->size(); ++i)
    out.emplace_back((*value_)[i], file_, path_ + "[" + std::to_string(i) + "]");
  return out;
}

std::string Field::string() const {
  if (!value_->is_string()) fail(std::string("expected a string, not ") + type_name(*value_));
  return value_->get<std::string>();
}

std::string Field::file_name() const {
  const std::string s = string();
  const std::filesystem::path p(s);
  bool dots = false;
  for (const auto& part : p) dots = dots || part == "..";
  if (s.empty() || p.is_absolute() || dots || s.find('\0') != std::string::npos)
    fail("expected the name of a file inside the bake folder, not " + io::json_excerpt(*value_));
  return s;
}

double Field::number(double lo, double hi) const {
  if (!value_->is_number()) fail(std::string("expected a number, not ") + type_name(*value_));
  const double v = value_->get<double>();
  if (!std::isfinite(v) || v < lo || v > hi) fail(io::json_excerpt(*value_) + " is outside " + range_text(lo, hi));
  return v;
}

int Field::integer(int lo, int hi) const {
  const double v = number(lo, hi);
  if (v != std::floor(v)) fail("expected an integer, not " + io::json_excerpt(*value_));
  return int(v);
}

std::string Field::string_or(const std::string& key, const std::string& fallback) const {
  const std::optional<Field> f = find(key);
  return f ? f->string() : fallback;
}

std::vector<double> sh_numbers(const Field& a, std::size_t count) {
  std::vector<double> out;
  for (const Field& row : a.elements()) {
    if (row.value().is_array()) {
      for (const Field& v : row.elements()) out.push_back(v.number(-kMaxShCoefficient, kMaxShCoefficient));
    } else {
      out.push_back(row.number(-kMaxShCoefficient, kMaxShCoefficient));
    }
  }
  if (out.size() != count)
    a.fail("expected " + std::to_string(count / 3) + " RGB coefficients (" + std::to_string(count) + " numbers), not " +
           std::to_string(out.size()) + " numbers");
  return out;
}

std::vector<double> sh_text_numbers(const std::string& text, std::size_t count, const std::string& what) {
  std::istringstream in(text);
  std::vector<double> out;
  std::string token;
  while (in >> token) {
    char* end = nullptr;
    const double x = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0')
      throw Error(what + ": number " + std::to_string(out.size() + 1) + " is not a number");
    if (!std::isfinite(x) || std::fabs(x) > kMaxShCoefficient)
      throw Error(what + ": number " + std::to_string(out.size() + 1) + " (" + fmt_number(x) + ") is outside " +
                  range_text(-kMaxShCoefficient, kMaxShCoefficient));
    out.push_back(x);
  }
  if (out.size() != count)
    throw Error(what + " holds " + std::to_string(out.size()) + " numbers, expected " + std::to_string(count));
  return out;
}

std::string join_path(const std::string& folder, const std::string& file) {
  return (std::filesystem::path(folder) / file).string();
}

namespace {
bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}
}  // namespace

std::optional<std::string> find_engine_file(const Field& manifest, const std::string& folder, const std::string& tail) {
  if (const std::optional<Field> engine = manifest.find("engine"))
    if (const std::optional<Field> files = engine->find("files"))
      for (const Field& f : files->elements()) {
        const std::string name = f.file_name();
        if (ends_with(name, tail)) return join_path(folder, name);
      }
  return std::nullopt;
}

std::string engine_file(const Field& manifest, const std::string& folder, const std::string& tail) {
  if (std::optional<std::string> f = find_engine_file(manifest, folder, tail)) return *f;
  throw Error("'" + folder + "': the bake has no engine file *" + tail + " (bake with --target)");
}

std::optional<Field> manifest_entry(const Field& manifest, const std::string& kind, const std::string& distribution) {
  const std::optional<Field> files = manifest.find("files");
  if (!files) return std::nullopt;
  for (const Field& f : files->elements()) {
    if (f.at("kind").string() != kind) continue;
    if (kind == "prefilter")
      if (const std::optional<Field> p = f.find("parameters"))
        if (p->find("distribution") && p->at("distribution").string() != distribution) continue;
    if (kind == "irradiance" && !ends_with(f.at("path").file_name(), ".json")) continue;
    return f;
  }
  return std::nullopt;
}

std::string entry_file(const Field& entry, const std::string& folder) {
  return join_path(folder, entry.at("path").file_name());
}

void check_cube(const CubeLevels& cube, const std::string& file) {
  if (cube.levels.empty() || cube.size < 1) throw Error("'" + file + "': no levels");
  for (int l = 0; l < cube.level_count(); ++l) {
    const std::vector<float>& level = cube.levels[std::size_t(l)];
    for (std::size_t i = 0; i < level.size(); ++i)
      if (!std::isfinite(level[i]) || std::fabs(double(level[i])) > kMaxCubeTexel) {
        const std::size_t texel = i / 4, side = std::size_t(cube.level_size(l)) * std::size_t(cube.level_size(l));
        throw Error("'" + file + "': level " + std::to_string(l) + ", face " + std::to_string(texel / side) +
                    ", texel " + std::to_string(texel % side) + ": " + fmt_number(double(level[i])) +
                    " (a texel must be finite, within " + range_text(-kMaxCubeTexel, kMaxCubeTexel) + ")");
      }
  }
}

void check_table(const Table& table, const std::string& file, int channels) {
  if (table.width < 1 || table.height < 1) throw Error("'" + file + "': an empty table");
  if (table.channel_count() < channels)
    throw Error("'" + file + "': " + std::to_string(table.channel_count()) + " channels, the lookup needs " +
                std::to_string(channels));
  const std::size_t per_row = std::size_t(table.width) * std::size_t(table.channel_count());
  for (std::size_t i = 0; i < table.data.size(); ++i)
    if (!std::isfinite(table.data[i]) || std::fabs(double(table.data[i])) > kMaxTableValue) {
      const std::size_t row = i / per_row, col = (i % per_row) / std::size_t(table.channel_count());
      const std::size_t ch = i % std::size_t(table.channel_count());
      throw Error("'" + file + "': texel (" + std::to_string(col) + ", " + std::to_string(row) + ") channel " +
                  table.channels[ch] + ": " + fmt_number(double(table.data[i])) +
                  " (a table value must be finite, within " + range_text(-kMaxTableValue, kMaxTableValue) + ")");
    }
}

}  // namespace brdfbake::detail::bake_read
