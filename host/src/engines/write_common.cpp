// write_engine_files and what every target's writer shares (write_common.hpp). Every file is encoded
// in memory first (the target's writer.cpp), then all are written to temporaries in the output folder
// and renamed into place together, so a failure leaves the folder as it was (and removes it if we
// made it).
#include "engines/write_common.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>

#include "brdfbake/error.hpp"
#include "brdfbake/error_figures.hpp"
#include "io/astc_ktx2.hpp"
#include "io/atomic_file.hpp"
#include "io/babylon_env.hpp"
#include "io/cubemap_io.hpp"
#include "io/gpu_cube_read.hpp"
#include "io/half.hpp"
#include "io/ktx1.hpp"
#include "io/ktx2.hpp"
#include "io/packed_float.hpp"
#include "io/png_rgbd.hpp"
#include "text.hpp"

namespace brdfbake {
namespace detail::engines {

namespace fs = std::filesystem;

std::string fmt(double v, const char* f) {
  char buf[48];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

bool is_power_of_two(int v) { return v > 0 && (v & (v - 1)) == 0; }

StorageError measure_storage(const CubeLevels& cube, PixelType pixel) {
  StorageError e;
  for (const auto& level : cube.levels) {
    double max_rel = 0.0, max_abs = 0.0;
    for (size_t t = 0; t < level.size() / 4; ++t) {
      float stored[3];
      if (pixel == PixelType::R11G11B10) {
        int sat = 0;
        io::unpack_r11g11b10(io::pack_r11g11b10(level[4 * t], level[4 * t + 1], level[4 * t + 2], &sat), stored);
        e.clamped += size_t(sat);
      } else {
        for (size_t c = 0; c < 3; ++c)
          stored[c] = pixel == PixelType::F16 ? io::half_bits_to_float(io::float_to_half_bits(level[4 * t + c]))
                                              : level[4 * t + c];
      }
      for (size_t c = 0; c < 3; ++c) {
        const double v = level[4 * t + c], err = std::fabs(double(stored[c]) - v);
        if (!std::isfinite(stored[c])) ++e.clamped;
        max_abs = std::max(max_abs, err);
        if (v > 0.0) max_rel = std::max(max_rel, err / v);
      }
    }
    e.max_rel.push_back(max_rel);
    e.max_abs.push_back(max_abs);
  }
  return e;
}

namespace {
const char* pixel_name(PixelType p) {
  return p == PixelType::F16 ? "RGBA16F" : p == PixelType::F32 ? "RGBA32F" : "R11F_G11F_B10F";
}
}  // namespace

void add_storage_metadata(Metadata& delivered, const std::string& file, PixelType pixel, const StorageError& e) {
  delivered.emplace_back(file + ": format", pixel_name(pixel));
  delivered.emplace_back(file + ": storage_max_rel_error_per_level", detail::bounds_text(e.max_rel));
  delivered.emplace_back(file + ": storage_max_abs_error_per_level", detail::bounds_text(e.max_abs));
  delivered.emplace_back(file + ": storage_clamped_channels", std::to_string(e.clamped));
}

// The chain's metadata plus what the target adds.
CubeLevels with_target_metadata(const CubeLevels& cube, const EngineSettings& s) {
  CubeLevels out = cube;
  out.set_meta("engine_target", engine_target_name(s.target));
  out.set_meta("engine", s.engine);
  out.set_meta("engine_lod_from_roughness", s.lod_formula);
  out.set_meta("engine_schedule_source", s.schedule_source);
  return out;
}

void check_chain(const CubeLevels& cube, const EngineSettings& s, const char* what) {
  if (cube.size < 1 || cube.levels.empty()) throw Error(std::string("engine files: the ") + what + " is empty");
  const std::string schedule = cube.meta("roughness_schedule");
  if (cube.level_count() > 1 && schedule != roughness_schedule_name(s.schedule))
    throw Error(std::string("engine files: the ") + what + " was baked with the '" +
                (schedule.empty() ? "unknown" : schedule) + "' schedule; " + engine_target_name(s.target) +
                " reads its levels with the '" + roughness_schedule_name(s.schedule) + "' schedule (" + s.lod_formula +
                ")");
  if (s.power_of_two && !is_power_of_two(cube.size))
    throw Error(std::string("engine files: ") + engine_target_name(s.target) + " needs a power-of-two face size, not " +
                std::to_string(cube.size));
  if (s.min_size == 1 && cube.level_size(cube.level_count() - 1) != 1)
    throw Error(std::string("engine files: ") + engine_target_name(s.target) +
                " stores the full chain down to 1x1; the " + what + " stops at " +
                std::to_string(cube.level_size(cube.level_count() - 1)) + "x" +
                std::to_string(cube.level_size(cube.level_count() - 1)) + " (bake with min_size 1)");
}

const CubeLevels& skybox_of(const EngineBake& bake, CubeLevels& storage) {
  if (bake.skybox) return *bake.skybox;
  storage = CubeLevels{};
  storage.size = bake.prefiltered->size;
  storage.levels = {bake.prefiltered->levels.front()};
  // Level 0's own metadata: what describes the chain's other levels (its roughness schedule and the
  // engine's LOD from roughness, per-level lists) does not describe a one-level skybox.
  static const char* const kChainOnly[] = {"roughness_schedule",   "lod_from_roughness", "roughness_of_level",
                                           "roughness_per_level",  "min_size",           "subdivision_per_level",
                                           "refinement_per_level", "samples_per_level",  "bound_samples_per_level"};
  for (const auto& [key, value] : bake.prefiltered->metadata)
    if (std::find(std::begin(kChainOnly), std::end(kChainOnly), key) == std::end(kChainOnly))
      storage.metadata.emplace_back(key, value);
  storage.set_meta("kind", "skybox (level 0 of the prefiltered chain: the source cube)");
  storage.set_meta("levels", "1");
  return storage;
}

std::vector<uint8_t> ktx2_cube_bytes(const CubeLevels& cube, PixelType pixel, const std::string& name,
                                     const EngineWriteOptions& o, Metadata& delivered) {
  if (o.astc != AstcBlock::None) {
    const int block = o.astc == AstcBlock::Astc4x4 ? 4 : 6;
    const io::AstcCube astc = io::compress_astc_cube(cube, block, o.astc_quality);
    delivered.emplace_back(name + ": format", "ASTC " + std::to_string(block) + "x" + std::to_string(block) + " HDR");
    delivered.emplace_back(name + ": astc_max_rel_error_per_level", detail::bounds_text(astc.max_rel_error));
    delivered.emplace_back(name + ": astc_rms_rel_error_per_level", detail::bounds_text(astc.rms_rel_error));
    delivered.emplace_back(name + ": astc_max_abs_error_per_level", detail::bounds_text(astc.max_abs_error));
    delivered.emplace_back(name + ": astc_clamped_channels", std::to_string(astc.clamped));
    return io::astc_ktx2_bytes(cube, astc, o.astc_quality);
  }
  if (pixel == PixelType::R11G11B10) throw Error("engine files: " + name + ": KTX2 takes f16 or f32 (or ASTC)");
  io::Ktx2Image image;
  image.vk_format = pixel == PixelType::F16 ? io::kVkFormatR16G16B16A16Sfloat : io::kVkFormatR32G32B32A32Sfloat;
  image.width = image.height = uint32_t(cube.size);
  image.faces = 6;
  image.levels = uint32_t(cube.level_count());
  image.level_data = io::cube_level_bytes(cube, pixel);
  image.key_values = io::cube_key_values(cube, 2);
  add_storage_metadata(delivered, name, pixel, measure_storage(cube, pixel));
  return io::encode_ktx2(image);
}

std::vector<uint8_t> rgbd_face_png(const CubeLevels& cube, int level, int face, RgbdStats& stats) {
  const int s = cube.level_size(level);
  std::vector<uint8_t> rgba(size_t(s) * size_t(s) * 4);
  for (int j = 0; j < s; ++j)
    for (int i = 0; i < s; ++i) {
      const float* t = cube.texel(level, face, i, j);
      uint8_t* p = &rgba[4 * (size_t(s - 1 - j) * size_t(s) + size_t(i))];
      bool clamped = false;
      io::rgbd_encode(t, p, &clamped);
      if (clamped) ++stats.clamped;
      double d[3];
      io::rgbd_decode(p, d);
      const double m = std::max({double(t[0]), double(t[1]), double(t[2]), 1e-30});
      for (int c = 0; c < 3; ++c) stats.max_rel = std::max(stats.max_rel, std::fabs(d[c] - double(t[c])) / m);
    }
  return io::encode_png_rgba8(s, s, rgba);
}

void add_rgbd_metadata(Metadata& delivered, const std::string& file, const RgbdStats& st) {
  delivered.emplace_back(file + ": format", "PNG RGBD 8-bit (Babylon.js toRGBD)");
  delivered.emplace_back(file + ": rgbd_max_error_rel_to_texel_max", detail::bound_text(st.max_rel));
  delivered.emplace_back(file + ": rgbd_clamped_texels",
                         std::to_string(st.clamped) + " (values above 255 are clamped)");
}

nlohmann::ordered_json metadata_json(const Metadata& m) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const auto& [k, v] : m) j[k] = v;
  return j;
}

void check_sh(const ShCoefficients& sh) {
  if (sh.order < 3 || sh.irradiance_over_pi.size() < 27)
    throw Error("engine SH: need at least 3 bands (9 RGB coefficients), have " + std::to_string(sh.order));
  for (size_t i = 0; i < 27; ++i)
    if (!std::isfinite(sh.irradiance_over_pi[i])) throw Error("engine SH: a coefficient is not finite");
}

namespace {

// Sums of one level (or one face of it) decoded against its values: R, G, B of `texels` texels.
struct LevelSums {
  double squared_error = 0.0, squared_value = 0.0, max_rel = 0.0;
  void add(const float* decoded, const float* value, size_t texels, double level_max) {
    const double floor = 1e-6 * level_max;
    for (size_t t = 0; t < texels; ++t) {
      const float* d = decoded + 4 * t;
      const float* v = value + 4 * t;
      const double scale = std::max({double(v[0]), double(v[1]), double(v[2]), floor});
      for (int c = 0; c < 3; ++c) {
        const double e = double(d[c]) - double(v[c]);
        squared_error += e * e;
        squared_value += double(v[c]) * double(v[c]);
        if (scale > 0.0) max_rel = std::max(max_rel, std::fabs(e) / scale);
        if (!std::isfinite(d[c])) max_rel = std::numeric_limits<double>::infinity();
      }
    }
  }
  double rms_rel() const {
    return squared_value > 0.0 ? std::sqrt(squared_error / squared_value) : squared_error > 0.0 ? 1.0 : 0.0;
  }
};

double level_max(const std::vector<float>& level) {
  double m = 0.0;
  for (size_t t = 0; t < level.size() / 4; ++t)
    for (size_t c = 0; c < 3; ++c) m = std::max(m, double(level[4 * t + c]));
  return m;
}

std::string file_format(const std::string& name) {
  const std::string ext = fs::path(name).extension().string();
  return ext == ".json" || ext == ".gltf" ? "JSON" : "text";
}

}  // namespace

// The file's size and, where it holds texel values, its delivered error: its bytes decoded as the
// engine decodes them (io/gpu_cube_read.hpp), never through the encoder's own round trip.
EngineFileEntry measure_engine_file(const OutFile& f) {
  EngineFileEntry e;
  e.path = f.name;
  e.bytes = f.bytes.size();
  if (!f.values) {
    e.format = file_format(f.name);
    return e;
  }
  const CubeLevels& values = *f.values;
  LevelSums file;
  if (f.face >= 0) {  // one RGBD face image of one level
    const int s = values.level_size(f.level);
    const std::vector<float> decoded = io::decode_rgbd_face(f.bytes, s, "'" + f.name + "'");
    const size_t texels = size_t(s) * size_t(s);
    const std::vector<float>& level = values.levels[size_t(f.level)];
    file.add(decoded.data(), level.data() + 4 * texels * size_t(f.face), texels, level_max(level));
    e.format = "PNG RGBD 8-bit";
    e.values = "level " + std::to_string(f.level) + ", face " + kFaceNames[f.face];
  } else {
    CubeLevels decoded;
    if (fs::path(f.name).extension() == ".env") {
      const io::BabylonEnv env = io::decode_babylon_env(f.bytes);
      std::vector<std::vector<std::vector<uint8_t>>> faces;
      for (size_t k = 0; k < env.images.size(); ++k) {
        if (k % 6 == 0) faces.emplace_back();
        faces.back().push_back(env.images[k]);
      }
      decoded = io::decode_rgbd_cube(faces, env.width, "'" + f.name + "'");
      e.format = "RGBD PNG faces (.env)";
    } else {
      decoded = io::decode_gpu_cube(f.bytes, "'" + f.name + "'", &e.format);
    }
    if (decoded.levels.size() != values.levels.size() || decoded.size != values.size)
      throw Error("engine files: '" + f.name + "' decodes to " + std::to_string(decoded.levels.size()) + " levels of " +
                  std::to_string(decoded.size) + ", not the " + std::to_string(values.levels.size()) + " of " +
                  std::to_string(values.size) + " it encodes");
    for (size_t l = 0; l < values.levels.size(); ++l) {
      const std::vector<float>& level = values.levels[l];
      if (decoded.levels[l].size() != level.size())
        throw Error("engine files: '" + f.name + "': level " + std::to_string(l) + " decodes to another size");
      LevelSums one;
      one.add(decoded.levels[l].data(), level.data(), level.size() / 4, level_max(level));
      e.error_rms_rel_per_level.push_back(one.rms_rel());
      e.error_max_rel_per_level.push_back(one.max_rel);
      file.squared_error += one.squared_error;
      file.squared_value += one.squared_value;
      file.max_rel = std::max(file.max_rel, one.max_rel);
    }
    e.values = values.level_count() > 1 ? std::to_string(values.level_count()) + " levels" : "1 level";
  }
  e.measured = true;
  e.error_rms_rel = file.rms_rel();
  e.error_max_rel = file.max_rel;
  if (f.face >= 0) {
    e.error_rms_rel_per_level = {e.error_rms_rel};
    e.error_max_rel_per_level = {e.error_max_rel};
  }
  return e;
}

namespace {

// A file's delivered error as its own metadata records it (docs/CONVENTIONS.md, "Error figures"): the
// manifest entry's figures under their names, rounded up as every recorded bound is.
Metadata error_metadata(const EngineFileEntry& e) {
  return {{"error_name", kEngineErrorName},
          {kEngineErrorName, bound_text(e.error_rms_rel)},
          {kEngineErrorMaxName, bound_text(e.error_max_rel)},
          {std::string(kEngineErrorName) + "_per_level", bounds_text(e.error_rms_rel_per_level)},
          {std::string(kEngineErrorMaxName) + "_per_level", bounds_text(e.error_max_rel_per_level)},
          {"error_definition", kEngineErrorRmsRelDefinition},
          {std::string(kEngineErrorMaxName) + "_definition", kEngineErrorMaxRelDefinition},
          {"error_measurement", "this file (" + e.format + ", " + e.values +
                                    ") decoded as the engine decodes it, measured before these keys were added: "
                                    "they change no texel"}};
}

// `f` with its delivered error in its container's metadata, where the container has any: KTX1 and
// KTX2 key/values (brdfbake:NAME), the .env's manifest (its "brdfbake" member). The error depends
// on the texels alone, measured before (measure_engine_file), so the keys can hold it. An RGBD face
// PNG carries none (the .gltf's image entries do: with_face_errors).
void carry_error(OutFile& f, const EngineFileEntry& e) {
  const std::string ext = fs::path(f.name).extension().string();
  const Metadata meta = error_metadata(e);
  if (ext == ".ktx" || ext == ".ktx2") {
    std::vector<std::pair<std::string, std::string>> kv;
    for (const auto& [k, v] : meta) kv.emplace_back("brdfbake:" + k, v);
    f.bytes = ext == ".ktx" ? io::ktx1_with_key_values(f.bytes, kv, f.name) : io::ktx2_with_key_values(f.bytes, kv);
  } else if (ext == ".env") {
    io::BabylonEnv env = io::decode_babylon_env(f.bytes);
    for (const auto& [k, v] : meta) env.extra["brdfbake"][k] = v;
    f.bytes = io::encode_babylon_env(env);
  }
}

// A .gltf with each RGBD face's delivered error in its image's extras ("brdfbake"), by the face's
// entry.
void with_face_errors(OutFile& gltf, const std::vector<EngineFileEntry>& entries) {
  nlohmann::ordered_json j = nlohmann::ordered_json::parse(gltf.bytes.begin(), gltf.bytes.end());
  if (!j.contains("images") || !j["images"].is_array()) return;
  for (auto& image : j["images"]) {
    if (!image.contains("uri") || !image["uri"].is_string()) continue;
    for (const EngineFileEntry& e : entries)
      if (e.measured && e.path == image["uri"].get<std::string>())
        image["extras"]["brdfbake"] = metadata_json(error_metadata(e));
  }
  const std::string text = j.dump(2) + "\n";
  gltf.bytes.assign(text.begin(), text.end());
}

void write_all(const std::string& out_dir, const std::vector<OutFile>& files, std::vector<std::string>& written) {
  std::error_code ec;
  const bool existed = fs::is_directory(out_dir, ec);
  if (!existed && fs::exists(out_dir, ec)) io::throw_write_error(out_dir, "exists and is not a folder");
  if (!existed && !fs::create_directories(out_dir, ec))
    io::throw_write_error(out_dir, ec ? ec.message() : "cannot create");
  try {
    std::vector<std::unique_ptr<io::TempFile>> temps;
    for (const OutFile& f : files) {
      const std::string path = (fs::path(out_dir) / f.name).string();
      temps.push_back(std::make_unique<io::TempFile>(path));
      io::write_bytes(*temps.back(), std::string_view(reinterpret_cast<const char*>(f.bytes.data()), f.bytes.size()));
    }
    for (auto& t : temps) {
      t->commit();
      written.push_back(t->destination());
    }
  } catch (...) {
    if (!existed) fs::remove_all(out_dir, ec);
    throw;
  }
}

}  // namespace

}  // namespace detail::engines

