// write_engine_files: each target's file set (brdfbake/engines.hpp, docs/ENGINES.md). Every file is
// encoded in memory first, then all are written to temporaries in the output folder and renamed
// into place together, so a failure leaves the folder as it was (and removes it if we made it).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "brdfbake/engines.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/version.hpp"
#include "engines/babylon_frame.hpp"
#include "families/delivery.hpp"
#include "io/astc_ktx2.hpp"
#include "io/atomic_file.hpp"
#include "io/babylon_env.hpp"
#include "io/cubemap_io.hpp"
#include "io/half.hpp"
#include "io/ktx2.hpp"
#include "io/packed_float.hpp"
#include "io/png_rgbd.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;
const char* const kFaceNames[6] = {"px", "nx", "py", "ny", "pz", "nz"};
const char* const kBabylonFrame =
    "the environment mirrored in x, (x, y, z) -> (-x, y, z): Babylon.js's left-handed world, into which its loaders "
    "mirror right-handed content (the glTF loader's root, HDRCubeTexture)";

struct OutFile {
  std::string name;
  std::vector<uint8_t> bytes;
};

std::string fmt(double v, const char* f = "%.4g") {
  char buf[48];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

bool is_power_of_two(int v) { return v > 0 && (v & (v - 1)) == 0; }

// The stored-value error of a container format, measured on every R, G, B of every level.
struct StorageError {
  std::vector<double> max_rel;  // per level: max |stored - value| / |value| over values > 0
  std::vector<double> max_abs;
  size_t clamped = 0;
};

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

const char* pixel_name(PixelType p) {
  return p == PixelType::F16 ? "RGBA16F" : p == PixelType::F32 ? "RGBA32F" : "R11F_G11F_B10F";
}

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
  storage.metadata = bake.prefiltered->metadata;
  storage.set_meta("kind", "skybox (level 0 of the prefiltered chain: the source cube)");
  storage.set_meta("levels", "1");
  return storage;
}

// ---- KTX2 ----------------------------------------------------------------------------------------

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

// ---- Filament -----------------------------------------------------------------------------------

// The KTX1 "sh" value and sh.txt, as cmgen writes them (9 lines of "r g b"; sh.txt in cmgen's
// outputSh layout), with 9 significant digits instead of cmgen's stream default of 6.
std::string filament_sh_key(const std::array<Rgb3, 9>& sh) {
  std::string s;
  for (const Rgb3& c : sh) s += fmt(c[0], "%.9g") + " " + fmt(c[1], "%.9g") + " " + fmt(c[2], "%.9g") + "\n";
  return s;
}

std::string filament_sh_txt(const std::array<Rgb3, 9>& sh) {
  static const char* const kNames[9] = {"L00", "L1-1", "L10", "L11", "L2-2", "L2-1", "L20", "L21", "L22"};
  std::string s;
  for (size_t k = 0; k < 9; ++k)
    s += "(" + fmt(sh[k][0], "%18.15f") + ", " + fmt(sh[k][1], "%18.15f") + ", " + fmt(sh[k][2], "%18.15f") + "); // " +
         kNames[k] + ", irradiance, pre-scaled base\n";
  return s;
}

std::vector<OutFile> filament_files(const EngineSettings& s, const EngineBake& bake, const std::string& name,
                                    const EngineWriteOptions& o, Metadata& delivered) {
  const PixelType pixel = o.override_pixel ? o.pixel : s.pixel;
  const std::array<Rgb3, 9> sh = filament_sh(*bake.sh);
  io::Ktx1Options k1;
  k1.filament_r11_gltype = true;

  CubeLevels chain = with_target_metadata(*bake.prefiltered, s);
  chain.set_meta("sh_convention", s.sh_description);
  auto kv = io::cube_key_values(chain, 1);
  kv.emplace_back("sh", filament_sh_key(sh));
  const std::string ibl = name + "_ibl.ktx";
  add_storage_metadata(delivered, ibl, pixel, measure_storage(chain, pixel));
  std::vector<OutFile> files;
  files.push_back({ibl, io::encode_ktx1_cube(chain, pixel, kv, k1)});

  CubeLevels sky_storage;
  const CubeLevels sky = with_target_metadata(skybox_of(bake, sky_storage), s);
  const std::string skybox = name + "_skybox.ktx";
  add_storage_metadata(delivered, skybox, pixel, measure_storage(sky, pixel));
  files.push_back({skybox, io::encode_ktx1_cube(sky, pixel, io::cube_key_values(sky, 1), k1)});
  const std::string txt = filament_sh_txt(sh);
  files.push_back({"sh.txt", std::vector<uint8_t>(txt.begin(), txt.end())});
  return files;
}

