// Reading what `brdfbake view` shows. One row of kReaders per kind of file: the first row whose
// claim() accepts a path reads it. The container readers are io/ (ktx2, ktx1, dds, table_read,
// image_file, png_image) and read_merl (brdf.hpp); this file only turns their contents into items.
#include "view/load.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "brdfbake/engines.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/error_figures.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/math/equirect.hpp"
#include "engines/babylon_frame.hpp"
#include "io/babylon_env.hpp"
#include "io/dds.hpp"
#include "io/gpu_cube_read.hpp"
#include "io/half.hpp"
#include "io/image_file.hpp"
#include "io/json_input.hpp"
#include "io/ktx1.hpp"
#include "io/ktx2.hpp"
#include "io/png_image.hpp"
#include "io/png_rgbd.hpp"
#include "io/table_read.hpp"
#include "text.hpp"

namespace brdfbake::view {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;
constexpr const char* kKeyPrefix = "brdfbake:";

std::string lower_ext(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  for (auto& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

bool is_dir(const std::string& path) {
  std::error_code ec;
  return fs::is_directory(path, ec);
}

// The RGBD faces an EXT_lights_image_based document in `dir` names (defined with the engine readers).
std::set<std::string> gltf_faces_in(const fs::path& dir);

Metadata our_metadata(const std::vector<std::pair<std::string, std::string>>& kv) {
  Metadata m;
  for (const auto& [k, v] : kv)
    if (k.rfind(kKeyPrefix, 0) == 0) m.emplace_back(k.substr(std::strlen(kKeyPrefix)), v);
  return m;
}

Metadata metadata_object(const json& j) {
  Metadata m;
  if (!j.is_object()) return m;
  for (const auto& [k, v] : j.items()) m.emplace_back(k, v.is_string() ? v.get<std::string>() : v.dump());
  return m;
}

float component(const uint8_t* p, uint32_t bytes) {
  if (bytes == 2) return io::half_bits_to_float(static_cast<uint16_t>(p[0] | p[1] << 8));
  const uint32_t b = uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
  float f;
  std::memcpy(&f, &b, 4);
  return f;
}

// Levels of six faces in KTX order (per level: face, row, texel) -> a float RGBA cube.
CubeLevels cube_from_levels(uint32_t size, const std::vector<std::vector<uint8_t>>& levels, uint32_t components,
                            uint32_t bytes, Metadata metadata, const std::string& path) {
  CubeLevels cube;
  cube.size = static_cast<int>(size);
  cube.metadata = std::move(metadata);
  for (size_t l = 0; l < levels.size(); ++l) {
    const size_t s = static_cast<size_t>(cube.level_size(static_cast<int>(l)));
    const size_t texels = 6 * s * s;
    if (levels[l].size() != texels * components * bytes)
      throw Error("cannot read '" + path + "': level " + std::to_string(l) + " has the wrong size");
    std::vector<float> rgba(4 * texels, 1.0f);
    for (size_t t = 0; t < texels; ++t)
      for (size_t c = 0; c < components && c < 4; ++c)
        rgba[4 * t + c] = component(levels[l].data() + (t * components + c) * bytes, bytes);
    cube.levels.push_back(std::move(rgba));
  }
  return cube;
}

// ---- The readers ---------------------------------------------------------------------------------

// Our E/pi coefficients (3 bands) from an engine's 9 RGB coefficients: the engine's own conversion
// (brdfbake/engines.hpp, linear in our coefficients) probed with unit coefficients into a 9 x 9
// matrix, then solved per channel (Gaussian elimination, partial pivoting). So the sphere view
// draws is what the engine file holds, through the code that wrote it.
ShView sh_from_engine(const std::array<Rgb3, 9>& given, std::array<Rgb3, 9> (*forward)(const ShCoefficients&),
                      const std::string& window, Metadata metadata) {
  double m[9][10];
  for (size_t j = 0; j < 9; ++j) {
    ShCoefficients unit;
    unit.order = 3;
    unit.irradiance_over_pi.assign(27, 0.0);
    unit.radiance.assign(27, 0.0);
    unit.irradiance_over_pi[3 * j] = 1.0;
    const std::array<Rgb3, 9> column = forward(unit);
    for (size_t i = 0; i < 9; ++i) m[i][j] = column[i][0];
  }
  ShView sh;
  sh.order = 3;
  sh.irradiance_over_pi.assign(27, 0.0);
  for (size_t c = 0; c < 3; ++c) {
    double a[9][10];
    for (size_t i = 0; i < 9; ++i) {
      for (size_t j = 0; j < 9; ++j) a[i][j] = m[i][j];
      a[i][9] = given[i][c];
    }
    for (size_t col = 0; col < 9; ++col) {
      size_t pivot = col;
      for (size_t r = col + 1; r < 9; ++r)
        if (std::fabs(a[r][col]) > std::fabs(a[pivot][col])) pivot = r;
      if (!(std::fabs(a[pivot][col]) > 0)) throw Error("an engine's SH conversion is not invertible");
      for (size_t j = 0; j < 10; ++j) std::swap(a[col][j], a[pivot][j]);
      for (size_t r = 0; r < 9; ++r)
        if (r != col) {
          const double f = a[r][col] / a[col][col];
          for (size_t j = col; j < 10; ++j) a[r][j] -= f * a[col][j];
        }
    }
    for (size_t k = 0; k < 9; ++k) sh.irradiance_over_pi[3 * k + c] = a[k][9] / a[k][k];
  }
  sh.window = window;
  sh.metadata = std::move(metadata);
  return sh;
}

// "r g b" numbers, nine triples, from text (Filament's "sh" key: one triple a line; sh.txt:
// "( r, g, b); // L00, ..." lines).
bool nine_triples(const std::string& text, std::array<Rgb3, 9>* out) {
  std::vector<double> v;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    const size_t comment = line.find("//");
    if (comment != std::string::npos) line = line.substr(0, comment);
    for (char& ch : line)
      if (ch == '(' || ch == ')' || ch == ',' || ch == ';') ch = ' ';
    std::istringstream in(line);
    double x = 0;
    while (in >> x) v.push_back(x);
    if (!in.eof()) return false;
  }
  if (v.size() != 27) return false;
  for (size_t k = 0; k < 27; ++k) {
    if (!std::isfinite(v[k])) return false;
    (*out)[k / 3][k % 3] = v[k];
  }
  return true;
}

// A cube container read as a GPU samples it (io/gpu_cube_read.hpp): half, float, Filament's packed
// R11F_G11F_B10F, ASTC HDR.
Item gpu_cube_item(const std::string& path, const std::string& container) {
  std::string format;
  std::vector<std::pair<std::string, std::string>> kv;
  Item it;
  CubeLevels cube = io::read_gpu_cube(path, &format, &kv);
  cube.metadata = our_metadata(kv);
  it.kind = "cube (" + container + ", " + format + ")";
  for (const auto& [k, v] : kv) {
    std::array<Rgb3, 9> sh{};
    if (k == "sh" && nine_triples(v, &sh))  // Filament's irradiance, pre-scaled (docs/ENGINES.md)
      it.irradiance = sh_from_engine(sh, filament_sh, "as written", {{"sh_convention", "Filament (KTX1 sh key)"}});
  }
  it.content = std::move(cube);
  return it;
}

Item read_ktx2_file(const std::string& path) {
  const io::Ktx2Image k = io::read_ktx2(path);
  if (k.faces != 6) {
    Item it;
    it.kind = "table (KTX2)";
    it.content = io::read_table(path);
    return it;
  }
  return gpu_cube_item(path, "KTX2");
}

Item read_ktx1_file(const std::string& path) {
  // A cube (faceCount at byte 52) in any format a GPU samples, Filament's packed one included.
  {
    std::ifstream in(path, std::ios::binary);
    uint8_t head[64] = {};
    if (in.read(reinterpret_cast<char*>(head), 64) && head[52] == 6 && head[53] == 0 && head[54] == 0 && head[55] == 0)
      return gpu_cube_item(path, "KTX1");
  }
  const io::Ktx1Image k = io::read_ktx1(path);
  Item it;
  // A 2-D texture: a table of its channels (level 0).
  Table t;
  t.width = static_cast<int>(k.width);
  t.height = static_cast<int>(k.height);
  t.channels =
      k.components() == 3 ? std::vector<std::string>{"R", "G", "B"} : std::vector<std::string>{"R", "G", "B", "A"};
  t.metadata = our_metadata(k.key_values);
  const size_t texels = size_t(t.width) * size_t(t.height);
  for (size_t i = 0; i < texels * k.components(); ++i)
    t.data.push_back(component(k.level_data[0].data() + i * k.component_bytes(), k.component_bytes()));
  // Our channel names when the file records them (the first channels of each texel).
  std::vector<std::string> names;
  std::string cur;
  for (char c : t.meta("channels") + ",") {
    if (c != ',') {
      cur += c;
    } else if (!cur.empty()) {
      names.push_back(cur);
      cur.clear();
    }
  }
  if (!names.empty() && names.size() <= k.components()) {
    std::vector<float> kept;
    for (size_t i = 0; i < texels; ++i)
      for (size_t c = 0; c < names.size(); ++c) kept.push_back(t.data[i * k.components() + c]);
    t.data = std::move(kept);
    t.channels = names;
  }
  t.x_name = "column";
  t.y_name = "row";
  for (int i = 0; i < t.width; ++i) t.x.push_back(i);
  for (int j = 0; j < t.height; ++j) t.y.push_back(j);
  it.kind = "table (KTX1)";
  it.content = std::move(t);
  return it;
}

Item read_dds_file(const std::string& path) {
  const io::DdsImage d = io::read_dds(path);
  if (d.faces != 6) throw Error("cannot view '" + path + "': a 2-D DDS texture (view shows DDS cubes)");
  Metadata meta;
  std::error_code ec;
  if (fs::exists(path + ".json", ec)) {
    const json j = io::parse_json(io::read_text_file(path + ".json", "DDS sidecar"), path + ".json");
    if (j.is_object() && j.contains("metadata")) meta = metadata_object(j["metadata"]);
  }
  Item it;
  it.kind = std::string("cube (DDS, ") + (d.dx10_header ? "DX10 header" : "legacy header") + ")";
  it.content = cube_from_levels(d.width, d.level_data, 4, d.component_bytes, std::move(meta), path);
  return it;
}

// A folder of per-level images as write_cubemap writes it: STEM.json lists the files and the layout.
bool is_cube_description(const json& j) {
  if (!j.is_object() || !j.contains("layout") || !j.contains("files") || !j["files"].is_array()) return false;
  const std::string layout = j["layout"].is_string() ? j["layout"].get<std::string>() : "";
  return layout == "faces" || layout == "horizontal-cross" || layout == "vertical-cross" || layout == "equirect";
}

// Images a sheet shows are read whole: 256 Mpixel is far beyond any output the tool writes.
constexpr uint64_t kMaxViewPixels = uint64_t(1) << 28;

io::FloatImage read_image(const std::string& path) {
  try {
    return io::read_image(path, io::ImageLimits{kMaxViewPixels, 0});
  } catch (const Error& e) {
    throw Error("cannot read '" + path + "': " + e.what());
  }
}

const float* pixel(const io::FloatImage& im, int x, int y) {
  return &im.pixels[(size_t(y) * size_t(im.width) + size_t(x)) * size_t(im.channels)];
}

CubeLevels cube_from_folder(const std::string& description) {
  const json j = io::parse_json(io::read_text_file(description, "cube description"), description);
  const std::string layout = j["layout"].get<std::string>();
  const std::vector<std::string> files = j["files"].get<std::vector<std::string>>();
  const fs::path dir = fs::path(description).parent_path();
  CubeLevels cube;
  cube.metadata = metadata_object(j.value("metadata", json::object()));
  const size_t per_level = layout == "faces" ? 6 : 1;
  if (files.empty() || files.size() % per_level != 0)
    throw Error("cannot view '" + description + "': " + std::to_string(files.size()) + " files for the " + layout +
                " layout");
  struct Cell {
    int col, row;
    bool rotate;
  };
  static const Cell kHorizontal[6] = {{2, 1, false}, {0, 1, false}, {1, 0, false},
                                      {1, 2, false}, {1, 1, false}, {3, 1, false}};
  static const Cell kVertical[6] = {{2, 1, false}, {0, 1, false}, {1, 0, false},
                                    {1, 2, false}, {1, 1, false}, {1, 3, true}};
  for (size_t l = 0; l < files.size() / per_level; ++l) {
    std::vector<io::FloatImage> images;
    for (size_t k = 0; k < per_level; ++k) images.push_back(read_image((dir / files[l * per_level + k]).string()));
    int s = 0;
    if (layout == "faces")
      s = images[0].width;
    else if (layout == "horizontal-cross")
      s = images[0].width / 4;
    else if (layout == "vertical-cross")
      s = images[0].width / 3;
    else
      s = std::max(1, images[0].width / 4);
    if (l == 0) cube.size = s;
    if (s != cube.level_size(static_cast<int>(l)))
      throw Error("cannot view '" + description + "': level " + std::to_string(l) + " is " + std::to_string(s) +
                  " a side, expected " + std::to_string(cube.level_size(static_cast<int>(l))));
    std::vector<float> rgba(24u * size_t(s) * size_t(s), 1.0f);
    for (int f = 0; f < 6; ++f)
      for (int jj = 0; jj < s; ++jj)
        for (int ii = 0; ii < s; ++ii) {
          float* o = &rgba[4 * ((size_t(f) * size_t(s) + size_t(jj)) * size_t(s) + size_t(ii))];
          const float* p = nullptr;
          float sampled[3];
          if (layout == "faces") {
            p = pixel(images[size_t(f)], ii, jj);
          } else if (layout == "equirect") {
            // The equirect back onto the cube: bilinear at the texel centre's direction.
            const io::FloatImage& im = images[0];
            double u = 0, v = 0;
            math::equirect_coords(math::cube_texel_direction(f, s, ii, jj), u, v);
            const double x = u * im.width - 0.5, y = std::clamp(v * im.height - 0.5, 0.0, double(im.height - 1));
            const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
            const double fx = x - x0, fy = y - y0;
            for (int c = 0; c < 3; ++c) {
              auto at = [&](int xi, int yi) {
                xi = ((xi % im.width) + im.width) % im.width;
                yi = std::clamp(yi, 0, im.height - 1);
                return double(pixel(im, xi, yi)[c]);
              };
              sampled[c] = static_cast<float>((1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) +
                                              fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1)));
            }
            p = sampled;
          } else {
            const Cell c = layout == "horizontal-cross" ? kHorizontal[f] : kVertical[f];
            const int si = c.rotate ? s - 1 - ii : ii, sj = c.rotate ? s - 1 - jj : jj;
            p = pixel(images[0], c.col * s + si, c.row * s + sj);
          }
          std::copy(p, p + 3, o);
        }
    cube.levels.push_back(std::move(rgba));
  }
  return cube;
}

