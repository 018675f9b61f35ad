// ASTC HDR KTX2 cubemaps (see astc_ktx2.hpp).
#include "io/astc_ktx2.hpp"

#include <astcenc.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "brdfbake/error.hpp"
#include "io/atomic_file.hpp"
#include "io/cubemap_io.hpp"
#include "io/ktx2.hpp"
#include "text.hpp"

namespace brdfbake::io {
namespace {

struct ContextDeleter {
  void operator()(astcenc_context* c) const { astcenc_context_free(c); }
};

void check(astcenc_error e, const char* call) {
  if (e != ASTCENC_SUCCESS) throw Error(std::string("astcenc: ") + call + ": " + astcenc_get_error_string(e));
}

}  // namespace

AstcCube compress_astc_cube(const CubeLevels& cube, int block, double quality) {
  if (block != 4 && block != 6) throw Error("ASTC: block size " + std::to_string(block) + " (expected 4 or 6)");
  if (!(quality >= 0.0 && quality <= 100.0)) throw Error("ASTC: quality must be in [0, 100]");
  AstcCube out;
  out.block = block;
  out.vk_format = block == 4 ? kVkFormatAstc4x4SfloatBlock : kVkFormatAstc6x6SfloatBlock;

  astcenc_config config{};
  check(astcenc_config_init(ASTCENC_PRF_HDR, unsigned(block), unsigned(block), 1, float(quality), 0, &config),
        "astcenc_config_init");
  astcenc_context* raw = nullptr;
  check(astcenc_context_alloc(&config, 1, &raw), "astcenc_context_alloc");
  std::unique_ptr<astcenc_context, ContextDeleter> context(raw);
  const astcenc_swizzle swizzle{ASTCENC_SWZ_R, ASTCENC_SWZ_G, ASTCENC_SWZ_B, ASTCENC_SWZ_1};

  for (int l = 0; l < cube.level_count(); ++l) {
    const unsigned s = unsigned(cube.level_size(l));
    const size_t face_texels = size_t(s) * s;
    const size_t blocks =
        size_t((s + unsigned(block) - 1) / unsigned(block)) * ((s + unsigned(block) - 1) / unsigned(block));
    std::vector<uint8_t> level(6 * blocks * 16);
    std::vector<float> decoded(cube.levels[size_t(l)].size());
    double max_abs = 0.0, max_rel = 0.0, sum_rel2 = 0.0, peak = 0.0;
    size_t n_rel = 0;
    for (float v : cube.levels[size_t(l)]) peak = std::max(peak, double(std::fabs(v)));
    for (int f = 0; f < 6; ++f) {
      std::vector<float> in(cube.levels[size_t(l)].begin() + std::ptrdiff_t(4 * face_texels * size_t(f)),
                            cube.levels[size_t(l)].begin() + std::ptrdiff_t(4 * face_texels * size_t(f + 1)));
      for (size_t t = 0; t < face_texels; ++t) {
        for (size_t c = 0; c < 3; ++c) {
          float& v = in[4 * t + c];
          if (!(v >= 0.0f)) v = 0.0f;  // environments are non-negative; guards NaN
          if (v > float(kAstcHdrMax)) {
            v = float(kAstcHdrMax);
            ++out.clamped;
          }
        }
        in[4 * t + 3] = 1.0f;
      }
      void* slices[1] = {in.data()};
      astcenc_image image{s, s, 1, ASTCENC_TYPE_F32, slices};
      uint8_t* dst = level.data() + size_t(f) * blocks * 16;
      check(astcenc_compress_image(context.get(), &image, &swizzle, dst, blocks * 16, 0), "astcenc_compress_image");
      check(astcenc_compress_reset(context.get()), "astcenc_compress_reset");
      // Decode what was stored, as a GPU would.
      float* dec = decoded.data() + 4 * face_texels * size_t(f);
      void* out_slices[1] = {dec};
      astcenc_image out_image{s, s, 1, ASTCENC_TYPE_F32, out_slices};
      check(astcenc_decompress_image(context.get(), dst, blocks * 16, &out_image, &swizzle, 0),
            "astcenc_decompress_image");
      check(astcenc_decompress_reset(context.get()), "astcenc_decompress_reset");
      const float* ref = cube.levels[size_t(l)].data() + 4 * face_texels * size_t(f);
      for (size_t t = 0; t < face_texels; ++t)
        for (size_t c = 0; c < 3; ++c) {
          const double d = dec[4 * t + c], r = ref[4 * t + c];
          if (!std::isfinite(d)) throw Error("astcenc decoded a non-finite value at level " + std::to_string(l));
          const double err = std::fabs(d - r);
          max_abs = std::max(max_abs, err);
          const double rel = err / std::max(std::fabs(r), 1e-6 * peak + 1e-30);
          max_rel = std::max(max_rel, rel);
          if (r > 0.0) {
            sum_rel2 += (err / r) * (err / r);
            ++n_rel;
          }
        }
    }
    out.level_data.push_back(std::move(level));
    out.decoded.push_back(std::move(decoded));
    out.max_abs_error.push_back(max_abs);
    out.max_rel_error.push_back(max_rel);
    out.rms_rel_error.push_back(n_rel ? std::sqrt(sum_rel2 / double(n_rel)) : 0.0);
  }
  return out;
}

std::vector<std::pair<std::string, std::string>> astc_key_values(const CubeLevels& cube, const AstcCube& astc,
                                                                 double quality) {
  auto kv = cube_key_values(cube, 2);
  const std::string b = std::to_string(astc.block);
  char q[32];
  std::snprintf(q, sizeof q, "%g", quality);
  kv.emplace_back("brdfbake:astc_block", b + "x" + b);
  kv.emplace_back("brdfbake:astc_encoder", "ARM astcenc (libastcenc), profile HDR, effort " + std::string(q));
  kv.emplace_back("brdfbake:astc_max_abs_error_per_level", detail::bounds_text(astc.max_abs_error));
  kv.emplace_back("brdfbake:astc_max_rel_error_per_level", detail::bounds_text(astc.max_rel_error));
  kv.emplace_back("brdfbake:astc_rms_rel_error_per_level", detail::bounds_text(astc.rms_rel_error));
  kv.emplace_back("brdfbake:astc_clamped_channels", std::to_string(astc.clamped));
  kv.emplace_back("brdfbake:astc_error_definition",
                  "measured by decoding the stored blocks with astcenc: |decoded - baked| over R, G, B of every "
                  "texel of the level; relative to max(|baked|, 1e-6 of the level's peak); RMS over texels > 0; "
                  "adds to the bake's own error");
  return kv;
}

std::vector<uint8_t> astc_ktx2_bytes(const CubeLevels& cube, const AstcCube& astc, double quality) {
  Ktx2Image image;
  image.vk_format = astc.vk_format;
  image.width = image.height = uint32_t(cube.size);
  image.faces = 6;
  image.levels = uint32_t(astc.level_data.size());
  image.level_data = astc.level_data;
  image.key_values = astc_key_values(cube, astc, quality);
  return encode_ktx2(image);
}

AstcCube write_astc_ktx2_cube(const CubeLevels& cube, const std::string& path, int block, double quality) {
  AstcCube astc;
  std::vector<uint8_t> bytes;
  try {
    astc = compress_astc_cube(cube, block, quality);
    bytes = astc_ktx2_bytes(cube, astc, quality);
  } catch (const Error& e) {
    throw_write_error(path, e.what());
  }
  write_file_atomically(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
  return astc;
}

}  // namespace brdfbake::io
