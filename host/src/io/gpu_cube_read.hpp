// Cube files read back as a GPU samples them once an engine has loaded them: every texel decoded
// from its stored encoding to float, so that a renderer's filtering can be emulated on the values a
// shader sees (the preview family's split-sum render, host/src/families/preview/).
//
//   .ktx2  VK_FORMAT_R16G16B16(A16)_SFLOAT, R32G32B32(A32)_SFLOAT (exact), and
//          VK_FORMAT_ASTC_{4x4,6x6}_SFLOAT_BLOCK decoded by ARM's astcenc (the reference decoder of
//          the ASTC specification, HDR profile: what a GPU's decoder returns);
//   .ktx   KTX 1.1 half or float (io/ktx1.hpp), and the packed GL_R11F_G11F_B10F that Filament
//          loads (glType GL_UNSIGNED_INT_10F_11F_11F_REV or Filament's GL_R11F_G11F_B10F, 4 bytes a
//          texel; OpenGL 4.6, 8.25, decoded exactly by io/packed_float.hpp);
//   RGBD   Babylon.js's 8-bit RGBD PNG faces (.env images, EXT_lights_image_based images), expanded
//          as Babylon.js's EnvironmentTextureTools (_UploadLevelsAsync) does where half-float
//          rendering exists (WebGL 2): its rgbdDecode post-process, rgb = (rgb' / 255)^2.2 / (a / 255)
//          in fp32 (helperFunctions.fx, fromRGBD), rendered into a HALF_FLOAT cube (binary16
//          rounding).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "brdfbake/environment.hpp"

namespace brdfbake::io {

// Every level of a cube container, RGBA float (alpha 1 where the file has none). Throws Error for
// a file that is not a cube of one of the formats above. `format` (when given) is set to what the
// file stores ("RGBA16F", "R11F_G11F_B10F", "ASTC 4x4 SFLOAT", ...), `key_values` to the file's
// key/value data (e.g. Filament's "sh").
CubeLevels read_gpu_cube(const std::string& path, std::string* format = nullptr,
                         std::vector<std::pair<std::string, std::string>>* key_values = nullptr);

// The same of a file's bytes already in memory (`origin` names it in messages).
CubeLevels decode_gpu_cube(const std::vector<uint8_t>& bytes, const std::string& origin, std::string* format = nullptr,
                           std::vector<std::pair<std::string, std::string>>* key_values = nullptr);

// One RGBD face image of `size` x `size` as Babylon.js reads it (below): RGBA float, alpha 1, the
// face's row 0 first. Throws Error naming `origin` for another size or a bad PNG.
std::vector<float> decode_rgbd_face(const std::vector<uint8_t>& png, int size, const std::string& origin);

// Babylon.js's RGBD faces: levels[l][f] the PNG bytes of face f (+X, -X, +Y, -Y, +Z, -Z) of level l,
// level 0 the largest (face size `size`, halved each level), read as Babylon.js 8.46.2 reads them: row
// 0 of an image is the face's last row (engines/babylon_frame.hpp). `origin` names them in messages.
CubeLevels decode_rgbd_cube(const std::vector<std::vector<std::vector<uint8_t>>>& levels, int size,
                            const std::string& origin);

}  // namespace brdfbake::io
