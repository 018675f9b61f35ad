// Babylon.js's .env environment file, as its EnvironmentTextureTools (CreateEnvTextureAsync,
// GetEnvInfo, CreateImageDataArrayBufferViews) define it:
//
//   8 magic bytes 0x86 0x16 0x87 0x96 0xF6 0xD6 0x96 0x36
//   a JSON manifest in ASCII, terminated by a NUL byte:
//     {"version": 2, "width": S, "imageType": "image/png",
//      "irradiance": {"x": [r, g, b], "y": .., "z": .., "xx": .., "yy": .., "zz": .., "yz": .., "zx": .., "xy": ..},
//      "specular": {"mipmaps": [{"length": bytes, "position": offset}, ...], "lodGenerationScale": 0.8}}
//   the images, one per (level, face), level-major (level 0 first), faces +X, -X, +Y, -Y, +Z, -Z;
//     "position" counts from the first byte after the NUL.
//
// Babylon requires the full chain: 6 (log2(S) + 1) images (S a power of two), each an 8-bit RGBA
// PNG holding RGBD (png_rgbd.hpp); Babylon.js 8.46.2 uploads each with UNPACK_FLIP_Y (createTexture's
// invertY), so an image's row 0 lands on the face's last row (the writers and readers of faces do the
// flipping: engines/babylon_frame.hpp). The irradiance is Babylon's spherical polynomial
// (SphericalPolynomial.FromHarmonics).
#pragma once

#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace brdfbake::io {

inline constexpr uint8_t kBabylonEnvMagic[8] = {0x86, 0x16, 0x87, 0x96, 0xF6, 0xD6, 0x96, 0x36};

struct BabylonEnv {
  int width = 0;                                      // face size of level 0
  std::array<std::array<double, 3>, 9> polynomial{};  // x, y, z, xx, yy, zz, yz, zx, xy
  double lod_generation_scale = 0.8;
  std::vector<std::vector<uint8_t>> images;                         // 6 (log2(width) + 1) PNG files, level-major
  nlohmann::ordered_json extra = nlohmann::ordered_json::object();  // extra manifest members (ours: "brdfbake")
};

// The file. Throws Error when the image count does not match the width.
std::vector<uint8_t> encode_babylon_env(const BabylonEnv& env);
// Parses a file as Babylon's GetEnvInfo does, checking the magic, the manifest, the version, the
// image count and that every image lies inside the file. Throws Error with the reason.
BabylonEnv decode_babylon_env(const std::vector<uint8_t>& bytes);

}  // namespace brdfbake::io
