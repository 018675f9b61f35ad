// Engine targets (brdfbake/engines.hpp) across targets: the names and settings of the registry, and the ASTC
// HDR KTX2 chains two targets share (write_common; generic, khronos-viewer) read back field by field with their
// measured error. Each target's own checks (its schedule and SH against the engine's formulas, its files read
// back from the bytes, its split-sum lookup) are its tests/host/test_target_<target>.cpp. No device: the chains
// are synthetic. The Filament comparison with cmgen runs in tests/device.
#include <astcenc.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "brdfbake/engines.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "engines/babylon_frame.hpp"
#include "io/astc_ktx2.hpp"
#include "io/babylon_env.hpp"
#include "io/cubemap_io.hpp"
#include "io/ktx2.hpp"
#include "io/packed_float.hpp"
#include "io/png_rgbd.hpp"
#include "support/temp_dir.hpp"
#include "support/tolerances.hpp"
#include "test_target_support.hpp"

namespace brdfbake {
namespace {

using namespace target_test;  // NOLINT: temp_dir, read_all, u32, synthetic_chain

// ---- Descriptor ------------------------------------------------------------------------------------

TEST(EngineTarget, NamesRoundTripAndUnknownIsAnError) {
  for (const std::string& n : engine_target_names()) EXPECT_EQ(engine_target_name(engine_target_from_name(n)), n);
  EXPECT_EQ(engine_target_names().size(), 5u);
  try {
    engine_target_from_name("unreal");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("khronos-viewer"), std::string::npos) << e.what();
  }
}

TEST(EngineTarget, SettingsFixWhatEachEngineReads) {
  const EngineSettings f = engine_settings(EngineTarget::Filament);
  EXPECT_EQ(f.schedule, RoughnessSchedule::Filament);
  EXPECT_EQ(f.pixel, PixelType::R11G11B10);
  EXPECT_EQ(f.size, 256);     // cmgen IBL_DEFAULT_SIZE
  EXPECT_EQ(f.min_size, 16);  // cmgen IBL_DEFAULT_MIN_LOD_SIZE
  EXPECT_TRUE(f.skybox);
  EXPECT_EQ(f.files, (std::vector<std::string>{"NAME_ibl.ktx", "NAME_skybox.ktx", "sh.txt"}));
  EXPECT_EQ(engine_settings(EngineTarget::Babylon).schedule, RoughnessSchedule::Babylon);
  EXPECT_EQ(engine_settings(EngineTarget::Babylon).min_size, 1);  // .env holds the full chain
  EXPECT_EQ(engine_settings(EngineTarget::Gltf).schedule, RoughnessSchedule::Linear);
  EXPECT_EQ(engine_settings(EngineTarget::KhronosViewer).schedule, RoughnessSchedule::Linear);
  EXPECT_EQ(engine_settings(EngineTarget::Generic).schedule, RoughnessSchedule::Linear);
  EXPECT_EQ(engine_settings(EngineTarget::Generic).pixel, PixelType::F16);
}

// ---- SH conventions ----------------------------------------------------------------------------

// ---- KTX 1.1 keys --------------------------------------------------------------------------------

// ---- Babylon .env -----------------------------------------------------------------------------

// ---- ASTC HDR KTX2 ------------------------------------------------------------------------------

// Six faces of `size`^2 texels of ASTC HDR blocks (`block` x `block`, 16 bytes each, consecutive
// faces of `face_bytes`) decoded to RGBA float by a decompress-only astcenc context.
std::vector<float> astc_decode_faces(const uint8_t* blocks, size_t face_bytes, unsigned size, int block) {
  astcenc_config config{};
  EXPECT_EQ(astcenc_config_init(ASTCENC_PRF_HDR, unsigned(block), unsigned(block), 1, ASTCENC_PRE_FASTEST,
                                ASTCENC_FLG_DECOMPRESS_ONLY, &config),
            ASTCENC_SUCCESS);
  astcenc_context* context = nullptr;
  EXPECT_EQ(astcenc_context_alloc(&config, 1, &context), ASTCENC_SUCCESS);
  std::vector<float> out(6u * size * size * 4u, -1.0f);
  if (!context) return out;
  const astcenc_swizzle rgba{ASTCENC_SWZ_R, ASTCENC_SWZ_G, ASTCENC_SWZ_B, ASTCENC_SWZ_A};
  for (size_t f = 0; f < 6; ++f) {
    void* slices[1] = {out.data() + 4u * size * size * f};
    astcenc_image image{size, size, 1, ASTCENC_TYPE_F32, slices};
    EXPECT_EQ(astcenc_decompress_image(context, blocks + f * face_bytes, face_bytes, &image, &rgba, 0),
              ASTCENC_SUCCESS);
    EXPECT_EQ(astcenc_decompress_reset(context), ASTCENC_SUCCESS);
  }
  astcenc_context_free(context);
  return out;
}

TEST(AstcKtx2, StructureFieldByFieldAndMeasuredError) {
  const fs::path dir = temp_dir("astc");
  fs::create_directories(dir);
  const CubeLevels chain = synthetic_chain(32, 4, RoughnessSchedule::Linear);
  for (int block : {4, 6}) {
    const fs::path path = dir / ("c" + std::to_string(block) + ".ktx2");
    const io::AstcCube astc = io::write_astc_ktx2_cube(chain, path.string(), block, 10.0);
    const auto b = read_all(path);
    EXPECT_EQ(std::memcmp(b.data(), "\xABKTX 20\xBB\r\n\x1A\n", 12), 0);
    EXPECT_EQ(u32(b, 12), block == 4 ? 1000066000u : 1000066004u);  // VK_FORMAT_ASTC_NxN_SFLOAT_BLOCK
    EXPECT_EQ(u32(b, 16), 1u);                                      // typeSize 1 for block formats
    EXPECT_EQ(u32(b, 20), 32u);
    EXPECT_EQ(u32(b, 36), 6u);  // faceCount
    EXPECT_EQ(u32(b, 40), 4u);  // levels 32, 16, 8, 4
    EXPECT_EQ(u32(b, 44), 0u);  // supercompressionScheme: none
    EXPECT_EQ(u64(b, 64), 0u);  // no supercompression global data
    for (uint32_t l = 0; l < 4; ++l) {
      const uint64_t s = 32u >> l, blocks = (s + uint64_t(block) - 1) / uint64_t(block);
      EXPECT_EQ(u64(b, 88 + 24 * l), 6 * blocks * blocks * 16) << l;  // byteLength: whole blocks
      EXPECT_EQ(u64(b, 96 + 24 * l), u64(b, 88 + 24 * l));            // uncompressedByteLength
      EXPECT_EQ(u64(b, 80 + 24 * l) % 16, 0u);                        // lcm(16, 4)
    }
    // DFD (KDF): ASTC model 162, BT.709, linear, texelBlockDimension N-1, 16 bytes, one sample of
    // 128 bits, ASTC_DATA | FLOAT | SIGNED, -1.0f .. 1.0f
    const size_t dfd = u32(b, 48);
    EXPECT_EQ(u32(b, 52), 4u + 24u + 16u);
    EXPECT_EQ(u32(b, dfd + 12) & 0xFFu, 162u);
    EXPECT_EQ((u32(b, dfd + 12) >> 8) & 0xFFu, 1u);
    EXPECT_EQ((u32(b, dfd + 12) >> 16) & 0xFFu, 1u);
    EXPECT_EQ(u32(b, dfd + 16), uint32_t(block - 1) | uint32_t(block - 1) << 8);
    EXPECT_EQ(u32(b, dfd + 20), 16u);
    EXPECT_EQ(u32(b, dfd + 28), 127u << 16 | 0xC0u << 24);
    EXPECT_EQ(u32(b, dfd + 36), 0xBF800000u);
    EXPECT_EQ(u32(b, dfd + 40), 0x3F800000u);
    // the reader accepts it and the delivered error is in the metadata, as measured
    const io::Ktx2Image k = io::decode_ktx2(b);
    EXPECT_EQ(key(k.key_values, "KTXorientation"), "rd");
    const std::string rel = key(k.key_values, "brdfbake:astc_max_rel_error_per_level");
    ASSERT_NE(rel, "<missing>");
    std::istringstream in(rel);
    for (size_t l = 0; l < astc.max_rel_error.size(); ++l) {
      double recorded = -1.0;
      in >> recorded;
      // rounded up to 3 digits: never below what was measured
      EXPECT_GE(recorded, astc.max_rel_error[l]);
      EXPECT_LE(recorded, astc.max_rel_error[l] * 1.01 + 1e-12);
    }
    // The blocks the file holds, found through its level index (not our reader) and decoded by a
    // decompress-only astcenc context of our own, as a GPU would: every texel of every face and
    // level against the source chain.
    const std::string abs_recorded = key(k.key_values, "brdfbake:astc_max_abs_error_per_level");
    ASSERT_NE(abs_recorded, "<missing>");
    std::istringstream abs_in(abs_recorded);
    ASSERT_EQ(astc.max_abs_error.size(), 4u);
    for (size_t l = 0; l < 4; ++l) {
      const unsigned s = 32u >> l;
      const size_t face_texels = size_t(s) * s, blocks = size_t((s + unsigned(block) - 1) / unsigned(block));
      const size_t face_bytes = blocks * blocks * 16, offset = size_t(u64(b, 80 + 24 * l));
      ASSERT_EQ(size_t(u64(b, 88 + 24 * l)), 6 * face_bytes);
      ASSERT_LE(offset + 6 * face_bytes, b.size());
      const std::vector<float> decoded = astc_decode_faces(b.data() + offset, face_bytes, s, block);
      // the error of every channel, and relative to the largest source value of its block
      double max_abs = 0.0, max_of_block = 0.0;
      for (size_t f = 0; f < 6; ++f)
        for (unsigned by = 0; by < s; by += unsigned(block))
          for (unsigned bx = 0; bx < s; bx += unsigned(block)) {
            std::vector<size_t> texels;
            for (unsigned j = by; j < std::min(s, by + unsigned(block)); ++j)
              for (unsigned i = bx; i < std::min(s, bx + unsigned(block)); ++i)
                texels.push_back(f * face_texels + j * s + i);
            double peak = 0.0, worst = 0.0;
            for (size_t t : texels)
              for (size_t c = 0; c < 3; ++c) {
                const double got = decoded[4 * t + c], want = chain.levels[l][4 * t + c];
                ASSERT_TRUE(std::isfinite(got)) << "level " << l << " texel " << t;
                peak = std::max(peak, want);
                worst = std::max(worst, std::fabs(got - want));
              }
            max_abs = std::max(max_abs, worst);
            max_of_block = std::max(max_of_block, worst / peak);
          }
      // what a GPU decodes is what the encoder measured, and within the file's recorded bounds
      EXPECT_EQ(decoded, astc.decoded[l]) << "block " << block << " level " << l;
      double recorded_abs = -1.0;
      abs_in >> recorded_abs;
      EXPECT_LE(max_abs, recorded_abs) << "block " << block << " level " << l;
      EXPECT_GE(max_abs, astc.max_abs_error[l]) << "block " << block << " level " << l;
      EXPECT_GT(max_abs, 0.0) << "lossy: a zero error means the source itself was stored";
      // and that error is ASTC HDR's at this effort, not a misplaced face, level or channel
      EXPECT_LE(max_of_block, block == 4 ? test::kAstcHdr4x4OfBlock : test::kAstcHdr6x6OfBlock)
          << "block " << block << " level " << l;
      EXPECT_LE(astc.rms_rel_error[l], astc.max_rel_error[l]);
    }
  }
}

}  // namespace
}  // namespace brdfbake
