// Loading environments: equirects and crosses (OpenEXR and Radiance RGBE read directly, other
// formats through the OpenImageIO module, io/image_file), six face files, KTX2 cubes, and the
// procedural builtin:studio and builtin:sun; validation of the values.
#include "brdfbake/environment.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "brdfbake/cancel.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/equirect.hpp"
#include "io/image_file.hpp"
#include "io/special_files.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;
using brdfbake::math::kPi;

const char* const kFaceNames[6] = {"px", "nx", "py", "ny", "pz", "nz"};

// ---- Image files --------------------------------------------------------------------------------

struct RgbImage {
  int width = 0, height = 0;
  std::vector<float> rgb;
  std::string description;
  std::vector<std::string> notes;  // EnvImage::notes
};

uint64_t budget_of(const EnvLoadOptions& o) { return o.memory_budget > 0 ? o.memory_budget : default_memory_budget(); }

// Which channels of an image hold R, G and B (the same for grey). Channels are found by name (R, G,
// B, or Y for grey; a layer's "diffuse.R" counts as R); an image without names (or with
// OpenImageIO's defaults for data that has none) is grey, grey and alpha, or RGB by its count. An
// image with names but no colour channel (only alpha, depth, ...) is refused naming what it holds:
// using alpha as grey radiance would be a silent wrong value.
void colour_channels(const io::FloatImage& image, const std::string& path, int ch[3]) {
  const int nch = image.channels;
  auto name_of = [&](int c) {
    return size_t(c) < image.channel_names.size() ? image.channel_names[size_t(c)] : std::string();
  };
  auto base_of = [](std::string n) {
    const size_t dot = n.rfind('.');
    if (dot != std::string::npos) n = n.substr(dot + 1);
    for (char& x : n) x = static_cast<char>(std::toupper(static_cast<unsigned char>(x)));
    return n;
  };
  bool named = false;
  for (int c = 0; c < nch; ++c) {
    const std::string n = name_of(c);
    // OpenImageIO's names for channels a file leaves unnamed beyond the fourth: channelN
    if (!n.empty() && n.rfind("channel", 0) != 0) named = true;
  }
  if (!named) {
    ch[0] = 0;
    ch[1] = nch >= 3 ? 1 : 0;
    ch[2] = nch >= 3 ? 2 : 0;
    return;
  }
  int r = -1, g = -1, b = -1, y = -1;
  for (int c = 0; c < nch; ++c) {
    const std::string n = base_of(name_of(c));
    if (n == "R" && r < 0) r = c;
    if (n == "G" && g < 0) g = c;
    if (n == "B" && b < 0) b = c;
    if ((n == "Y" || n == "L") && y < 0) y = c;
  }
  if (r >= 0 && g >= 0 && b >= 0) {
    ch[0] = r;
    ch[1] = g;
    ch[2] = b;
    return;
  }
  if (y >= 0 && r < 0 && g < 0 && b < 0) {
    ch[0] = ch[1] = ch[2] = y;
    return;
  }
  std::string found;
  for (int c = 0; c < nch && c < 12; ++c) found += (c ? ", " : "") + name_of(c).substr(0, 24);
  if (nch > 12) found += ", ...";
  throw Error("environment '" + path + "' has no colour channels (it holds " + found +
              "): expected R, G and B, or Y for grey");
}

// Level 0 of the first image of a file (io::read_image), as RGB float: R, G, B found by name,
// else by their count (colour_channels).
RgbImage read_rgb_image(const std::string& path, uint64_t memory_budget) {
  // A FIFO or a device is refused here without opening it: decoders need a file (special_files.hpp).
  if (const std::string problem = io::input_problem(path, io::Streams::No); !problem.empty())
    throw Error("cannot read environment '" + path + "': " + problem);
  io::FloatImage image;
  try {
    image = io::read_image(path, io::ImageLimits{kMaxEnvironmentPixels, memory_budget});
  } catch (const Cancelled&) {
    throw;
  } catch (const RuntimeFailure& e) {
    throw IoError("cannot read environment '" + path + "': " + e.what());
  } catch (const Error& e) {
    throw Error("cannot read environment '" + path + "': " + e.what());
  }
  const int w = image.width, h = image.height, nch = image.channels;
  if (w < 1 || h < 1 || nch < 1) throw Error("environment '" + path + "' has no pixels");
  int ch[3] = {0, 0, 0};
  colour_channels(image, path, ch);
  RgbImage out;
  out.width = w;
  out.height = h;
  if (nch == 3 && ch[0] == 0 && ch[1] == 1 && ch[2] == 2) {
    out.rgb = std::move(image.pixels);
  } else {
    out.rgb.resize(static_cast<size_t>(w) * static_cast<size_t>(h) * 3);
    for (size_t p = 0; p < static_cast<size_t>(w) * static_cast<size_t>(h); ++p)
      for (size_t c = 0; c < 3; ++c)
        out.rgb[3 * p + c] = image.pixels[p * static_cast<size_t>(nch) + static_cast<size_t>(ch[c])];
  }
  out.description = image.description;
  if (!image.transfer_note.empty()) out.notes.push_back("'" + path + "': " + image.transfer_note);
  return out;
}

