// Reading tables back from every format write_table writes (io/table_read.hpp). The layouts are
// the writers' (host/src/io/table_io.cpp): texel (i, j) is pixel (i, j), row 0 first; channels in
// order in R, G, B, A; metadata as "brdfbake:KEY" attributes, text chunks or key/value pairs.
#include "io/table_read.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <regex>
#include <sstream>

#include "brdfbake/error.hpp"
#include "io/half.hpp"
#include "io/image_file.hpp"
#include "io/json_input.hpp"
#include "io/ktx2.hpp"
#include "io/png_image.hpp"
#include "text.hpp"

namespace brdfbake::io {

namespace {

namespace fs = std::filesystem;
constexpr const char* kKeyPrefix = "brdfbake:";
constexpr double kHalfPi = 1.5707963267948966;

[[noreturn]] void fail(const std::string& path, const std::string& why) {
  throw Error("cannot read '" + path + "': " + why);
}

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string trim(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

using detail::split;  // text.hpp

bool parse_double(const std::string& text, double* v) {
  const std::string t = trim(text);
  if (t.empty()) return false;
  char* end = nullptr;
  *v = std::strtod(t.c_str(), &end);
  return *end == '\0';
}

// Our keys ("brdfbake:KEY") without the prefix; the channel names from "channels".
void take_metadata(Table& t, const std::vector<std::pair<std::string, std::string>>& entries) {
  for (const auto& [key, value] : entries) {
    if (key.rfind(kKeyPrefix, 0) != 0) continue;
    const std::string k = key.substr(std::strlen(kKeyPrefix));
    if (k == "channels")
      t.channels = split(value, ',');
    else
      t.metadata.emplace_back(k, value);
  }
}

// x and y from the metadata rules, or indices.
void fill_axes(Table& t) {
  auto indices = [](int n) {
    std::vector<double> v(static_cast<size_t>(n));
    for (int k = 0; k < n; ++k) v[size_t(k)] = k;
    return v;
  };
  std::string x_rule = t.meta("x_axis"), y_rule = t.meta("y_axis");
  const std::string axes = t.meta("axes");
  if (!axes.empty()) {  // "column i: NAME = ...; row j: NAME = ..." (tabulate)
    const size_t row = axes.find("row ");
    x_rule = axes.substr(0, row);
    if (row != std::string::npos) y_rule = axes.substr(row);
  }
  if (!axis_from_rule(x_rule, t.width, &t.x_name, &t.x)) {
    t.x_name = "column";
    t.x = indices(t.width);
  }
  if (t.height > 1 || !y_rule.empty()) {
    if (!axis_from_rule(y_rule, t.height, &t.y_name, &t.y)) {
      t.y_name = "row";
      t.y = indices(t.height);
    }
  }
}

// Image pixels (row 0 first, `file_channels` interleaved) into the table's channels.
void take_pixels(Table& t, const std::vector<float>& px, int file_channels, const std::string& path) {
  const size_t nc = t.channels.size();
  if (nc == 0 || static_cast<int>(nc) > file_channels)
    fail(path, std::to_string(nc) + " channels named for " + std::to_string(file_channels) + " in the file");
  const size_t texels = static_cast<size_t>(t.width) * static_cast<size_t>(t.height);
  t.data.resize(texels * nc);
  for (size_t k = 0; k < texels; ++k)
    for (size_t c = 0; c < nc; ++c) t.data[k * nc + c] = px[k * size_t(file_channels) + c];
}

std::vector<std::string> default_channels(int n) {
  static const char* const kNames[] = {"R", "G", "B", "A"};
  std::vector<std::string> out;
  for (int c = 0; c < n && c < 4; ++c) out.push_back(kNames[c]);
  return out;
}

// A table image is read whole (one at most 256 Mpixel).
FloatImage read_whole(const std::string& path) {
  try {
    return read_image(path, ImageLimits{});
  } catch (const Error& e) {
    throw Error("cannot read '" + path + "': " + e.what());
  }
}

Table read_exr_table(const std::string& path) {
  const FloatImage im = read_whole(path);
  Table t;
  t.width = im.width;
  t.height = im.height;
  take_metadata(t, im.attributes);
  if (t.channels.empty()) t.channels = im.channel_names;
  take_pixels(t, im.pixels, im.channels, path);
  fill_axes(t);
  return t;
}

Table read_png_table(const std::string& path) {
  const PngImage im = read_png(path);
  Table t;
  t.width = im.width;
  t.height = im.height;
  take_metadata(t, im.text);
  if (t.channels.empty()) t.channels = default_channels(im.channels);
  std::vector<float> px(im.samples.size());
  const float scale = 1.0f / static_cast<float>(im.max_sample());
  for (size_t k = 0; k < px.size(); ++k) px[k] = static_cast<float>(im.samples[k]) * scale;
  take_pixels(t, px, im.channels, path);
  // A table written with a per-channel range mapping records value = stored * png_scale.
  const std::string s = t.meta("png_scale");
  if (!s.empty()) {
    const std::vector<std::string> parts = split(s, ',');
    const size_t nc = t.channels.size();
    if (parts.size() != nc)
      fail(path, "png_scale has " + std::to_string(parts.size()) + " values for " + std::to_string(nc) + " channels");
    for (size_t c = 0; c < nc; ++c) {
      double k = 0;
      if (!parse_double(parts[c], &k)) fail(path, "png_scale is not a list of numbers");
      for (size_t i = c; i < t.data.size(); i += nc) t.data[i] = static_cast<float>(double(t.data[i]) * k);
    }
  }
  fill_axes(t);
  return t;
}

Table read_hdr_table(const std::string& path) {
  const FloatImage im = read_whole(path);
  Table t;
  t.width = im.width;
  t.height = im.height;
  const std::string sidecar = path + ".json";
  std::error_code ec;
  if (!fs::exists(sidecar, ec)) {
    t.channels = default_channels(3);
    take_pixels(t, im.pixels, 3, path);
    fill_axes(t);
    return t;
  }
  const auto j = parse_json(read_text_file(sidecar, "table sidecar"), sidecar);
  try {
    if (j.at("width").get<int>() != im.width || j.at("height").get<int>() != im.height)
      fail(path, "the image size does not match its sidecar " + sidecar);
    t.channels = j.at("channels").get<std::vector<std::string>>();
    for (const auto& [k, v] : j.at("metadata").items()) t.metadata.emplace_back(k, v.get<std::string>());
    take_pixels(t, im.pixels, 3, path);
    t.x_name = j.at("x").at("name").get<std::string>();
    t.x = j.at("x").at("values").get<std::vector<double>>();
    if (j.contains("y")) {
      t.y_name = j.at("y").at("name").get<std::string>();
      t.y = j.at("y").at("values").get<std::vector<double>>();
    }
  } catch (const nlohmann::json::exception& e) {
    fail(path, "malformed sidecar " + sidecar + ": " + e.what());
  }
  if (t.x.size() != size_t(t.width) || (!t.y_name.empty() && t.y.size() != size_t(t.height)))
    fail(path, "the sidecar's coordinates do not match the image size");
  return t;
}

Table read_ktx2_table(const std::string& path) {
  const Ktx2Image k = read_ktx2(path);
  if (k.faces != 1) fail(path, "a cubemap, not a table");
  uint32_t components = 0, bytes = 0;
  switch (k.vk_format) {
    case 90:
      components = 3;
      bytes = 2;
      break;  // R16G16B16_SFLOAT
    case 97:
      components = 4;
      bytes = 2;
      break;  // R16G16B16A16_SFLOAT
    case 106:
      components = 3;
      bytes = 4;
      break;  // R32G32B32_SFLOAT
    case 109:
      components = 4;
      bytes = 4;
      break;  // R32G32B32A32_SFLOAT
    default:
      fail(path, "vkFormat " + std::to_string(k.vk_format) + " is not an RGB or RGBA float format");
  }
  Table t;
  t.width = static_cast<int>(k.width);
  t.height = static_cast<int>(std::max<uint32_t>(1, k.height));
  take_metadata(t, k.key_values);
  if (t.channels.empty()) t.channels = default_channels(static_cast<int>(components));
  const auto& data = k.level_data.at(0);
  const size_t n = static_cast<size_t>(t.width) * static_cast<size_t>(t.height) * components;
  std::vector<float> px(n);
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* p = data.data() + i * bytes;
    if (bytes == 2) {
      px[i] = half_bits_to_float(static_cast<uint16_t>(p[0] | p[1] << 8));
    } else {
      const uint32_t b = uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
      std::memcpy(&px[i], &b, 4);
    }
  }
  take_pixels(t, px, static_cast<int>(components), path);
  fill_axes(t);
  return t;
}

// CSV: '#' metadata lines ("# key: value"), a header row, one row per cell (x, [y,] channels), rows
// j outer. A file without metadata lines (eval's output) has no coordinate columns: every column
// is a channel and x is the row index ("pair").
Table read_csv_table(const std::string& path) {
  const std::string text = read_text_file(path, "CSV table");
  std::istringstream in(text);
  std::string line;
  Table t;
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    if (header.empty() && line[0] == '#') {
      const std::string body = trim(line.substr(1));
      const size_t colon = body.find(": ");
      if (colon != std::string::npos) t.metadata.emplace_back(body.substr(0, colon), body.substr(colon + 2));
      continue;
    }
    const std::vector<std::string> fields = split(line, ',');
    if (header.empty()) {
      for (const auto& f : fields) {
        std::string h = trim(f);
        if (h.size() >= 2 && h.front() == '"' && h.back() == '"') h = h.substr(1, h.size() - 2);
        header.push_back(h);
      }
      continue;
    }
    if (fields.size() != header.size())
      fail(path, "row " + std::to_string(rows.size() + 1) + " has " + std::to_string(fields.size()) +
                     " fields, the header " + std::to_string(header.size()));
    std::vector<double> r(fields.size());
    for (size_t c = 0; c < fields.size(); ++c)
      if (!parse_double(fields[c], &r[c]))
        fail(path, "row " + std::to_string(rows.size() + 1) + ": '" + fields[c] + "' is not a number");
    rows.push_back(std::move(r));
  }
  if (header.empty() || rows.empty()) fail(path, "no header or no rows");
  if (t.metadata.empty()) {  // eval: values only
    t.channels = header;
    t.width = static_cast<int>(rows.size());
    t.height = 1;
    t.x_name = "pair";
    for (size_t k = 0; k < rows.size(); ++k) {
      t.x.push_back(double(k));
      t.data.insert(t.data.end(), rows[k].begin(), rows[k].end());
    }
    for (auto& v : t.data)
      if (!std::isfinite(v)) v = 0.0f;
    return t;
  }
  // A y column: the metadata names a y axis, or the x column repeats.
  const size_t n = rows.size();
  size_t width = n;
  for (size_t k = 1; k < n; ++k)
    if (rows[k][0] == rows[0][0]) {
      width = k;
      break;
    }
  const std::string axes = t.meta("axes");
  const bool has_y =
      header.size() >= 3 && (!t.meta("y_axis").empty() || axes.find("row ") != std::string::npos || width < n);
  const size_t first_channel = has_y ? 2 : 1;
  if (header.size() <= first_channel) fail(path, "no channel columns");
  if (n % width != 0)
    fail(path, std::to_string(n) + " rows do not make whole rows of " + std::to_string(width) + " cells");
  t.width = static_cast<int>(width);
  t.height = static_cast<int>(n / width);
  t.x_name = header[0];
  if (has_y) t.y_name = header[1];
  t.channels.assign(header.begin() + static_cast<std::ptrdiff_t>(first_channel), header.end());
  for (size_t i = 0; i < width; ++i) t.x.push_back(rows[i][0]);
  if (has_y)
    for (size_t j = 0; j < n / width; ++j) t.y.push_back(rows[j * width][1]);
  for (const auto& r : rows)
    for (size_t c = first_channel; c < r.size(); ++c) t.data.push_back(static_cast<float>(r[c]));
  return t;
}

// The C header: #define SYM_WIDTH / _HEIGHT / _CHANNELS, the comment block (channels, the value
// type, the axes, the metadata), and the array.
Table read_header_table(const std::string& path) {
  const std::string text = read_text_file(path, "C header table");
  Table t;
  bool half = false, in_meta = false;
  std::istringstream in(text);
  std::string line;
  const std::regex define(R"(^#define \w+_(WIDTH|HEIGHT|CHANNELS) (\d+))");
  const std::regex axes(R"(^// column i along x \((.*)\), row j along y(?: \((.*)\))?, row 0 first\.)");
  while (std::getline(in, line)) {
    std::smatch m;
    if (std::regex_search(line, m, define)) {
      const int v = std::atoi(m[2].str().c_str());
      if (m[1] == "WIDTH")
        t.width = v;
      else if (m[1] == "HEIGHT")
        t.height = v;
      continue;
    }
    if (std::regex_search(line, m, axes)) {
      t.x_name = m[1];
      t.y_name = m[2];
      continue;
    }
    if (line.rfind("// Channels: ", 0) == 0) {
      for (const auto& c : split(line.substr(13), ',')) t.channels.push_back(trim(c));
      continue;
    }
    if (line.rfind("// Values: ", 0) == 0) half = line.find("binary16") != std::string::npos;
    if (line == "// Metadata:") {
      in_meta = true;
      continue;
    }
    if (in_meta && line.rfind("//   ", 0) == 0) {
      const std::string body = line.substr(5);
      const size_t colon = body.find(": ");
      if (colon != std::string::npos) t.metadata.emplace_back(body.substr(0, colon), body.substr(colon + 2));
      continue;
    }
    if (line.rfind("//", 0) != 0) in_meta = false;
  }
  const size_t open = text.find('{'), close = text.rfind('}');
  if (t.width <= 0 || t.height <= 0 || t.channels.empty() || open == std::string::npos || close == std::string::npos ||
      close < open)
    fail(path, "not a table header written by brdfbake (no size, channels or array)");
  for (std::string v : split(text.substr(open + 1, close - open - 1), ',')) {
    v = trim(v);
    if (v.empty()) continue;
    if (half) {
      t.data.push_back(half_bits_to_float(static_cast<uint16_t>(std::strtoul(v.c_str(), nullptr, 16))));
    } else {
      if (!v.empty() && (v.back() == 'f' || v.back() == 'F')) v.pop_back();
      double d = 0;
      if (!parse_double(v, &d)) fail(path, "'" + v + "' is not a number");
      t.data.push_back(static_cast<float>(d));
    }
  }
  if (t.data.size() != size_t(t.width) * size_t(t.height) * t.channels.size())
    fail(path, std::to_string(t.data.size()) + " values for " + std::to_string(t.width) + "x" +
                   std::to_string(t.height) + "x" + std::to_string(t.channels.size()));
  const std::string x_name = t.x_name, y_name = t.y_name;
  fill_axes(t);
  if (t.x_name == "column" && !x_name.empty()) t.x_name = x_name;
  if (t.y_name == "row" && !y_name.empty()) t.y_name = y_name;
  return t;
}

}  // namespace

