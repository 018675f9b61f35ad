// Internal: what every target's writer shares (registry.hpp): the chain's checks and metadata, the
// storage error of a container format, KTX2 chains (RGBA16F/32F or ASTC HDR: io/astc_ktx2's one
// assembly), RGBD PNG faces as Babylon.js reads them, and the SH bases of the engines' conventions.
#pragma once

#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "brdfbake/engines.hpp"
#include "engines/registry.hpp"

namespace brdfbake::detail::engines {

std::string fmt(double v, const char* f = "%.4g");
bool is_power_of_two(int v);

// The stored-value error of a container format, measured on every R, G, B of every level.
struct StorageError {
  std::vector<double> max_rel;  // per level: max |stored - value| / |value| over values > 0
  std::vector<double> max_abs;
  size_t clamped = 0;
};
StorageError measure_storage(const CubeLevels& cube, PixelType pixel);
void add_storage_metadata(Metadata& delivered, const std::string& file, PixelType pixel, const StorageError& e);
// The chain's metadata plus what the target adds.
CubeLevels with_target_metadata(const CubeLevels& cube, const EngineSettings& s);
// The chain against the target: its schedule, power-of-two size, full chain.
void check_chain(const CubeLevels& cube, const EngineSettings& s, const char* what);
// The skybox cube: the bake's, or level 0 of the chain (in `storage`).
const CubeLevels& skybox_of(const EngineBake& bake, CubeLevels& storage);
// A KTX2 cube file: RGBA16F/32F, or ASTC HDR (o.astc), with its delivered error in `delivered`.
std::vector<uint8_t> ktx2_cube_bytes(const CubeLevels& cube, PixelType pixel, const std::string& name,
                                     const EngineWriteOptions& o, Metadata& delivered);

// ---- RGBD PNG faces (gltf, babylon) ---------------------------------------------------------------

inline constexpr const char* kFaceNames[6] = {"px", "nx", "py", "ny", "pz", "nz"};
inline constexpr const char* kBabylonFrame =
    "the environment mirrored in x, (x, y, z) -> (-x, y, z): Babylon.js's left-handed world, into which its loaders "
    "mirror right-handed content (the glTF loader's root, HDRCubeTexture)";
struct RgbdStats {
  double max_rel = 0.0;  // max |decoded - value| / max channel of the texel
  size_t clamped = 0;
};
// One face of one level as Babylon.js reads it: bottom row first (babylon_frame.hpp).
std::vector<uint8_t> rgbd_face_png(const CubeLevels& cube, int level, int face, RgbdStats& stats);
void add_rgbd_metadata(Metadata& delivered, const std::string& file, const RgbdStats& st);
nlohmann::ordered_json metadata_json(const Metadata& m);

// A file's size and delivered error: its bytes decoded as the engine decodes them (.ktx, .ktx2,
// .env, an RGBD face PNG) against `f.values`; a file without values (JSON, text) only its size.
EngineFileEntry measure_engine_file(const OutFile& f);

// ---- SH bases -------------------------------------------------------------------------------------

// The basis constants of the real SH of bands 0..2 (docs/CONVENTIONS.md, without the
// Condon-Shortley phase): Y_k = kShBasis[k] poly_k(x, y, z), poly = 1, y, z, x, xy, yz, 3z^2 - 1,
// xz, x^2 - y^2.
inline constexpr double kShBasis[9] = {0.28209479177387814, 0.4886025119029199, 0.4886025119029199,
                                       0.4886025119029199,  1.0925484305920792, 1.0925484305920792,
                                       0.31539156525252005, 1.0925484305920792, 0.5462742152960396};
// The Condon-Shortley sign of Filament's and Babylon's bases relative to ours: they carry
// (-1)^m for m > 0 and the matching sign for m < 0 (Filament CubemapSH::computeShBasis, Babylon
// SH3ylmBasisConstants), i.e. negative for l1-1, l11, l2-1, l21.
inline constexpr double kCondonShortley[9] = {1, -1, 1, -1, 1, -1, 1, -1, 1};

// At least 3 bands, every coefficient finite; throws Error.
void check_sh(const ShCoefficients& sh);

}  // namespace brdfbake::detail::engines