// Cross layouts (docs/CONVENTIONS.md): cells of the face size s, faces as stored in a cube (no
// rotation) except -Z in the vertical cross, which is turned by 180 degrees.
//   horizontal (4s x 3s):   . +Y  .  .      vertical (3s x 4s):   . +Y  .
//                          -X +Z +X -Z                           -X +Z +X
//                           . -Y  .  .                            . -Y  .
//                                                                 . -Z  .   (rotated 180)
struct CrossCell {
  int col, row;
  bool rotate180;
};
const CrossCell kHorizontalCross[6] = {{2, 1, false}, {0, 1, false}, {1, 0, false},
                                       {1, 2, false}, {1, 1, false}, {3, 1, false}};
const CrossCell kVerticalCross[6] = {{2, 1, false}, {0, 1, false}, {1, 0, false},
                                     {1, 2, false}, {1, 1, false}, {1, 3, true}};

EnvImage cube_from_cross(const RgbImage& img, bool horizontal) {
  const int s = horizontal ? img.width / 4 : img.width / 3;
  const CrossCell* cells = horizontal ? kHorizontalCross : kVerticalCross;
  EnvImage env;
  env.layout = EnvImage::Layout::Cube;
  env.width = env.height = s;
  env.rgb.resize(18u * static_cast<size_t>(s) * static_cast<size_t>(s));
  for (int f = 0; f < 6; ++f)
    for (int j = 0; j < s; ++j)
      for (int i = 0; i < s; ++i) {
        const int si = cells[f].rotate180 ? s - 1 - i : i, sj = cells[f].rotate180 ? s - 1 - j : j;
        const size_t src = 3 * (static_cast<size_t>(cells[f].row * s + sj) * static_cast<size_t>(img.width) +
                                static_cast<size_t>(cells[f].col * s + si));
        const size_t dst =
            3 * ((static_cast<size_t>(f) * static_cast<size_t>(s) + static_cast<size_t>(j)) * static_cast<size_t>(s) +
                 static_cast<size_t>(i));
        for (size_t c = 0; c < 3; ++c) env.rgb[dst + c] = img.rgb[src + c];
      }
  return env;
}

// ---- Validation -------------------------------------------------------------------------------

void validate(EnvImage& env, bool sanitize) {
  EnvSanitizeReport r;
  float max_finite = 0.0f;
  for (float v : env.rgb) {
    if (std::isnan(v))
      ++r.nan;
    else if (std::isinf(v))
      ++r.infinite;
    else if (v < 0.0f)
      ++r.negative;
    else
      max_finite = std::max(max_finite, v);
  }
  if (r.total() == 0) return;
  if (!sanitize) {
    throw Error("environment '" + env.source + "' has " + std::to_string(r.nan) + " NaN, " +
                std::to_string(r.infinite) + " infinite and " + std::to_string(r.negative) +
                " negative pixel values (of " + std::to_string(env.rgb.size()) + "); pass --sanitize to replace them");
  }
  for (float& v : env.rgb) {
    if (std::isnan(v) || v < 0.0f)
      v = 0.0f;  // NaN, -inf and negatives
    else if (std::isinf(v))
      v = max_finite;  // +inf
  }
  r.replaced = true;
  env.sanitize = r;
}