// The description file of a cube folder, or "".
std::string cube_folder_description(const std::string& dir) {
  std::error_code ec;
  std::vector<std::string> candidates;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.is_regular_file(ec) && lower_ext(e.path().string()) == ".json") candidates.push_back(e.path().string());
  std::sort(candidates.begin(), candidates.end());
  for (const auto& c : candidates) {
    try {
      if (is_cube_description(io::parse_json(io::read_text_file(c, "JSON"), c))) return c;
    } catch (const Error&) {
    }
  }
  return "";
}

Item read_sh(const json& j, const std::string& path) {
  ShView sh;
  try {
    sh.order = j.at("order").get<int>();
    for (const auto& t : j.at("irradiance_over_pi"))
      for (const auto& v : t) sh.irradiance_over_pi.push_back(v.get<double>());
    if (j.contains("radiance"))
      for (const auto& t : j["radiance"])
        for (const auto& v : t) sh.radiance.push_back(v.get<double>());
    sh.window = j.value("window", "");
    sh.metadata = metadata_object(j.value("metadata", json::object()));
  } catch (const json::exception& e) {
    throw Error("cannot view '" + path + "': malformed SH coefficients (" + e.what() + ")");
  }
  if (sh.order < 1 || sh.order > 8 || sh.irradiance_over_pi.size() != 3u * size_t(sh.order) * size_t(sh.order))
    throw Error("cannot view '" + path + "': " + std::to_string(sh.irradiance_over_pi.size() / 3) +
                " coefficients for order " + std::to_string(sh.order));
  if (!sh.radiance.empty() && sh.radiance.size() != sh.irradiance_over_pi.size()) sh.radiance.clear();
  Item it;
  it.kind = "SH coefficients (JSON)";
  it.content = std::move(sh);
  return it;
}