// ---- RGBD PNG faces (glTF, Babylon) ---------------------------------------------------------------

struct RgbdStats {
  double max_rel = 0.0;  // max |decoded - value| / max channel of the texel
  size_t clamped = 0;
};

// One face of one level as Babylon.js reads it: bottom row first (babylon_frame.hpp).
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

std::vector<OutFile> gltf_files(const EngineSettings& s, const EngineBake& bake, const std::string& name,
                                const EngineWriteOptions& o, Metadata& delivered) {
  if (!(o.intensity >= 0.0) || !std::isfinite(o.intensity)) throw Error("engine files: intensity must be >= 0");
  // Babylon.js's frame (babylon_frame.hpp): the environment mirrored in x; the rotation by scene
  CubeLevels chain = with_target_metadata(detail::mirror_cube_x(*bake.prefiltered), s);
  chain.set_meta("babylon_scene", detail::gltf_scene_name(o.gltf_scene));
  chain.set_meta("frame", kBabylonFrame);
  chain.set_meta("face_rows", "bottom row first (Babylon.js reads row 0 of a face image as its last row)");
  std::vector<OutFile> files;
  nlohmann::ordered_json images = nlohmann::ordered_json::array();
  nlohmann::ordered_json specular = nlohmann::ordered_json::array();
  RgbdStats stats;
  for (int l = 0; l < chain.level_count(); ++l) {
    nlohmann::ordered_json faces = nlohmann::ordered_json::array();
    for (int f = 0; f < 6; ++f) {
      const std::string file = name + "_specular_" + std::to_string(l) + "_" + kFaceNames[f] + ".png";
      files.push_back({file, rgbd_face_png(chain, l, f, stats)});
      faces.push_back(images.size());
      images.push_back({{"uri", file}, {"mimeType", "image/png"}});
    }
    specular.push_back(faces);
  }
  nlohmann::ordered_json coefficients = nlohmann::ordered_json::array();
  const std::array<Rgb3, 9> irradiance = gltf_irradiance_coefficients(*bake.sh);
  for (const Rgb3& c : detail::mirror_gltf_coefficients_x(irradiance)) coefficients.push_back(c);
  nlohmann::ordered_json light;
  light["name"] = name;
  light["intensity"] = o.intensity;  // always written: Babylon's loader scales the SH by it unchecked
  light["rotation"] = detail::gltf_scene_rotation(o.gltf_scene);
  light["irradianceCoefficients"] = coefficients;
  light["specularImageSize"] = chain.size;
  light["specularImages"] = specular;

  Metadata meta = chain.metadata;
  meta.emplace_back("sh_convention", s.sh_description);
  nlohmann::ordered_json gltf;
  gltf["asset"] = {{"version", "2.0"},
                   {"generator", std::string("brdfbake ") + kVersion},
                   {"extras", {{"brdfbake", metadata_json(meta)}}}};
  gltf["extensionsUsed"] = {"EXT_lights_image_based"};
  gltf["scene"] = 0;
  gltf["scenes"] = {{{"extensions", {{"EXT_lights_image_based", {{"light", 0}}}}}}};
  gltf["images"] = images;
  gltf["extensions"] = {{"EXT_lights_image_based", {{"lights", {light}}}}};
  const std::string text = gltf.dump(2) + "\n";
  files.insert(files.begin(), OutFile{name + ".gltf", std::vector<uint8_t>(text.begin(), text.end())});
  add_rgbd_metadata(delivered, name + "_specular_*.png", stats);
  return files;
}