bool ends_with(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  std::string tail = s.substr(s.size() - suffix.size());
  std::transform(tail.begin(), tail.end(), tail.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return tail == suffix;
}

EnvImage load_faces(const std::vector<std::string>& files, const std::string& spec, uint64_t memory_budget) {
  EnvImage env;
  env.layout = EnvImage::Layout::Cube;
  env.source = spec;
  int s = 0;
  for (size_t f = 0; f < 6; ++f) {
    const RgbImage img = read_rgb_image(files[f], memory_budget / 2);  // the face and the cube it joins
    if (img.width != img.height)
      throw Error("cube face '" + files[f] + "' is " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                  "; faces must be square");
    if (f == 0) {
      s = img.width;
      env.width = env.height = s;
      env.rgb.reserve(18u * static_cast<size_t>(s) * static_cast<size_t>(s));
    } else if (img.width != s) {
      throw Error("cube face '" + files[f] + "' is " + std::to_string(img.width) + "x" + std::to_string(img.width) +
                  " but '" + files[0] + "' is " + std::to_string(s) + "x" + std::to_string(s));
    }
    env.rgb.insert(env.rgb.end(), img.rgb.begin(), img.rgb.end());
    env.notes.insert(env.notes.end(), img.notes.begin(), img.notes.end());
  }
  env.description = "six faces of " + std::to_string(s) + "x" + std::to_string(s);
  return env;
}

// ---- Built-in environments ----------------------------------------------------------------------

struct V3 {
  double x, y, z;
};
V3 v3(const Vec3& d) { return {d.x, d.y, d.z}; }
double dot(const V3& a, const V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(const V3& a, const V3& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
V3 unit(const V3& a) {
  const double n = std::sqrt(dot(a, a));
  return {a.x / n, a.y / n, a.z / n};
}
// The direction at azimuth and elevation in degrees (azimuth 0 along +Z, 90 along +X).
V3 from_angles(double azimuth_deg, double elevation_deg) {
  const double az = azimuth_deg * kPi / 180.0, el = elevation_deg * kPi / 180.0;
  return {std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el)};
}
double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

// A rectangular softbox: angular half-sizes, soft edges over the outer 20% of each half-size, in
// the frame (right, up, centre) of its centre direction.
struct Softbox {
  V3 centre;
  double half_w, half_h;  // radians
  double radiance[3];
  V3 right, up;
  double cos_reach;  // directions with d.centre below it are outside (quick rejection)
};
Softbox softbox(const V3& centre, double half_w, double half_h, double r, double g, double b) {
  Softbox s{centre, half_w, half_h, {r, g, b}, {}, {}, 0.0};
  s.right = unit(std::fabs(centre.y) > 0.99 ? cross(V3{0, 0, 1}, centre) : cross(V3{0, 1, 0}, centre));
  s.up = cross(centre, s.right);
  s.cos_reach = std::cos(std::min(1.5, 1.5 * std::hypot(half_w, half_h)));
  return s;
}
double softbox_weight(const Softbox& b, const V3& d) {
  const double f = dot(d, b.centre);
  if (f <= b.cos_reach) return 0.0;
  const double x = std::fabs(std::atan2(dot(d, b.right), f)), y = std::fabs(std::atan2(dot(d, b.up), f));
  if (x >= b.half_w || y >= b.half_h) return 0.0;
  return smoothstep(b.half_w, 0.8 * b.half_w, x) * smoothstep(b.half_h, 0.8 * b.half_h, y);
}

void studio_radiance(const V3& d, double out[3]) {
  static const Softbox boxes[] = {
      softbox(from_angles(45, 30), 0.26, 0.17, 30.0, 28.5, 27.0),    // key, warm
      softbox(from_angles(-60, 15), 0.22, 0.30, 7.0, 7.6, 8.4),      // fill, cool
      softbox(from_angles(0, 80), 0.35, 0.35, 14.0, 14.0, 14.0),     // top
      softbox(from_angles(180, 10), 0.52, 0.035, 20.0, 20.0, 20.0),  // rim strip behind
  };
  // grey room: dark floor, walls brightening towards the ceiling
  const double g = d.y < 0.0 ? 0.06 + 0.02 * (1.0 + d.y) : 0.10 + 0.22 * d.y;
  out[0] = g;
  out[1] = g * 0.98;
  out[2] = g * 0.95;
  for (const Softbox& b : boxes) {
    const double w = softbox_weight(b, d);
    for (int c = 0; c < 3; ++c) out[c] += w * b.radiance[c];
  }
}

// The sun of builtin:sun: 0.5 degree radius, radiance 5e4 (warm white), at azimuth -120 degrees
// and elevation 35 degrees; a faint aureole falls off as exp(-theta / 1.5 degrees).
constexpr double kSunRadius = 0.5 * kPi / 180.0;
constexpr double kSunRadiance = 5.0e4;
const V3& sun_direction() {
  static const V3 d = from_angles(-120.0, 35.0);
  return d;
}
void sun_radiance(const V3& d, double out[3]) {
  if (d.y >= 0.0) {  // sky: deep blue at the zenith, pale at the horizon
    const double t = std::pow(1.0 - d.y, 3.0);
    out[0] = 0.20 + 0.70 * t;
    out[1] = 0.40 + 0.55 * t;
    out[2] = 0.90 + 0.35 * t;
  } else {  // dark ground
    out[0] = 0.10;
    out[1] = 0.08;
    out[2] = 0.06;
  }
  const double theta = std::acos(std::clamp(dot(d, sun_direction()), -1.0, 1.0));
  if (theta < kSunRadius) {
    out[0] += kSunRadiance;
    out[1] += kSunRadiance * 0.96;
    out[2] += kSunRadiance * 0.88;
  } else {
    const double a = 40.0 * std::exp(-(theta - kSunRadius) / (1.5 * kPi / 180.0));
    out[0] += a;
    out[1] += a * 0.95;
    out[2] += a * 0.85;
  }
}

// Renders a direction function into an equirect: each pixel the solid-angle-weighted mean of k x k
// sub-samples (k = 16 near the sun, where the disc's edge needs it, else 2).
EnvImage render_equirect(const std::string& name, int width, void (*radiance)(const V3&, double*), bool sun) {
  const int w = width, h = width / 2;
  EnvImage env;
  env.layout = EnvImage::Layout::Equirect;
  env.width = w;
  env.height = h;
  env.source = "builtin:" + name;
  env.rgb.resize(static_cast<size_t>(w) * static_cast<size_t>(h) * 3);
  const double pixel_angle = 2.0 * kPi / w;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const V3 centre = v3(math::equirect_direction((x + 0.5) / w, (y + 0.5) / h));
      int k = 2;
      if (sun && std::acos(std::clamp(dot(centre, sun_direction()), -1.0, 1.0)) <
                     kSunRadius + 4.0 * pixel_angle / std::max(0.05, std::sqrt(1.0 - centre.y * centre.y)))
        k = 16;
      double sum[3] = {0, 0, 0}, wsum = 0;
      for (int sy = 0; sy < k; ++sy)
        for (int sx = 0; sx < k; ++sx) {
          const double v = (y + (sy + 0.5) / k) / h;
          const V3 d = v3(math::equirect_direction((x + (sx + 0.5) / k) / w, v));
          const double weight = std::cos(kPi * (0.5 - v));  // solid angle of the sub-sample
          double l[3];
          radiance(d, l);
          for (int c = 0; c < 3; ++c) sum[c] += weight * l[c];
          wsum += weight;
        }
      for (size_t c = 0; c < 3; ++c)
        env.rgb[3 * (static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) + c] =
            static_cast<float>(sum[c] / wsum);
    }
  env.description = "procedural equirect " + std::to_string(w) + "x" + std::to_string(h);
  return env;
}

}  // namespace