Item read_manifest(const json& j, const std::string& path) {
  FileList list;
  const fs::path dir = fs::path(path).parent_path();
  for (const auto& f : j["files"]) {
    if (!f.is_object() || !f.contains("path") || !f["path"].is_string())
      throw Error("cannot view '" + path + "': a file entry without a path");
    list.paths.push_back((dir / f["path"].get<std::string>()).string());
    Metadata notes;
    // the error figure under its kind's name (error_name; error_bound in an older manifest)
    const std::string figure = f.contains("error_name") && f["error_name"].is_string()
                                   ? f["error_name"].get<std::string>()
                                   : std::string(kLegacyErrorBoundName);
    for (const std::string& key :
         {std::string("kind"), figure, std::string("runtime"), std::string("channels"), std::string("device")})
      if (f.contains(key) && !f[key].is_null())
        notes.emplace_back(key, f[key].is_string() ? f[key].get<std::string>() : f[key].dump());
    list.notes.push_back(std::move(notes));
  }
  if (j.contains("preview") && j["preview"].is_object() && j["preview"].contains("files")) {
    for (const auto& f : j["preview"]["files"])  // the preview's JSON stands for its files
      if (f.is_string() && lower_ext(f.get<std::string>()) == ".json") {
        list.paths.push_back((dir / f.get<std::string>()).string());
        list.notes.emplace_back();
      }
  }
  // An engine target's file set (docs/ENGINES.md), as written beside the tables: each file, the
  // RGBD faces of an EXT_lights_image_based document drawn as its chain.
  if (j.contains("engine") && j["engine"].is_object() && j["engine"].contains("files") &&
      j["engine"]["files"].is_array()) {
    const std::set<std::string> faces = gltf_faces_in(dir);
    const std::string target = j["engine"].value("target", "");
    for (const auto& f : j["engine"]["files"]) {
      if (!f.is_string()) continue;
      const std::string p = (dir / f.get<std::string>()).string();
      if (faces.count(fs::path(p).lexically_normal().string())) continue;
      list.paths.push_back(p);
      list.notes.push_back({{"kind", "engine file (" + target + ")"}});
    }
  }
  Item it;
  it.kind = "manifest";
  it.content = std::move(list);
  return it;
}