using namespace detail::engines;

EngineWriteResult write_engine_files(EngineTarget target, const EngineBake& bake, const std::string& out_dir,
                                     const EngineWriteOptions& o) {
  const TargetDef& def = target_def(target);
  const EngineSettings s = def.settings();
  if (!bake.prefiltered) throw Error("engine files: no prefiltered chain");
  check_chain(*bake.prefiltered, s, "prefiltered chain");
  if (!bake.sh && def.needs_sh)
    throw Error(std::string("engine files: ") + engine_target_name(target) + " needs the irradiance SH");
  if (!(o.astc_quality >= 0.0 && o.astc_quality <= 100.0))
    throw Error("engine files: astc_quality must be in [0, 100]");
  if (o.astc != AstcBlock::None && !def.astc) {
    std::string ktx2;
    for (const TargetDef* t : targets())
      if (t->astc) ktx2 += std::string(ktx2.empty() ? "" : ", ") + t->name;
    throw Error("engine files: ASTC applies to KTX2 targets (" + ktx2 + "), not " + engine_target_name(target));
  }
  if (o.override_pixel && o.pixel == PixelType::R11G11B10 && s.pixel != PixelType::R11G11B10)
    throw Error("engine files: R11F_G11F_B10F is Filament's KTX1 format");
  std::string name = o.name;
  if (name.empty()) {
    name = fs::path(out_dir).lexically_normal().filename().string();
    if (name.empty() || name == "." || name == "..")
      name = fs::path(out_dir).lexically_normal().parent_path().filename().string();
    if (name.empty() || name == "." || name == "..") name = "environment";
  }
  if (name.find('/') != std::string::npos) throw Error("engine files: the base name '" + name + "' contains '/'");

  EngineWriteResult result;
  std::vector<OutFile> files;
  try {
    files = def.write(s, bake, name, o, result.delivered);  // the target's writer.cpp
  } catch (const Error& e) {
    io::throw_write_error(out_dir, e.what());
  }
  try {
    // Each file measured, then its figures written into it where its container has metadata (its
    // size is the file's with them).
    for (OutFile& f : files) {
      result.entries.push_back(measure_engine_file(f));
      if (result.entries.back().measured) carry_error(f, result.entries.back());
    }
    for (size_t k = 0; k < files.size(); ++k) {
      if (fs::path(files[k].name).extension() == ".gltf") with_face_errors(files[k], result.entries);
      result.entries[k].bytes = files[k].bytes.size();
    }
  } catch (const Error& e) {
    io::throw_write_error(out_dir, e.what());
  }
  write_all(out_dir, files, result.files);
  return result;
}

}  // namespace brdfbake