std::vector<std::string> builtin_environment_names() { return {"studio", "sun"}; }

EnvImage builtin_environment(const std::string& name, int width) {
  if (width < 4 || width % 2 != 0 || width > 16384)
    throw Error("builtin environment width must be even and in 4..16384 (got " + std::to_string(width) + ")");
  if (name == "studio") return render_equirect(name, width, studio_radiance, false);
  if (name == "sun") return render_equirect(name, width, sun_radiance, true);
  throw Error("unknown builtin environment 'builtin:" + name + "' (expected builtin:studio or builtin:sun)");
}

// The six face files a spec names ("PX,NX,PY,NY,PZ,NZ", or a path holding "{face}"), or none.
static std::vector<std::string> face_files(const std::string& spec) {
  std::vector<std::string> faces;
  if (spec.find(',') != std::string::npos) {
    std::stringstream ss(spec);
    std::string item;
    while (std::getline(ss, item, ',')) faces.push_back(item);
    if (faces.size() != 6)
      throw Error("a cube from face files needs six files (+X,-X,+Y,-Y,+Z,-Z), got " + std::to_string(faces.size()));
  } else if (const size_t at = spec.find("{face}"); at != std::string::npos) {
    for (const char* f : kFaceNames) faces.push_back(spec.substr(0, at) + f + spec.substr(at + 6));
  }
  return faces;
}

