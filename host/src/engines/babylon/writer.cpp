// The `babylon` target's file as Babylon.js's EnvironmentTextureTools.CreateEnvTextureAsync writes
// one: NAME.env, RGBD PNG faces per level (bottom row first), the full chain, the irradiance as
// Babylon's spherical polynomial; the environment mirrored in x (engines/babylon_frame.hpp).
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/version.hpp"
#include "engines/babylon/babylon.hpp"
#include "engines/babylon_frame.hpp"
#include "engines/write_common.hpp"
#include "io/babylon_env.hpp"
#include "io/cubemap_io.hpp"
#include "io/ktx1.hpp"
#include "text.hpp"

namespace brdfbake {

std::array<Rgb3, 9> babylon_polynomial(const ShCoefficients& sh) {
  detail::engines::check_sh(sh);
  // Babylon's cube pipeline (CubeMapToSphericalPolynomialTools): radiance SH in its basis ->
  // convertIncidentRadianceToIrradiance (x A_l) -> convertIrradianceToLambertianRadiance (/ pi)
  // -> SphericalPolynomial.FromHarmonics, whose constants (1.02333, 0.886277, 0.247708, 0.429043,
  // 0.495417, 0.858086; the first the product (2 pi / 3) Y_1, and so on) and final / pi are
  // reproduced exactly, 0.886277 included.
  std::array<Rgb3, 9> h{};
  for (size_t k = 0; k < 9; ++k)
    for (size_t c = 0; c < 3; ++c) h[k][c] = detail::engines::kCondonShortley[k] * sh.irradiance_over_pi[3 * k + c];
  std::array<Rgb3, 9> p{};
  for (size_t c = 0; c < 3; ++c) {
    const double l00 = h[0][c], l1m1 = h[1][c], l10 = h[2][c], l11 = h[3][c], l2m2 = h[4][c], l2m1 = h[5][c],
                 l20 = h[6][c], l21 = h[7][c], l22 = h[8][c];
    p[0][c] = -1.02333 * l11;                                    // x
    p[1][c] = -1.02333 * l1m1;                                   // y
    p[2][c] = 1.02333 * l10;                                     // z
    p[3][c] = 0.886277 * l00 - 0.247708 * l20 + 0.429043 * l22;  // xx
    p[4][c] = 0.886277 * l00 - 0.247708 * l20 - 0.429043 * l22;  // yy
    p[5][c] = 0.886277 * l00 + 0.495417 * l20;                   // zz
    p[6][c] = -0.858086 * l2m1;                                  // yz
    p[7][c] = -0.858086 * l21;                                   // zx
    p[8][c] = 0.858086 * l2m2;                                   // xy
    for (size_t k = 0; k < 9; ++k) p[k][c] /= math::kPi;
  }
  return p;
}

namespace detail::engines::babylon {

std::vector<OutFile> create_env_texture(const EngineSettings& s, const EngineBake& bake, const std::string& name,
                                        const EngineWriteOptions&, Metadata& delivered) {
  // Babylon.js's frame (babylon_frame.hpp): the environment and its polynomial mirrored in x
  CubeLevels chain = with_target_metadata(brdfbake::detail::mirror_cube_x(*bake.prefiltered), s);
  chain.set_meta("frame", kBabylonFrame);
  io::BabylonEnv env;
  env.width = chain.size;
  env.lod_generation_scale = kBabylonLodGenerationScale;
  const std::array<Rgb3, 9> p = brdfbake::detail::mirror_babylon_polynomial_x(brdfbake::babylon_polynomial(*bake.sh));
  for (size_t k = 0; k < 9; ++k) env.polynomial[k] = p[k];
  RgbdStats stats;
  for (int l = 0; l < chain.level_count(); ++l)
    for (int f = 0; f < 6; ++f) env.images.push_back(rgbd_face_png(chain, l, f, stats));
  Metadata meta = chain.metadata;
  meta.emplace_back("sh_convention", s.sh_description);
  meta.emplace_back("face_rows", "bottom row first (Babylon.js reads row 0 of a face image as its last row)");
  meta.emplace_back("rgbd_max_error_rel_to_texel_max", brdfbake::detail::bound_text(stats.max_rel));
  meta.emplace_back("rgbd_clamped_texels", std::to_string(stats.clamped));
  env.extra["brdfbake"] = metadata_json(meta);
  add_rgbd_metadata(delivered, name + ".env", stats);
  return {{name + ".env", io::encode_babylon_env(env), std::make_shared<const CubeLevels>(std::move(chain))}};
}

}  // namespace detail::engines::babylon

}  // namespace brdfbake