bool is_preview_json(const json& j) {
  return j.is_object() && j.value("kind", std::string()) == "preview" && j.contains("spheres") && j.contains("files") &&
         j["files"].is_object() && j["files"].contains("sheet");
}

// A preview (brdfbake preview, bake --preview): its contact sheet as drawn, named in its JSON, with
// the JSON's numbers in the caption.
Item read_preview(const json& j, const std::string& path) {
  const fs::path sheet = fs::path(path).parent_path() / j["files"]["sheet"].get<std::string>();
  const io::PngImage png = io::read_png(sheet.string());
  if (png.bit_depth != 8 || png.channels < 3)
    throw Error("cannot view '" + sheet.string() + "': not the 8-bit RGB sheet a preview writes");
  Picture pic;
  pic.width = png.width;
  pic.height = png.height;
  pic.rgb.reserve(size_t(png.width) * size_t(png.height) * 3);
  for (int y = 0; y < png.height; ++y)
    for (int x = 0; x < png.width; ++x)
      for (int c = 0; c < 3; ++c) pic.rgb.push_back(static_cast<uint8_t>(png.at(x, y, c)));
  std::vector<double> rms;
  double bound = 0.0;
  for (const auto& s : j["spheres"]) {
    if (s.contains("error")) rms.push_back(s["error"]["linear"]["rms"].get<double>());
    if (s.contains("reference_bound")) bound = std::max(bound, s["reference_bound"]["rms"].get<double>());
  }
  std::sort(rms.begin(), rms.end());
  char b[256];
  std::snprintf(b, sizeof b, "target %s, %zu spheres", j.value("target", std::string("?")).c_str(),
                j["spheres"].size());
  pic.caption = b;
  if (!rms.empty())
    pic.caption += ", split-sum vs reference RMS " + detail::percent_text(rms[rms.size() / 2]) + " median, " +
                   detail::percent_text(rms.back()) + " worst sphere; reference within " + detail::percent_text(bound);
  Item it;
  it.kind = "preview";
  it.content = std::move(pic);
  return it;
}