uint64_t default_memory_budget() {
  static const uint64_t budget = [] {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
    uint64_t usable = pages > 0 && page > 0 ? uint64_t(pages) * uint64_t(page) : uint64_t(4) << 30;
    // a container's limit (cgroup v2, then v1) where it is lower
    for (const char* file : {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
      std::ifstream in(file);
      std::string text;
      if (in >> text && !text.empty() && std::isdigit(static_cast<unsigned char>(text[0]))) {
        const uint64_t limit = std::strtoull(text.c_str(), nullptr, 10);
        if (limit > 0) usable = std::min(usable, limit);
      }
    }
    return usable / 2;
  }();
  return budget;
}

uint64_t parse_byte_size(const std::string& text) {
  const auto bad = [&] {
    return Error("'" + text.substr(0, 40) + "' is not a size (e.g. 512MiB, 8GiB, 1.5G or a number of bytes)");
  };
  size_t end = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &end);
  } catch (const std::exception&) {
    throw bad();
  }
  std::string unit = text.substr(end);
  std::transform(unit.begin(), unit.end(), unit.begin(), [](unsigned char c) { return char(std::toupper(c)); });
  static const std::pair<const char*, double> kUnits[] = {
      {"", 1.0},       {"B", 1.0},     {"K", 0x1p10},   {"KI", 0x1p10}, {"KIB", 0x1p10}, {"KB", 1e3},
      {"M", 0x1p20},   {"MI", 0x1p20}, {"MIB", 0x1p20}, {"MB", 1e6},    {"G", 0x1p30},   {"GI", 0x1p30},
      {"GIB", 0x1p30}, {"GB", 1e9},    {"T", 0x1p40},   {"TI", 0x1p40}, {"TIB", 0x1p40}, {"TB", 1e12}};
  double scale = 0.0;
  for (const auto& [name, factor] : kUnits)
    if (unit == name) scale = factor;
  if (!(scale > 0.0) || !std::isfinite(value) || !(value > 0.0)) throw bad();
  const double bytes = value * scale;
  if (bytes < 1.0 || bytes > std::ldexp(1.0, 60)) throw bad();
  return static_cast<uint64_t>(bytes);
}

EnvImage load_environment(const std::string& spec, const EnvLoadOptions& options) {
  if (spec.empty()) throw Error("no environment given (a file, six files, or builtin:studio / builtin:sun)");
  if (spec.rfind("builtin:", 0) == 0) return builtin_environment(spec.substr(8), options.builtin_width);

  EnvImage env;
  const std::vector<std::string> faces = face_files(spec);
  if (!faces.empty()) {
    env = load_faces(faces, spec, budget_of(options));
  } else if (ends_with(spec, ".ktx2")) {
    if (const std::string problem = io::input_problem(spec, io::Streams::No); !problem.empty())
      throw Error("cannot read environment '" + spec + "': " + problem);
    // The reader holds the file (its sizes checked against the file's length) and level 0 as RGB
    // floats: at most 3 times the file's size (binary16 RGB, 6 bytes a texel, becomes 12).
    std::error_code ec;
    const uint64_t bytes = fs::is_regular_file(spec, ec) ? uint64_t(fs::file_size(spec, ec)) : 0;
    if (!ec && 3 * bytes > budget_of(options))
      throw Error("cannot read environment '" + spec + "': a " + io::mib_text(bytes) + " KTX2 file takes up to " +
                  io::mib_text(3 * bytes) + " to read, above the memory budget of " + io::mib_text(budget_of(options)) +
                  " (--memory-budget)");
    env = read_ktx2_cube(spec, 0);
  } else {
    RgbImage img = read_rgb_image(spec, budget_of(options));
    env.notes = img.notes;
    if (img.width == 2 * img.height) {
      env.layout = EnvImage::Layout::Equirect;
      env.width = img.width;
      env.height = img.height;
      env.rgb = std::move(img.rgb);
      env.description = "equirect: " + img.description;
    } else if (3 * img.width == 4 * img.height && img.width % 4 == 0) {
      env = cube_from_cross(img, true);
      env.notes = img.notes;
      env.description = "horizontal cross: " + img.description;
    } else if (4 * img.width == 3 * img.height && img.width % 3 == 0) {
      env = cube_from_cross(img, false);
      env.notes = img.notes;
      env.description = "vertical cross: " + img.description;
    } else {
      throw Error("environment '" + spec + "' is " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                  ": expected an equirect of 2:1, a horizontal cross of 4:3 or a vertical cross of 3:4");
    }
  }
  env.source = spec;
  validate(env, options.sanitize);
  return env;
}