std::vector<OutFile> babylon_files(const EngineSettings& s, const EngineBake& bake, const std::string& name,
                                   Metadata& delivered) {
  // Babylon.js's frame (babylon_frame.hpp): the environment and its polynomial mirrored in x
  CubeLevels chain = with_target_metadata(detail::mirror_cube_x(*bake.prefiltered), s);
  chain.set_meta("frame", kBabylonFrame);
  io::BabylonEnv env;
  env.width = chain.size;
  env.lod_generation_scale = kBabylonLodGenerationScale;
  const std::array<Rgb3, 9> p = detail::mirror_babylon_polynomial_x(babylon_polynomial(*bake.sh));
  for (size_t k = 0; k < 9; ++k) env.polynomial[k] = p[k];
  RgbdStats stats;
  for (int l = 0; l < chain.level_count(); ++l)
    for (int f = 0; f < 6; ++f) env.images.push_back(rgbd_face_png(chain, l, f, stats));
  Metadata meta = chain.metadata;
  meta.emplace_back("sh_convention", s.sh_description);
  meta.emplace_back("face_rows", "bottom row first (Babylon.js reads row 0 of a face image as its last row)");
  meta.emplace_back("rgbd_max_error_rel_to_texel_max", detail::bound_text(stats.max_rel));
  meta.emplace_back("rgbd_clamped_texels", std::to_string(stats.clamped));
  env.extra["brdfbake"] = metadata_json(meta);
  add_rgbd_metadata(delivered, name + ".env", stats);
  return {{name + ".env", io::encode_babylon_env(env)}};
}

// ---- The folder ----------------------------------------------------------------------------------

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

EngineWriteResult write_engine_files(EngineTarget target, const EngineBake& bake, const std::string& out_dir,
                                     const EngineWriteOptions& o) {
  const EngineSettings s = engine_settings(target);
  if (!bake.prefiltered) throw Error("engine files: no prefiltered chain");
  check_chain(*bake.prefiltered, s, "prefiltered chain");
  if (!bake.sh && target != EngineTarget::KhronosViewer)
    throw Error(std::string("engine files: ") + engine_target_name(target) + " needs the irradiance SH");
  if (!(o.astc_quality >= 0.0 && o.astc_quality <= 100.0))
    throw Error("engine files: astc_quality must be in [0, 100]");
  if (o.astc != AstcBlock::None && target != EngineTarget::Generic && target != EngineTarget::KhronosViewer)
    throw Error(std::string("engine files: ASTC applies to KTX2 targets (generic, khronos-viewer), not ") +
                engine_target_name(target));
  if (o.override_pixel && o.pixel == PixelType::R11G11B10 && target != EngineTarget::Filament)
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
    switch (target) {
      case EngineTarget::Generic: {
        const CubeLevels chain = with_target_metadata(*bake.prefiltered, s);
        const PixelType pixel = o.override_pixel ? o.pixel : s.pixel;
        files.push_back({name + "_ggx.ktx2", ktx2_cube_bytes(chain, pixel, name + "_ggx.ktx2", o, result.delivered)});
        const std::string json = sh_to_json(*bake.sh, chain.metadata);
        files.push_back({name + "_sh.json", std::vector<uint8_t>(json.begin(), json.end())});
        break;
      }
      case EngineTarget::Filament:
        files = filament_files(s, bake, name, o, result.delivered);
        break;
      case EngineTarget::Gltf:
        files = gltf_files(s, bake, name, o, result.delivered);
        break;
      case EngineTarget::Babylon:
        files = babylon_files(s, bake, name, result.delivered);
        break;
      case EngineTarget::KhronosViewer: {
        if (!bake.irradiance_cube) throw Error("engine files: khronos-viewer needs the Lambertian (irradiance) cube");
        const PixelType pixel = o.override_pixel ? o.pixel : s.pixel;
        const CubeLevels chain = with_target_metadata(*bake.prefiltered, s);
        files.push_back({name + "_ggx.ktx2", ktx2_cube_bytes(chain, pixel, name + "_ggx.ktx2", o, result.delivered)});
        const CubeLevels lambertian = with_target_metadata(*bake.irradiance_cube, s);
        files.push_back({name + "_lambertian.ktx2",
                         ktx2_cube_bytes(lambertian, pixel, name + "_lambertian.ktx2", o, result.delivered)});
        if (bake.charlie) {
          check_chain(*bake.charlie, s, "Charlie chain");
          const CubeLevels charlie = with_target_metadata(*bake.charlie, s);
          files.push_back(
              {name + "_charlie.ktx2", ktx2_cube_bytes(charlie, pixel, name + "_charlie.ktx2", o, result.delivered)});
        }
        break;
      }
    }
  } catch (const Error& e) {
    io::throw_write_error(out_dir, e.what());
  }
  write_all(out_dir, files, result.files);
  return result;
}

}  // namespace brdfbake