// A JSON file: a preview's, a manifest, SH coefficients, a cube folder's description, or the sidecar of a file
// that view reads through its main file (.hdr table, .dds, MERL .binary).
Item read_json_file(const std::string& path) {
  const json j = io::parse_json(io::read_text_file(path, "JSON file"), path);
  if (is_preview_json(j)) return read_preview(j, path);
  if (j.is_object() && j.contains("files") && j["files"].is_array() && !j["files"].empty() && j["files"][0].is_object())
    return read_manifest(j, path);
  if (j.is_object() && j.contains("order") && j.contains("irradiance_over_pi")) return read_sh(j, path);
  if (is_cube_description(j)) {
    Item it;
    it.kind = "cube (folder of " + j["layout"].get<std::string>() + " images)";
    it.content = cube_from_folder(path);
    return it;
  }
  if (j.is_object() && j.contains("layout") && j["layout"].is_string() &&
      j["layout"].get<std::string>().rfind("dds", 0) == 0 && j.contains("files") && j["files"].is_array() &&
      !j["files"].empty())
    return read_dds_file((fs::path(path).parent_path() / j["files"][0].get<std::string>()).string());
  const std::string main = path.size() > 5 ? path.substr(0, path.size() - 5) : "";
  std::error_code ec;
  if (!main.empty() && fs::exists(main, ec) && j.is_object() && (j.contains("image") || j.contains("format")))
    return load(main);
  throw Error("cannot view '" + path +
              "': not a JSON file brdfbake writes (a manifest, SH coefficients, a cube folder's "
              "description or a sidecar)");
}

// ---- Engine files (docs/ENGINES.md) ----------------------------------------------------------------

// Babylon.js's .env: its RGBD PNG faces decoded as Babylon.js does, and its irradiance polynomial.
Item read_babylon_env_file(const std::string& path) {
  const io::BabylonEnv env = io::decode_babylon_env(io::read_binary_file(path, "Babylon .env file"));
  std::vector<std::vector<std::vector<uint8_t>>> levels;
  for (size_t k = 0; k < env.images.size(); ++k) {
    if (k % 6 == 0) levels.emplace_back();
    levels.back().push_back(env.images[k]);
  }
  Item it;
  it.kind = "cube (Babylon.js .env, RGBD PNG faces)";
  // in the environment's frame, as Babylon.js's left-handed world sees it (engines/babylon_frame.hpp)
  CubeLevels cube = detail::mirror_cube_x(io::decode_rgbd_cube(levels, env.width, "cannot view '" + path + "'"));
  if (env.extra.contains("brdfbake")) cube.metadata = metadata_object(env.extra["brdfbake"]);
  it.irradiance = sh_from_engine(detail::mirror_babylon_polynomial_x(env.polynomial), babylon_polynomial, "as written",
                                 {{"sh_convention", "Babylon.js spherical polynomial (.env irradiance)"}});
  it.content = std::move(cube);
  return it;
}

// The EXT_lights_image_based light of a glTF document: {face PNG paths per level, face size,
// coefficients}, or nothing when the document has none.
struct GltfLight {
  std::vector<std::vector<std::string>> faces;
  int size = 0;
  std::array<Rgb3, 9> coefficients{};
  std::array<double, 4> rotation = {0.0, 0.0, 0.0, 1.0};
  Metadata metadata;
};

