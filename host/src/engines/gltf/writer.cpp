// The `gltf` target's files: NAME.gltf with EXT_lights_image_based (RGBD PNG faces per level, bottom
// row first, the environment mirrored in x for Babylon.js's scenes: engines/babylon_frame.hpp) and the
// extension's irradianceCoefficients.
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/version.hpp"
#include "engines/babylon_frame.hpp"
#include "engines/gltf/gltf.hpp"
#include "engines/write_common.hpp"
#include "io/babylon_env.hpp"
#include "io/cubemap_io.hpp"
#include "io/ktx1.hpp"
#include "text.hpp"

namespace brdfbake {

std::array<Rgb3, 9> gltf_irradiance_coefficients(const ShCoefficients& sh) {
  detail::engines::check_sh(sh);
  // E_lm in the Condon-Shortley basis: s_k A_l w_l L_k = s_k pi irradiance_over_pi[k].
  std::array<Rgb3, 9> out{};
  for (size_t k = 0; k < 9; ++k)
    for (size_t c = 0; c < 3; ++c)
      out[k][c] = detail::engines::kCondonShortley[k] * math::kPi * sh.irradiance_over_pi[3 * k + c];
  return out;
}

namespace detail::engines::gltf {

std::vector<OutFile> ext_lights_image_based(const EngineSettings& s, const EngineBake& bake, const std::string& name,
                                            const EngineWriteOptions& o, Metadata& delivered) {
  if (!(o.intensity >= 0.0) || !std::isfinite(o.intensity)) throw Error("engine files: intensity must be >= 0");
  // Babylon.js's frame (babylon_frame.hpp): the environment mirrored in x; the rotation by scene
  CubeLevels chain = with_target_metadata(brdfbake::detail::mirror_cube_x(*bake.prefiltered), s);
  chain.set_meta("babylon_scene", brdfbake::detail::gltf_scene_name(o.gltf_scene));
  chain.set_meta("frame", kBabylonFrame);
  chain.set_meta("face_rows", "bottom row first (Babylon.js reads row 0 of a face image as its last row)");
  std::vector<OutFile> files;
  nlohmann::ordered_json images = nlohmann::ordered_json::array();
  nlohmann::ordered_json specular = nlohmann::ordered_json::array();
  RgbdStats stats;
  const auto values = std::make_shared<const CubeLevels>(chain);
  for (int l = 0; l < chain.level_count(); ++l) {
    nlohmann::ordered_json faces = nlohmann::ordered_json::array();
    for (int f = 0; f < 6; ++f) {
      const std::string file = name + "_specular_" + std::to_string(l) + "_" + kFaceNames[f] + ".png";
      files.push_back({file, rgbd_face_png(chain, l, f, stats), values, l, f});
      faces.push_back(images.size());
      images.push_back({{"uri", file}, {"mimeType", "image/png"}});
    }
    specular.push_back(faces);
  }
  nlohmann::ordered_json coefficients = nlohmann::ordered_json::array();
  const std::array<Rgb3, 9> irradiance = gltf_irradiance_coefficients(*bake.sh);
  for (const Rgb3& c : brdfbake::detail::mirror_gltf_coefficients_x(irradiance)) coefficients.push_back(c);
  nlohmann::ordered_json light;
  light["name"] = name;
  light["intensity"] = o.intensity;  // always written: Babylon's loader scales the SH by it unchecked
  light["rotation"] = brdfbake::detail::gltf_scene_rotation(o.gltf_scene);
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

}  // namespace detail::engines::gltf

}  // namespace brdfbake