void check_environment_size(uint64_t width, uint64_t height, const std::string& source, const EnvLoadOptions& options) {
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  if (width > kMaxEnvironmentPixels || height > kMaxEnvironmentPixels || width * height > kMaxEnvironmentPixels)
    throw Error("environment '" + source + "' is " + size + " (" + std::to_string(width * height) +
                " pixels): more than the limit of " + std::to_string(kMaxEnvironmentPixels) +
                " pixels (16384x16384); scale it down first");
  const uint64_t need = width * height * 3 * sizeof(float) * 2, budget = budget_of(options);
  if (need > budget)
    throw Error("environment '" + source + "' is " + size + ": taking it in needs " + io::mib_text(need) +
                ", above the memory budget of " + io::mib_text(budget) +
                " (half the memory this process may use); scale it down first");
}

EnvImage environment_from_equirect(int width, int height, std::vector<float> rgb, const std::string& source,
                                   const EnvLoadOptions& options) {
  if (height < 1 || width != 2 * height)
    throw Error("environment '" + source + "' is " + std::to_string(width) + "x" + std::to_string(height) +
                ": an equirect must be twice as wide as it is high");
  check_environment_size(static_cast<uint64_t>(width), static_cast<uint64_t>(height), source, options);
  if (rgb.size() != 3u * static_cast<size_t>(width) * static_cast<size_t>(height))
    throw Error("environment '" + source + "': " + std::to_string(rgb.size()) + " values for " + std::to_string(width) +
                "x" + std::to_string(height) + " RGB pixels");
  EnvImage env;
  env.layout = EnvImage::Layout::Equirect;
  env.width = width;
  env.height = height;
  env.rgb = std::move(rgb);
  env.source = source;
  env.description = "equirect " + std::to_string(width) + "x" + std::to_string(height) + " (in memory)";
  validate(env, options.sanitize);
  return env;
}

std::vector<std::string> environment_files(const std::string& spec) {
  if (spec.empty() || spec.rfind("builtin:", 0) == 0) return {};
  std::vector<std::string> files = face_files(spec);
  if (files.empty()) files.push_back(spec);
  return files;
}

void check_builtin_environment(const std::string& spec) {
  if (spec.rfind("builtin:", 0) != 0) return;
  const std::string name = spec.substr(8);
  for (const auto& n : builtin_environment_names())
    if (n == name) return;
  throw Error("unknown builtin environment '" + spec.substr(0, 80) + "' (expected builtin:studio or builtin:sun)");
}

void check_environment_source(const std::string& spec) {
  if (spec.empty()) throw Error("no environment given (a file, six files, or builtin:studio / builtin:sun)");
  if (spec.rfind("builtin:", 0) == 0) return check_builtin_environment(spec);
  std::vector<std::string> files = face_files(spec);
  if (files.empty()) files.push_back(spec);
  namespace fs = std::filesystem;
  for (const auto& f : files) {
    std::error_code ec;
    if (!fs::exists(f, ec)) throw Error("cannot read environment '" + f + "': no such file");
    if (fs::is_directory(f, ec)) throw Error("cannot read environment '" + f + "': it is a folder");
    if (const std::string problem = io::input_problem(f, io::Streams::No); !problem.empty())
      throw Error("cannot read environment '" + f + "': " + problem);
    if (::access(f.c_str(), R_OK) != 0) throw Error("cannot read environment '" + f + "': permission denied");
  }
}

}  // namespace brdfbake