std::optional<GltfLight> gltf_light(const std::string& path) {
  const json j = io::parse_json(io::read_text_file(path, "glTF document"), path);
  const json* light = nullptr;
  if (j.is_object() && j.contains("extensions") && j["extensions"].is_object() &&
      j["extensions"].contains("EXT_lights_image_based")) {
    const json& ext = j["extensions"]["EXT_lights_image_based"];
    if (ext.is_object() && ext.contains("lights") && ext["lights"].is_array() && !ext["lights"].empty())
      light = &ext["lights"][0];
  }
  if (!light) return std::nullopt;
  GltfLight out;
  try {
    const fs::path dir = fs::path(path).parent_path();
    out.size = light->at("specularImageSize").get<int>();
    for (const json& level : light->at("specularImages")) {
      out.faces.emplace_back();
      for (const json& index : level)
        out.faces.back().push_back(
            (dir / j.at("images").at(index.get<size_t>()).at("uri").get<std::string>()).string());
    }
    const json& c = light->at("irradianceCoefficients");
    if (c.size() != 9) throw Error("irradianceCoefficients does not hold 9 triples");
    for (size_t k = 0; k < 9; ++k)
      for (size_t ch = 0; ch < 3; ++ch) out.coefficients[k][ch] = c.at(k).at(ch).get<double>();
    if (j.contains("asset") && j["asset"].contains("extras") && j["asset"]["extras"].contains("brdfbake"))
      out.metadata = metadata_object(j["asset"]["extras"]["brdfbake"]);
    if (light->contains("rotation")) out.rotation = light->at("rotation").get<std::array<double, 4>>();
  } catch (const json::exception& e) {
    throw Error("cannot view '" + path + "': a malformed EXT_lights_image_based light (" + e.what() + ")");
  }
  return out;
}

// A glTF document with an EXT_lights_image_based light: its specular chain from the RGBD PNGs it
// names, and its irradiance coefficients.
Item read_gltf_file(const std::string& path) {
  const std::optional<GltfLight> light = gltf_light(path);
  if (!light)
    throw Error("cannot view '" + path +
                "': a glTF document without an EXT_lights_image_based light (view shows the lights brdfbake "
                "writes, not scenes)");
  std::vector<std::vector<std::vector<uint8_t>>> levels;
  for (const auto& faces : light->faces) {
    levels.emplace_back();
    for (const std::string& f : faces) levels.back().push_back(io::read_binary_file(f, "RGBD face"));
  }
  Item it;
  it.kind = "cube (glTF EXT_lights_image_based, RGBD PNG faces)";
  CubeLevels cube = io::decode_rgbd_cube(levels, light->size, "cannot view '" + path + "'");
  // in the glTF frame, as the Babylon.js scene its rotation is for samples it
  std::array<Rgb3, 9> coefficients = light->coefficients;
  detail::gltf_scene_of_rotation(light->rotation, "cannot view '" + path + "'");  // only the rotations emulated
  detail::gltf_light_to_scene_frame(cube, coefficients);
  cube.metadata = light->metadata;
  it.irradiance = sh_from_engine(coefficients, gltf_irradiance_coefficients, "as written",
                                 {{"sh_convention", "EXT_lights_image_based irradianceCoefficients"}});
  it.content = std::move(cube);
  return it;
}

// Filament's sh.txt (cmgen's layout): nine "(r, g, b); // Lnn" lines of pre-scaled coefficients.
Item read_sh_txt_file(const std::string& path) {
  std::array<Rgb3, 9> sh{};
  if (!nine_triples(io::read_text_file(path, "text file"), &sh))
    throw Error("cannot view '" + path + "': not nine lines of r, g, b coefficients (Filament's sh.txt)");
  Item it;
  it.kind = "SH coefficients (Filament sh.txt)";
  it.content = sh_from_engine(sh, filament_sh, "as written", {{"sh_convention", "Filament, pre-scaled (sh.txt)"}});
  return it;
}

// The PNGs an EXT_lights_image_based document in `dir` names (its RGBD faces), by full path.
std::set<std::string> gltf_faces_in(const fs::path& dir) {
  std::set<std::string> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (!e.is_regular_file(ec) || lower_ext(e.path().string()) != ".gltf") continue;
    try {
      if (const std::optional<GltfLight> light = gltf_light(e.path().string()))
        for (const auto& level : light->faces)
          for (const auto& f : level) out.insert(fs::path(f).lexically_normal().string());
    } catch (const Error&) {
    }
  }
  return out;
}

