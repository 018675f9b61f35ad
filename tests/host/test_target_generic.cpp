// The `generic` target, brdfbake's own runtime (docs/CONVENTIONS.md): the preview's split-sum lookup against the
// engine's own formula (host/src/engines/generic/splitsum.cpp on a staircase chain, test_target_support.hpp). The
// engine's own render of the target's files and its orientation probe: no engine renders it: the runtime is ours; its
// files are the bake's tables (tests/device) and its ASTC KTX2 chains (test_engines.cpp, AstcKtx2).
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

// docs/CONVENTIONS.md: (levels - 1) r.
TEST(PreviewLookup, GenericLodIsTheEnginesFormulaAndLevelsBlendLinearly) {
  expect_lookup_is_engines(EngineTarget::Generic, 5, [](double r, int levels) { return (levels - 1) * r; });
}

}  // namespace
}  // namespace brdfbake
