// The `filament` target's files as `cmgen -x DIR -f ktx` writes them: NAME_ibl.ktx (the chain, the
// "sh" key), NAME_skybox.ktx and sh.txt; and Filament's SH convention (CubemapSH::preprocessSHForShader).
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/version.hpp"
#include "engines/babylon_frame.hpp"
#include "engines/filament/filament.hpp"
#include "engines/write_common.hpp"
#include "io/babylon_env.hpp"
#include "io/cubemap_io.hpp"
#include "io/ktx1.hpp"
#include "text.hpp"

namespace brdfbake {

std::array<Rgb3, 9> filament_sh(const ShCoefficients& sh) {
  detail::engines::check_sh(sh);
  // Filament: c_k = A_k^F (A_l / pi) L_k^F with Y_k^F = A_k^F poly_k its signed basis, and
  // L_k^F = s_k L_k (s the Condon-Shortley sign), A_k^F = s_k kShBasis[k]: the signs cancel and
  // c_k = kShBasis[k] (A_l / pi) L_k = kShBasis[k] irradiance_over_pi[k] (windowed alike).
  std::array<Rgb3, 9> out{};
  for (size_t k = 0; k < 9; ++k)
    for (size_t c = 0; c < 3; ++c) out[k][c] = detail::engines::kShBasis[k] * sh.irradiance_over_pi[3 * k + c];
  return out;
}

namespace detail::engines::filament {

namespace {

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

}  // namespace

std::vector<OutFile> cmgen_ktx(const EngineSettings& s, const EngineBake& bake, const std::string& name,
                               const EngineWriteOptions& o, Metadata& delivered) {
  const PixelType pixel = o.override_pixel ? o.pixel : s.pixel;
  const std::array<Rgb3, 9> sh = brdfbake::filament_sh(*bake.sh);
  io::Ktx1Options k1;
  k1.filament_r11_gltype = true;

  CubeLevels chain = with_target_metadata(*bake.prefiltered, s);
  chain.set_meta("sh_convention", s.sh_description);
  auto kv = io::cube_key_values(chain, 1);
  kv.emplace_back("sh", filament_sh_key(sh));
  const std::string ibl = name + "_ibl.ktx";
  add_storage_metadata(delivered, ibl, pixel, measure_storage(chain, pixel));
  std::vector<OutFile> files;
  files.push_back({ibl, io::encode_ktx1_cube(chain, pixel, kv, k1), std::make_shared<const CubeLevels>(chain)});

  CubeLevels sky_storage;
  const CubeLevels sky = with_target_metadata(skybox_of(bake, sky_storage), s);
  const std::string skybox = name + "_skybox.ktx";
  add_storage_metadata(delivered, skybox, pixel, measure_storage(sky, pixel));
  files.push_back({skybox, io::encode_ktx1_cube(sky, pixel, io::cube_key_values(sky, 1), k1),
                   std::make_shared<const CubeLevels>(sky)});
  const std::string txt = filament_sh_txt(sh);
  files.push_back({"sh.txt", std::vector<uint8_t>(txt.begin(), txt.end())});
  return files;
}

}  // namespace detail::engines::filament

}  // namespace brdfbake