// An 8-bit PNG that is not a brdfbake table: an RGBD face of an EXT_lights_image_based document
// beside it (decoded to radiance as the extension's loader does), else a picture (a contact sheet),
// shown as stored.
std::optional<Item> read_png_picture(const std::string& path) {
  const io::PngImage im = io::read_png(path);
  if (im.bit_depth != 8) return std::nullopt;
  for (const auto& [k, v] : im.text)
    if (k.rfind(kKeyPrefix, 0) == 0 && k != "brdfbake:files") return std::nullopt;  // a table
  HdrImage h;
  h.width = im.width;
  h.height = im.height;
  const size_t n = size_t(im.width) * size_t(im.height), nc = size_t(im.channels);
  Item it;
  const std::string key = fs::path(path).lexically_normal().string();
  if (nc == 4 && gltf_faces_in(fs::path(path).parent_path()).count(key)) {
    for (size_t t = 0; t < n; ++t) {
      uint8_t px[4];
      for (size_t c = 0; c < 4; ++c) px[c] = static_cast<uint8_t>(im.samples[4 * t + c]);
      double rgb[3];
      io::rgbd_decode(px, rgb);
      for (double v : rgb) h.rgb.push_back(static_cast<float>(v));
    }
    it.kind = "RGBD face (EXT_lights_image_based)";
  } else {
    for (size_t t = 0; t < n; ++t)
      for (size_t c = 0; c < 3; ++c) h.rgb.push_back(float(im.samples[t * nc + (nc >= 3 ? c : 0)]) / 255.0f);
    h.display_referred = true;
    it.kind = "picture (8-bit PNG)";
  }
  it.content = std::move(h);
  return it;
}

Item read_table_file(const std::string& path) {
  Item it;
  const std::string ext = lower_ext(path);
  const char* container = ext == ".exr"   ? "OpenEXR"
                          : ext == ".png" ? "PNG"
                          : ext == ".hdr" ? "RGBE"
                          : ext == ".csv" ? "CSV"
                                          : "C header";
  // An RGB(E) image with no table description is an environment (or any HDR picture).
  std::error_code ec;
  if (ext == ".hdr" && !fs::exists(path + ".json", ec)) {
    const io::FloatImage im = read_image(path);
    HdrImage h{im.width, im.height, im.pixels, {}};
    it.kind = "HDR image (RGBE)";
    it.content = std::move(h);
    return it;
  }
  if (ext == ".png") {  // a preview's sheet: through its NAME.json
    const std::string sibling = path.substr(0, path.size() - 4) + ".json";
    if (fs::is_regular_file(sibling, ec)) {
      const json j = io::parse_json(io::read_text_file(sibling, "JSON file"), sibling);
      if (is_preview_json(j)) return read_preview(j, sibling);
    }
  }
  if (ext == ".exr") {
    io::FloatImage im = read_image(path);
    const bool table = std::any_of(im.attributes.begin(), im.attributes.end(),
                                   [](const auto& a) { return a.first == std::string(kKeyPrefix) + "channels"; });
    if (!table) {
      if (im.channels < 3)
        throw Error("cannot view '" + path + "': an OpenEXR image of " + std::to_string(im.channels) +
                    " channels without a table description");
      HdrImage h;
      h.width = im.width;
      h.height = im.height;
      h.metadata = our_metadata(im.attributes);
      for (size_t t = 0; t < size_t(im.width) * size_t(im.height); ++t)
        for (size_t c = 0; c < 3; ++c) h.rgb.push_back(im.pixels[t * size_t(im.channels) + c]);
      it.kind = "HDR image (OpenEXR)";
      it.content = std::move(h);
      return it;
    }
  }
  if (ext == ".png")
    if (std::optional<Item> picture = read_png_picture(path)) return std::move(*picture);
  Table t = io::read_table(path);
  it.kind = ext == ".csv" && t.x_name == "pair" && t.meta("kind").empty() ? "BRDF values (eval CSV)"
                                                                          : std::string("table (") + container + ")";
  it.content = std::move(t);
  return it;
}

Item read_eval_binary(const std::string& path) {
  const std::vector<uint8_t> bytes = io::read_binary_file(path, "float32 file");
  if (bytes.empty() || bytes.size() % 12 != 0)
    throw Error("cannot view '" + path + "': " + std::to_string(bytes.size()) +
                " bytes is not a whole number of float32 r, g, b triples");
  Table t;
  t.channels = {"r", "g", "b"};
  t.width = static_cast<int>(bytes.size() / 12);
  t.height = 1;
  t.x_name = "pair";
  t.data.resize(bytes.size() / 4);
  for (size_t k = 0; k < t.data.size(); ++k) {
    t.data[k] = component(bytes.data() + 4 * k, 4);
    if (!std::isfinite(t.data[k])) t.data[k] = 0.0f;
  }
  for (int i = 0; i < t.width; ++i) t.x.push_back(i);
  Item it;
  it.kind = "BRDF values (eval float32)";
  it.content = std::move(t);
  return it;
}

Item read_merl_file(const std::string& path) {
  Item it;
  it.kind = "MERL table";
  it.content = read_merl(path);
  return it;
}

// Folders inside folders are shown too, this deep at most (a bake's folder inside a project).
constexpr int kMaxFolderDepth = 4;

