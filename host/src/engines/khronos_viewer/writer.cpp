// The `khronos-viewer` target's files as the glTF-IBL-Sampler writes them: NAME_ggx.ktx2,
// NAME_lambertian.ktx2 and (with a Charlie chain) NAME_charlie.ktx2, RGBA16F or ASTC HDR.
#include "brdfbake/error.hpp"
#include "engines/khronos_viewer/khronos_viewer.hpp"
#include "engines/write_common.hpp"

namespace brdfbake::detail::engines::khronos_viewer {

std::vector<OutFile> ibl_sampler_ktx2(const EngineSettings& s, const EngineBake& bake, const std::string& name,
                                      const EngineWriteOptions& o, Metadata& delivered) {
  std::vector<OutFile> files;
  if (!bake.irradiance_cube) throw Error("engine files: khronos-viewer needs the Lambertian (irradiance) cube");
  const PixelType pixel = o.override_pixel ? o.pixel : s.pixel;
  const CubeLevels chain = with_target_metadata(*bake.prefiltered, s);
  files.push_back({name + "_ggx.ktx2", ktx2_cube_bytes(chain, pixel, name + "_ggx.ktx2", o, delivered),
                   std::make_shared<const CubeLevels>(chain)});
  const CubeLevels lambertian = with_target_metadata(*bake.irradiance_cube, s);
  files.push_back({name + "_lambertian.ktx2",
                   ktx2_cube_bytes(lambertian, pixel, name + "_lambertian.ktx2", o, delivered),
                   std::make_shared<const CubeLevels>(lambertian)});
  if (bake.charlie) {
    check_chain(*bake.charlie, s, "Charlie chain");
    const CubeLevels charlie = with_target_metadata(*bake.charlie, s);
    files.push_back({name + "_charlie.ktx2", ktx2_cube_bytes(charlie, pixel, name + "_charlie.ktx2", o, delivered),
                     std::make_shared<const CubeLevels>(charlie)});
  }
  return files;
}

}  // namespace brdfbake::detail::engines::khronos_viewer