bool axis_from_rule(const std::string& rule, int n, std::string* name, std::vector<double>* values) {
  if (n <= 0) return false;
  std::string r = rule;
  // "column i: NAME = ..." / "row j: NAME = ..."
  static const std::regex prefix(R"(^\s*(column|row) \w+: )");
  r = std::regex_replace(r, prefix, "", std::regex_constants::format_first_only);
  const size_t eq = r.find(" = ");
  if (eq == std::string::npos) return false;
  const std::string nm = trim(r.substr(0, eq));
  if (nm.empty() || nm.find(' ') != std::string::npos) return false;
  const std::string rhs = r.substr(eq + 3);
  // The cell index is one letter (i, j, k, m: whichever the rule uses).
  const std::regex centre(R"(\([a-z] \+ 0\.5\) / \w+( pi/2)?)");
  const std::regex ends(R"([a-z] / \(\w+ - 1\)( pi/2)?)");
  const std::regex lohi(R"(\[lo, hi\] = \[([-+0-9.eE]+), ([-+0-9.eE]+)\])");
  const std::regex minmax(R"(\bmin ([-+0-9.eE]+), max ([-+0-9.eE]+))");
  std::smatch m;
  bool endpoints = false, half_pi = false;
  // The rule starts with the fraction, or with "lo + (hi - lo) FRACTION" / "min + (max - min) FRACTION".
  const bool offset = rhs.rfind("lo + (hi - lo) ", 0) == 0 || rhs.rfind("min + (max - min) ", 0) == 0;
  const std::string fraction = offset ? rhs.substr(rhs.find(") ") + 2) : rhs;
  if (std::regex_search(fraction, m, centre) && m.position(0) == 0) {
    half_pi = m[1].matched;
  } else if (std::regex_search(fraction, m, ends) && m.position(0) == 0) {
    endpoints = true;
    half_pi = m[1].matched;
  } else {
    return false;
  }
  double lo = 0.0, hi = 1.0;
  if (offset) {
    if (!(std::regex_search(rhs, m, lohi) || std::regex_search(rhs, m, minmax))) return false;
    if (!parse_double(m[1], &lo) || !parse_double(m[2], &hi)) return false;
  }
  if (half_pi) hi *= kHalfPi;
  values->resize(static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) {
    const double t = endpoints ? (n > 1 ? double(k) / double(n - 1) : 0.0) : (k + 0.5) / n;
    (*values)[size_t(k)] = lo + (hi - lo) * t;
  }
  *name = nm;
  return true;
}

Table read_table(const std::string& path) {
  const std::string ext = lower(fs::path(path).extension().string());
  if (ext == ".exr") return read_exr_table(path);
  if (ext == ".png") return read_png_table(path);
  if (ext == ".hdr") return read_hdr_table(path);
  if (ext == ".ktx2") return read_ktx2_table(path);
  if (ext == ".csv") return read_csv_table(path);
  if (ext == ".h") return read_header_table(path);
  fail(path, "not a table format (expected .exr .png .hdr .ktx2 .csv .h)");
}

}  // namespace brdfbake::io
