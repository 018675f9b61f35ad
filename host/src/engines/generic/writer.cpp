// The `generic` target's files: NAME_ggx.ktx2 (RGBA16F, or ASTC HDR) and NAME_sh.json, brdfbake's
// own runtime convention (docs/CONVENTIONS.md).
#include "engines/generic/generic.hpp"
#include "engines/write_common.hpp"

namespace brdfbake::detail::engines::generic {

std::vector<OutFile> write(const EngineSettings& s, const EngineBake& bake, const std::string& name,
                           const EngineWriteOptions& o, Metadata& delivered) {
  std::vector<OutFile> files;
  const CubeLevels chain = with_target_metadata(*bake.prefiltered, s);
  const PixelType pixel = o.override_pixel ? o.pixel : s.pixel;
  files.push_back({name + "_ggx.ktx2", ktx2_cube_bytes(chain, pixel, name + "_ggx.ktx2", o, delivered),
                   std::make_shared<const CubeLevels>(chain)});
  const std::string json = sh_to_json(*bake.sh, chain.metadata);
  files.push_back({name + "_sh.json", std::vector<uint8_t>(json.begin(), json.end())});
  return files;
}

}  // namespace brdfbake::detail::engines::generic
