// The `khronos-viewer` target, the glTF-Sample-Viewer / glTF-IBL-Sampler convention: the preview's split-sum lookup
// against the engine's own formula (host/src/engines/khronos_viewer/splitsum.cpp on a staircase chain,
// test_target_support.hpp) and its files read back field by field from the bytes
// (host/src/engines/khronos_viewer/writer.cpp). The engine's own render of the target's files and its orientation
// probe: none: no registry here carries the Sample Viewer; its files stay checked against its source (ibl.glsl, its
// KTX2 loader) by reading (docs/ENGINES.md, "Engine truth").
#include <gtest/gtest.h>

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
#include "io/babylon_env.hpp"
#include "io/cubemap_io.hpp"
#include "io/ktx2.hpp"
#include "io/packed_float.hpp"
#include "io/png_rgbd.hpp"
#include "support/tolerances.hpp"
#include "test_target_support.hpp"

namespace brdfbake {
namespace {

using namespace target_test;  // NOLINT: the shared helpers of every target's test

// ---- The split-sum lookup ------------------------------------------------------------------------

// ibl.glsl getIBLRadianceGGX: roughness (u_MipCount - 1).
TEST(PreviewLookup, KhronosViewerLodIsTheEnginesFormulaAndLevelsBlendLinearly) {
  expect_lookup_is_engines(EngineTarget::KhronosViewer, 5, [](double r, int levels) { return (levels - 1) * r; });
}

// ---- The files, read back ----------------------------------------------------------------------

// glTF-IBL-Sampler: roughness = currentMipLevel / (mipLevelCount - 1); glTF-Sample-Viewer:
// lod = roughness * float(u_MipCount - 1).
TEST(EngineSchedule, KhronosLinearMatchesSamplerAndViewer) {
  const int levels = 5;
  for (int l = 0; l < levels; ++l)
    EXPECT_DOUBLE_EQ(schedule_roughness(RoughnessSchedule::Linear, l, levels), double(l) / (levels - 1));
  for (double r = 0.0; r <= 1.0; r += 0.125)
    EXPECT_DOUBLE_EQ(schedule_lod(RoughnessSchedule::Linear, r, levels), r * (levels - 1));
}

}  // namespace
}  // namespace brdfbake
