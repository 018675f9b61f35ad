// The delivered error an engine file's manifest entry records (EngineFileEntry, write_engine_files) is
// the error of what the engine decodes from that file: each encoding's file is decoded here by a
// decoder of the test's own, written from the format's specification (KTX 1.1 and OpenGL's
// R11F_G11F_B10F bit layout; Babylon.js's .env container, its RGBD PNG faces read by OpenImageIO and
// fromRGBD into a half-float cube; KTX 2.0 RGBA16F through Imath's half), compared with the float
// values the writer was given, and the two figures recomputed from the definitions
// (docs/CONVENTIONS.md, "Error figures"). Each test also plants the figure of another encoding (the
// binary16 error recorded for an R11F_G11F_B10F file, no gamma for RGBD) and checks that the same
// comparison refuses it: the check can fail.
#include <Imath/half.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "brdfbake/engines.hpp"
#include "brdfbake/error_figures.hpp"
#include "brdfbake/tables.hpp"
#include "engines/babylon_frame.hpp"
#include "test_target_support.hpp"

namespace brdfbake {
namespace {

using namespace target_test;  // NOLINT: temp_dir, read_all, u32, synthetic_chain, sh_one_plus_x

// ---- The figures, from their definitions ---------------------------------------------------------

struct Figures {
  double rms_rel = 0.0, max_rel = 0.0;
};
struct Sums {
  double err2 = 0.0, val2 = 0.0, max_rel = 0.0;
};

// R, G, B of `texels` RGBA texels: sums of squares and the max relative to each texel's largest
// channel (floored at 1e-6 of the level's largest value).
void accumulate(Sums& s, const float* decoded, const float* value, size_t texels, double level_max) {
  for (size_t t = 0; t < texels; ++t) {
    const double scale =
        std::max({double(value[4 * t]), double(value[4 * t + 1]), double(value[4 * t + 2]), 1e-6 * level_max});
    for (size_t c = 0; c < 3; ++c) {
      const double e = double(decoded[4 * t + c]) - double(value[4 * t + c]);
      s.err2 += e * e;
      s.val2 += double(value[4 * t + c]) * double(value[4 * t + c]);
      s.max_rel = std::max(s.max_rel, std::fabs(e) / scale);
    }
  }
}
double level_max(const std::vector<float>& level) {
  double m = 0.0;
  for (size_t t = 0; t < level.size() / 4; ++t)
    for (size_t c = 0; c < 3; ++c) m = std::max(m, double(level[4 * t + c]));
  return m;
}
Figures figures(const Sums& s) { return {std::sqrt(s.err2 / s.val2), s.max_rel}; }

// Recorded against recomputed: the same numbers to double rounding of different summation orders.
constexpr double kSameFigure = 1e-9;
bool same(double recorded, double recomputed) {
  return std::fabs(recorded - recomputed) <= kSameFigure * std::max(1e-12, std::fabs(recomputed));
}

// Per level and for the whole file, `decoded` against `values`; the entry must record exactly these.
void expect_entry(const EngineFileEntry& e, const CubeLevels& decoded, const CubeLevels& values) {
  ASSERT_TRUE(e.measured) << e.path;
  ASSERT_EQ(decoded.levels.size(), values.levels.size());
  ASSERT_EQ(e.error_rms_rel_per_level.size(), values.levels.size());
  Sums file;
  for (size_t l = 0; l < values.levels.size(); ++l) {
    Sums one;
    accumulate(one, decoded.levels[l].data(), values.levels[l].data(), values.levels[l].size() / 4,
               level_max(values.levels[l]));
    EXPECT_TRUE(same(e.error_rms_rel_per_level[l], figures(one).rms_rel))
        << e.path << " level " << l << ": " << e.error_rms_rel_per_level[l] << " vs " << figures(one).rms_rel;
    EXPECT_TRUE(same(e.error_max_rel_per_level[l], figures(one).max_rel))
        << e.path << " level " << l << ": " << e.error_max_rel_per_level[l] << " vs " << figures(one).max_rel;
    file.err2 += one.err2;
    file.val2 += one.val2;
    file.max_rel = std::max(file.max_rel, one.max_rel);
  }
  EXPECT_TRUE(same(e.error_rms_rel, figures(file).rms_rel)) << e.path;
  EXPECT_TRUE(same(e.error_max_rel, figures(file).max_rel)) << e.path;
  EXPECT_GT(e.error_rms_rel, 0.0) << e.path << ": every encoding here is lossy";
}

constexpr const char* kFaces[6] = {"px", "nx", "py", "ny", "pz", "nz"};  // the glTF target's face names

const EngineFileEntry& entry(const EngineWriteResult& w, const std::string& path) {
  for (const EngineFileEntry& e : w.entries)
    if (e.path == path) return e;
  throw std::runtime_error("no entry " + path);
}

// ---- Decoders of the test's own ----------------------------------------------------------------

// OpenGL 4.6, 8.25 / the unsigned 11- and 10-bit floats: 5-bit exponent (bias 15), 6 or 5 mantissa bits.
float unsigned_float(uint32_t bits, int mantissa_bits) {
  const uint32_t m = bits & ((1u << mantissa_bits) - 1u), e = bits >> mantissa_bits;
  if (e == 0) return float(std::ldexp(double(m), -14 - mantissa_bits));
  if (e == 31) return m ? NAN : INFINITY;
  return float(std::ldexp(1.0 + double(m) / double(1u << mantissa_bits), int(e) - 15));
}

// A KTX 1.1 cube of GL_R11F_G11F_B10F texels (R in bits 0..10, G 11..21, B 22..31): the header's 13
// fields, the key/value bytes skipped, then per level imageSize and six faces (4-byte rows: no
// padding).
CubeLevels decode_ktx1_r11g11b10(const std::vector<uint8_t>& b) {
  EXPECT_EQ(u32(b, 16), 0x8C3Au) << "glType: Filament's GL_R11F_G11F_B10F";
  const uint32_t width = u32(b, 36), faces = u32(b, 52), levels = u32(b, 56), kv = u32(b, 60);
  EXPECT_EQ(faces, 6u);
  CubeLevels c;
  c.size = int(width);
  size_t at = 64 + kv;
  for (uint32_t l = 0; l < levels; ++l) {
    const uint32_t s = std::max(1u, width >> l), image = u32(b, at);
    EXPECT_EQ(image, s * s * 4u) << "level " << l;
    at += 4;
    std::vector<float> v;
    for (uint32_t t = 0; t < 6 * s * s; ++t, at += 4) {
      const uint32_t p = u32(b, at);
      v.insert(v.end(),
               {unsigned_float(p & 0x7FF, 6), unsigned_float((p >> 11) & 0x7FF, 6), unsigned_float(p >> 22, 5), 1.0f});
    }
    c.levels.push_back(std::move(v));
  }
  EXPECT_EQ(at, b.size());
  return c;
}

// An 8-bit RGBA PNG read by OpenImageIO from bytes written to `scratch`, its alpha unassociated.
std::vector<uint8_t> png_rgba8(const uint8_t* data, size_t size, const fs::path& scratch, int* w) {
  {
    std::ofstream out(scratch, std::ios::binary);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  // RGBD's alpha is a divisor, not coverage: the bytes as stored, not premultiplied by OpenImageIO
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(scratch.string(), &config);
  if (!in) throw std::runtime_error("OpenImageIO cannot open " + scratch.string());
  const OIIO::ImageSpec& spec = in->spec();
  EXPECT_EQ(spec.nchannels, 4);
  *w = spec.width;
  std::vector<uint8_t> px(size_t(spec.width) * size_t(spec.height) * 4);
  EXPECT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, px.data()));
  in->close();
  return px;
}

// Babylon.js's fromRGBD (helperFunctions.fx): rgb = (rgb' / 255)^2.2 / (a / 255), in fp32, stored in
// a HALF_FLOAT cube; row 0 of the image is the face's last row. `gamma` 1 is the planted defect.
std::vector<float> rgbd_face(const std::vector<uint8_t>& px, int s, float gamma = 2.2f) {
  std::vector<float> out(size_t(s) * size_t(s) * 4, 1.0f);
  for (int row = 0; row < s; ++row)
    for (int col = 0; col < s; ++col) {
      const uint8_t* p = &px[4 * (size_t(row) * size_t(s) + size_t(col))];
      float* o = &out[4 * (size_t(s - 1 - row) * size_t(s) + size_t(col))];
      const float a = float(p[3]) / 255.0f;
      for (int c = 0; c < 3; ++c) o[c] = float(Imath::half(a > 0 ? std::pow(float(p[c]) / 255.0f, gamma) / a : 0.0f));
    }
  return out;
}

// ---- Filament: NAME_ibl.ktx and NAME_skybox.ktx, R11F_G11F_B10F ---------------------------------

TEST(EngineDeliveredError, FilamentR11G11B10IsTheDecodedFilesError) {
  const CubeLevels chain = synthetic_chain(16, 1, RoughnessSchedule::Filament);
  const ShCoefficients sh = sh_one_plus_x();
  EngineBake bake;
  bake.prefiltered = &chain;
  bake.sh = &sh;
  const fs::path dir = temp_dir("filament_delivered");
  EngineWriteOptions o;
  o.name = "env";
  const EngineWriteResult w = write_engine_files(EngineTarget::Filament, bake, dir.string(), o);
  ASSERT_EQ(w.entries.size(), w.files.size());

  const std::vector<uint8_t> ibl = read_all(dir / "env_ibl.ktx");
  const EngineFileEntry& e = entry(w, "env_ibl.ktx");
  EXPECT_EQ(e.bytes, ibl.size());
  EXPECT_EQ(e.format, "R11F_G11F_B10F");
  const CubeLevels decoded = decode_ktx1_r11g11b10(ibl);
  expect_entry(e, decoded, chain);
  // 6 (R, G) and 5 (B) mantissa bits: a relative step of 2^-6 and 2^-5, half of it at most
  EXPECT_LE(e.error_max_rel, std::ldexp(1.0, -6) * 1.0001);
  EXPECT_GT(e.error_rms_rel, std::ldexp(1.0, -10)) << "far above binary16's rounding";

  // The planted defect: the binary16 round trip's error recorded for this file (the figures a
  // storage error of the wrong encoding gives) is refused by the same comparison.
  CubeLevels f16 = chain;
  for (auto& level : f16.levels)
    for (float& v : level) v = float(Imath::half(v));
  Sums planted;
  for (size_t l = 0; l < chain.levels.size(); ++l)
    accumulate(planted, f16.levels[l].data(), chain.levels[l].data(), chain.levels[l].size() / 4,
               level_max(chain.levels[l]));
  EXPECT_FALSE(same(figures(planted).rms_rel, e.error_rms_rel))
      << "binary16's " << figures(planted).rms_rel << " against R11G11B10's " << e.error_rms_rel;
  EXPECT_FALSE(same(figures(planted).max_rel, e.error_max_rel));

  // The skybox: level 0 alone, the same encoding
  const std::vector<uint8_t> sky = read_all(dir / "env_skybox.ktx");
  CubeLevels level0 = chain;
  level0.levels.resize(1);
  expect_entry(entry(w, "env_skybox.ktx"), decode_ktx1_r11g11b10(sky), level0);
  // sh.txt holds no texels: its size and no figure
  EXPECT_FALSE(entry(w, "sh.txt").measured);
  EXPECT_EQ(entry(w, "sh.txt").bytes, fs::file_size(dir / "sh.txt"));
}

// ---- Babylon.js: NAME.env, RGBD PNG faces ------------------------------------------------------

TEST(EngineDeliveredError, BabylonRgbdPngIsTheDecodedFilesError) {
  const CubeLevels chain = synthetic_chain(8, 1, RoughnessSchedule::Babylon);
  const ShCoefficients sh = sh_one_plus_x();
  EngineBake bake;
  bake.prefiltered = &chain;
  bake.sh = &sh;
  const fs::path dir = temp_dir("babylon_delivered");
  EngineWriteOptions o;
  o.name = "env";
  const EngineWriteResult w = write_engine_files(EngineTarget::Babylon, bake, dir.string(), o);
  const std::vector<uint8_t> env = read_all(dir / "env.env");
  const EngineFileEntry& e = entry(w, "env.env");
  EXPECT_EQ(e.bytes, env.size());

  // The container: 8 magic bytes, the JSON manifest up to its NUL, the images at their positions
  // counted from the byte after the NUL.
  const auto nul = std::find(env.begin() + 8, env.end(), uint8_t(0));
  ASSERT_NE(nul, env.end());
  const nlohmann::json manifest = nlohmann::json::parse(std::string(env.begin() + 8, nul));
  const size_t base = size_t(nul - env.begin()) + 1;
  const auto& mips = manifest["specular"]["mipmaps"];
  ASSERT_EQ(mips.size(), 6 * chain.levels.size());
  // The values the file encodes: the chain in Babylon.js's left-handed frame (the writer's input)
  const CubeLevels values = detail::mirror_cube_x(chain);
  CubeLevels decoded, planted;
  decoded.size = planted.size = chain.size;
  const fs::path scratch = dir / "face.png";
  for (size_t l = 0; l < chain.levels.size(); ++l) {
    std::vector<float> level, level_planted;
    for (size_t f = 0; f < 6; ++f) {
      const auto& m = mips[6 * l + f];
      int s = 0;
      const std::vector<uint8_t> px =
          png_rgba8(env.data() + base + m["position"].get<size_t>(), m["length"].get<size_t>(), scratch, &s);
      ASSERT_EQ(s, chain.level_size(int(l)));
      const std::vector<float> face = rgbd_face(px, s), face_planted = rgbd_face(px, s, 1.0f);
      level.insert(level.end(), face.begin(), face.end());
      level_planted.insert(level_planted.end(), face_planted.begin(), face_planted.end());
    }
    decoded.levels.push_back(std::move(level));
    planted.levels.push_back(std::move(level_planted));
  }
  expect_entry(e, decoded, values);
  // 8 bits over a gamma of 2.2: a step of about 2.2 / 255 of the largest channel at the top
  EXPECT_LT(e.error_max_rel, 0.02);

  // The planted defect: RGBD decoded without its gamma (what a linear decoder of the same bytes
  // reads) gives another figure, which the comparison refuses.
  Sums p;
  for (size_t l = 0; l < values.levels.size(); ++l)
    accumulate(p, planted.levels[l].data(), values.levels[l].data(), values.levels[l].size() / 4,
               level_max(values.levels[l]));
  EXPECT_FALSE(same(figures(p).rms_rel, e.error_rms_rel));
}

// ---- glTF: one RGBD PNG file a face, each with its own figure ------------------------------------

TEST(EngineDeliveredError, GltfFacesEachCarryTheirDecodedError) {
  const CubeLevels chain = synthetic_chain(8, 1, RoughnessSchedule::Linear);
  const ShCoefficients sh = sh_one_plus_x();
  EngineBake bake;
  bake.prefiltered = &chain;
  bake.sh = &sh;
  const fs::path dir = temp_dir("gltf_delivered");
  EngineWriteOptions o;
  o.name = "env";
  const EngineWriteResult w = write_engine_files(EngineTarget::Gltf, bake, dir.string(), o);
  const CubeLevels values = detail::mirror_cube_x(chain);
  int faces = 0;
  for (int l = 0; l < chain.level_count(); ++l)
    for (int f = 0; f < 6; ++f) {
      const std::string name = "env_specular_" + std::to_string(l) + "_" + kFaces[f] + ".png";
      const std::vector<uint8_t> png = read_all(dir / name);
      int s = 0;
      const std::vector<uint8_t> px = png_rgba8(png.data(), png.size(), dir / "face.png", &s);
      const std::vector<float> decoded = rgbd_face(px, s);
      const std::vector<float>& level = values.levels[size_t(l)];
      Sums one;
      accumulate(one, decoded.data(), level.data() + 4 * size_t(s) * size_t(s) * size_t(f), size_t(s) * size_t(s),
                 level_max(level));
      const EngineFileEntry& e = entry(w, name);
      EXPECT_EQ(e.bytes, png.size());
      EXPECT_TRUE(same(e.error_rms_rel, figures(one).rms_rel)) << name;
      EXPECT_TRUE(same(e.error_max_rel, figures(one).max_rel)) << name;
      ++faces;
    }
  EXPECT_EQ(faces, 6 * chain.level_count());
  EXPECT_FALSE(entry(w, "env.gltf").measured);
}

// ---- khronos-viewer: KTX2 RGBA16F --------------------------------------------------------------

TEST(EngineDeliveredError, KhronosViewerHalfIsTheDecodedFilesError) {
  const CubeLevels chain = synthetic_chain(8, 1, RoughnessSchedule::Linear);
  CubeLevels lambertian = synthetic_chain(4, 4, RoughnessSchedule::Linear);
  const ShCoefficients sh = sh_one_plus_x();
  EngineBake bake;
  bake.prefiltered = &chain;
  bake.sh = &sh;
  bake.irradiance_cube = &lambertian;
  const fs::path dir = temp_dir("khronos_delivered");
  EngineWriteOptions o;
  o.name = "env";
  const EngineWriteResult w = write_engine_files(EngineTarget::KhronosViewer, bake, dir.string(), o);
  // KTX 2.0: the level index at byte 80 (24 bytes a level: offset, length, uncompressed length);
  // level l's six faces of RGBA16F.
  const std::vector<uint8_t> b = read_all(dir / "env_ggx.ktx2");
  ASSERT_EQ(u32(b, 12), 97u) << "VK_FORMAT_R16G16B16A16_SFLOAT";
  CubeLevels decoded;
  decoded.size = chain.size;
  for (size_t l = 0; l < chain.levels.size(); ++l) {
    const uint64_t at = u64(b, 80 + 24 * l), length = u64(b, 80 + 24 * l + 8);
    EXPECT_EQ(length, chain.levels[l].size() * 2);
    std::vector<float> v(chain.levels[l].size());
    for (size_t k = 0; k < v.size(); ++k) {
      Imath::half h;
      h.setBits(uint16_t(b[at + 2 * k] | (b[at + 2 * k + 1] << 8)));
      v[k] = float(h);
    }
    decoded.levels.push_back(std::move(v));
  }
  const EngineFileEntry& e = entry(w, "env_ggx.ktx2");
  EXPECT_EQ(e.format, "RGBA16F");
  expect_entry(e, decoded, chain);
  EXPECT_LE(e.error_max_rel, std::ldexp(1.0, -11) * 1.0001) << "binary16: half a step of 2^-10";
}

// ---- Every target: each file carries its manifest entry's figures -------------------------------

// The key/value pairs of a KTX2 file (KTX 2.0 "Key/Value Data": kvdByteOffset and kvdByteLength at
// bytes 56 and 60; keyAndValueByteLength, key NUL value, padding to 4).
std::vector<std::pair<std::string, std::string>> ktx2_keys(const std::vector<uint8_t>& b) {
  std::vector<std::pair<std::string, std::string>> kv;
  const size_t begin = u32(b, 56), end = begin + u32(b, 60);
  for (size_t at = begin; at < end;) {
    const uint32_t n = u32(b, at);
    const std::string entry(reinterpret_cast<const char*>(&b[at + 4]), n);
    const size_t nul = entry.find('\0');
    std::string value = entry.substr(nul + 1);
    if (!value.empty() && value.back() == '\0') value.pop_back();
    kv.emplace_back(entry.substr(0, nul), value);
    at += 4 + ((n + 3) & ~3u);
  }
  return kv;
}

// What a file records of its entry: rounded up (error_bound_text), never below the entry's number.
void expect_figures(const std::function<std::string(const std::string&)>& recorded, const EngineFileEntry& e) {
  EXPECT_EQ(recorded("error_name"), "error_rms_rel") << e.path;
  EXPECT_EQ(recorded("error_rms_rel"), error_bound_text(e.error_rms_rel)) << e.path;
  EXPECT_EQ(recorded("error_max_rel"), error_bound_text(e.error_max_rel)) << e.path;
  EXPECT_GE(std::stod(recorded("error_rms_rel")), e.error_rms_rel) << e.path;
  std::string per_level;
  for (double v : e.error_rms_rel_per_level) per_level += (per_level.empty() ? "" : " ") + error_bound_text(v);
  EXPECT_EQ(recorded("error_rms_rel_per_level"), per_level) << e.path;
  per_level.clear();
  for (double v : e.error_max_rel_per_level) per_level += (per_level.empty() ? "" : " ") + error_bound_text(v);
  EXPECT_EQ(recorded("error_max_rel_per_level"), per_level) << e.path;
  EXPECT_EQ(recorded("error_definition"), kEngineErrorRmsRelDefinition) << e.path;
  EXPECT_EQ(recorded("error_max_rel_definition"), kEngineErrorMaxRelDefinition) << e.path;
}

// Each target's files read back: a KTX1 or KTX2 file's key/values, a .env's manifest, a .gltf's image
// entries hold the figures of the file's entry (what manifest.json's engine.file_entries writes), and
// its entry's size is the file's with them; the figures are those of the file as written (the keys
// change no texel: the tests above decode the files with their keys).
TEST(EngineDeliveredError, EachFileCarriesItsManifestEntry) {
  const CubeLevels chain = synthetic_chain(8, 1, RoughnessSchedule::Linear);
  const CubeLevels filament_chain = synthetic_chain(8, 1, RoughnessSchedule::Filament);
  const CubeLevels babylon_chain = synthetic_chain(8, 1, RoughnessSchedule::Babylon);
  CubeLevels lambertian = synthetic_chain(4, 4, RoughnessSchedule::Linear);
  const ShCoefficients sh = sh_one_plus_x();
  int ktx1 = 0, ktx2 = 0, env = 0, faces = 0;
  for (const EngineTarget target : {EngineTarget::Generic, EngineTarget::Filament, EngineTarget::Babylon,
                                    EngineTarget::Gltf, EngineTarget::KhronosViewer}) {
    SCOPED_TRACE(engine_target_name(target));
    EngineBake bake;
    bake.prefiltered = target == EngineTarget::Filament  ? &filament_chain
                       : target == EngineTarget::Babylon ? &babylon_chain
                                                         : &chain;
    bake.sh = &sh;
    bake.irradiance_cube = &lambertian;
    const fs::path dir = temp_dir(std::string("carried_") + engine_target_name(target));
    EngineWriteOptions o;
    o.name = "env";
    const EngineWriteResult w = write_engine_files(target, bake, dir.string(), o);
    nlohmann::json gltf_images;
    for (const EngineFileEntry& e : w.entries) {
      const std::vector<uint8_t> b = read_all(dir / e.path);
      EXPECT_EQ(e.bytes, b.size()) << e.path;
      const std::string ext = fs::path(e.path).extension().string();
      if (ext == ".gltf") gltf_images = nlohmann::json::parse(b.begin(), b.end())["images"];
      if (!e.measured) continue;
      if (ext == ".ktx" || ext == ".ktx2") {
        const auto kv = ext == ".ktx" ? ktx1_keys(b) : ktx2_keys(b);
        expect_figures([&](const std::string& k) { return key(kv, "brdfbake:" + k); }, e);
        ++(ext == ".ktx" ? ktx1 : ktx2);
      } else if (ext == ".env") {
        const auto nul = std::find(b.begin() + 8, b.end(), uint8_t(0));
        const nlohmann::json m = nlohmann::json::parse(std::string(b.begin() + 8, nul))["brdfbake"];
        expect_figures([&](const std::string& k) { return m.value(k, std::string("<missing>")); }, e);
        ++env;
      }
    }
    // glTF: each face's figures in its image entry (the PNG files carry none of ours)
    for (const auto& image : gltf_images) {
      const EngineFileEntry& e = entry(w, image["uri"].get<std::string>());
      const nlohmann::json m = image["extras"]["brdfbake"];
      expect_figures([&](const std::string& k) { return m.value(k, std::string("<missing>")); }, e);
      ++faces;
    }
  }
  EXPECT_EQ(ktx1, 2) << "filament's _ibl.ktx and _skybox.ktx";
  EXPECT_EQ(ktx2, 3) << "generic's _ggx.ktx2, khronos-viewer's _ggx.ktx2 and _lambertian.ktx2";
  EXPECT_EQ(env, 1);
  EXPECT_EQ(faces, 6 * chain.level_count());
}

}  // namespace
}  // namespace brdfbake