FileList list_folder(const std::string& path, int depth) {
  FileList list;
  std::error_code ec;
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(path, ec)) {
    // Hidden entries are the tool's own temporaries, locks and staging folders.
    if (e.path().filename().string().rfind('.', 0) == 0) continue;
    names.push_back(e.path().string());
  }
  std::sort(names.begin(), names.end());
  const std::set<std::string> all(names.begin(), names.end());
  const std::set<std::string> faces = gltf_faces_in(path);
  for (const auto& n : names) {
    if (is_dir(n)) {
      const bool shown = fs::exists(fs::path(n) / "manifest.json", ec) || !cube_folder_description(n).empty();
      if (shown) {
        list.paths.push_back(n);
        list.notes.emplace_back();
        continue;
      }
      if (depth + 1 > kMaxFolderDepth) {
        list.skipped.push_back(n + " (a folder nested more than " + std::to_string(kMaxFolderDepth) + " deep)");
        continue;
      }
      FileList inner = list_folder(n, depth + 1);
      for (size_t k = 0; k < inner.paths.size(); ++k) {
        list.paths.push_back(inner.paths[k]);
        list.notes.push_back(inner.notes[k]);
      }
      for (auto& w : inner.skipped) list.skipped.push_back(std::move(w));
      continue;
    }
    if (lower_ext(n) == ".json" && all.count(n.substr(0, n.size() - 5))) continue;  // a sidecar
    if (faces.count(fs::path(n).lexically_normal().string())) continue;             // drawn by its .gltf
    try {
      kind_of(n);
    } catch (const Error&) {
      list.skipped.push_back(n + " (not a kind of file view shows)");
      continue;
    }
    list.paths.push_back(n);
    list.notes.emplace_back();
  }
  return list;
}

Item read_folder(const std::string& path) {
  Item it;
  std::error_code ec;
  if (fs::exists(fs::path(path) / "manifest.json", ec)) {
    it = read_json_file((fs::path(path) / "manifest.json").string());
    return it;
  }
  const std::string description = cube_folder_description(path);
  if (!description.empty()) return read_json_file(description);
  // Any other folder: the files in it that some reader claims (sidecars aside), in name order, and
  // those of the folders inside it; what no reader claims is listed as skipped.
  FileList list = list_folder(path, 0);
  if (list.paths.empty())
    throw Error(
        "cannot view '" + path + "': the folder holds nothing view can show" +
        (list.skipped.empty() ? std::string() : " (" + std::to_string(list.skipped.size()) + " files skipped)"));
  it.kind = "folder";
  it.content = std::move(list);
  return it;
}

struct Reader {
  const char* kind;  // for view_kind before reading
  bool (*claims)(const std::string& path, const std::string& ext, bool dir);
  Item (*read)(const std::string& path);
};

const Reader kReaders[] = {
    {"folder", [](const std::string&, const std::string&, bool dir) { return dir; }, read_folder},
    {"KTX2", [](const std::string&, const std::string& e, bool) { return e == ".ktx2"; }, read_ktx2_file},
    {"KTX1", [](const std::string&, const std::string& e, bool) { return e == ".ktx"; }, read_ktx1_file},
    {"DDS", [](const std::string&, const std::string& e, bool) { return e == ".dds"; }, read_dds_file},
    {"JSON", [](const std::string&, const std::string& e, bool) { return e == ".json"; }, read_json_file},
    {"MERL", [](const std::string&, const std::string& e, bool) { return e == ".binary"; }, read_merl_file},
    {"table",
     [](const std::string&, const std::string& e, bool) {
       return e == ".exr" || e == ".png" || e == ".hdr" || e == ".csv" || e == ".h";
     },
     read_table_file},
    {"float32",
     [](const std::string&, const std::string& e, bool) { return e == ".f32" || e == ".bin" || e == ".raw"; },
     read_eval_binary},
    {"Babylon.js .env", [](const std::string&, const std::string& e, bool) { return e == ".env"; },
     read_babylon_env_file},
    {"glTF EXT_lights_image_based", [](const std::string&, const std::string& e, bool) { return e == ".gltf"; },
     read_gltf_file},
    {"Filament sh.txt",
     [](const std::string& p, const std::string& e, bool) {
       return e == ".txt" && fs::path(p).filename().string().find("sh") != std::string::npos;
     },
     read_sh_txt_file},
};

const Reader* reader_for(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error("cannot view '" + path + "': no such file or folder");
  const bool dir = is_dir(path);
  const std::string ext = lower_ext(path);
  for (const Reader& r : kReaders)
    if (r.claims(path, ext, dir)) return &r;
  throw Error("cannot view '" + path +
              "': unknown kind of file (view shows .ktx2 .ktx .dds .exr .png .hdr .csv .h .json "
              ".binary .f32, the engine files .env .gltf sh.txt, and output folders)");
}

}  // namespace

std::string kind_of(const std::string& path) { return reader_for(path)->kind; }

Item load(const std::string& path) {
  Item it = reader_for(path)->read(path);
  it.path = path;
  return it;
}

}  // namespace brdfbake::view
