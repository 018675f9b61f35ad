// The MERL BRDF binary: the writer's byte layout as MERL's reader (BRDFRead.cpp) expects it, the round
// trip through our reader, the reader's bin lookup, the sidecar, and the errors.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>

#include "brdfbake/brdf.hpp"
#include "brdfbake/error.hpp"
#include "io/merl.hpp"
#include "support/temp_dir.hpp"
#include "support/tolerances.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;

// The test's temporary folder (removed when the test ends).
fs::path temp_dir() { return brdfbake::test::test_temp_root(); }

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A table of distinct values (some bins marked below the horizon).
MerlTable synthetic_table() {
  MerlTable t;
  t.values.resize(3 * kMerlBins);
  std::mt19937 rng(3u);
  std::uniform_real_distribution<double> u(0.0, 50.0);
  for (size_t k = 0; k < t.values.size(); ++k) t.values[k] = (k % 97 == 0) ? kMerlBelowHorizon : u(rng);
  t.metadata = {{"model", "synthetic"}, {"note", "a \"quoted\" value"}};
  return t;
}

TEST(Merl, ByteLayoutIsMerls) {
  const fs::path path = temp_dir() / "layout.binary";
  const MerlTable t = synthetic_table();
  write_merl(t, path.string());
  const std::string bytes = read_bytes(path);
  ASSERT_EQ(bytes.size(), 12u + 3u * kMerlBins * 8u);
  std::int32_t dims[3];
  std::memcpy(dims, bytes.data(), 12);
  EXPECT_EQ(dims[0], 90);
  EXPECT_EQ(dims[1], 90);
  EXPECT_EQ(dims[2], 180);
  // MERL's reader: value of channel c at bin (i, j, k) = brdf[((c * 90 + i) * 90 + j) * 180 + k] * scale[c]
  const double scale[3] = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};
  for (const size_t bin : {size_t(0), size_t(1), size_t(97 * 5 + 3), kMerlBins - 1}) {
    for (size_t c = 0; c < 3; ++c) {
      double stored;
      std::memcpy(&stored, bytes.data() + 12 + 8 * (c * kMerlBins + bin), 8);
      const double f = t.values[c * kMerlBins + bin];
      if (f < 0.0) {
        EXPECT_EQ(stored, -1.0) << bin;  // the marker, before scaling
      } else {
        EXPECT_NEAR(stored * scale[c], f, test::kRounding * f) << bin << " " << c;
      }
    }
  }
}

TEST(Merl, RoundTrip) {
  const fs::path path = temp_dir() / "round.binary";
  const MerlTable t = synthetic_table();
  write_merl(t, path.string());
  const MerlTable back = read_merl(path.string());
  ASSERT_EQ(back.values.size(), t.values.size());
  for (size_t k = 0; k < t.values.size(); ++k) {
    if (t.values[k] == kMerlBelowHorizon) {
      ASSERT_EQ(back.values[k], kMerlBelowHorizon) << k;
    } else {
      ASSERT_NEAR(back.values[k], t.values[k], test::kTwoRoundings * t.values[k]) << k;  // f / s * s
    }
  }
  EXPECT_NE(
      std::find(back.metadata.begin(), back.metadata.end(), std::pair<std::string, std::string>{"model", "synthetic"}),
      back.metadata.end());
  // the sidecar is JSON with the metadata
  const auto j = nlohmann::json::parse(read_bytes(path.string() + ".json"));
  EXPECT_EQ(j["metadata"]["note"], "a \"quoted\" value");
  EXPECT_EQ(j["file"], "round.binary");
}

// Every bin's centre directions fall back into that bin under MERL's own lookup.
TEST(Merl, BinCentresLookUpTheirOwnBin) {
  size_t checked = 0;
  for (int i = 0; i < kMerlThetaH; ++i)
    for (int j = 0; j < kMerlThetaD; ++j)
      for (int k = 0; k < kMerlPhiD; k += 7) {
        const io::MerlAngles a = io::merl_bin_centre(i, j, k);
        Vec3 wi{}, wo{};
        io::half_diff_to_directions(a.theta_h, a.theta_d, a.phi_d, wi, wo);
        ASSERT_EQ(io::merl_index(wi, wo), (size_t(i) * 90 + size_t(j)) * 180 + size_t(k)) << i << " " << j << " " << k;
        // reciprocity: the swapped pair lands in the same theta bins, phi_d folded
        const size_t swapped = io::merl_index(wo, wi);
        ASSERT_EQ(swapped / 180, (size_t(i) * 90 + size_t(j))) << i << " " << j << " " << k;
        ++checked;
      }
  EXPECT_GT(checked, 200000u);
}

// A tabulated table: the marker exactly where a direction is below the horizon, and f at the bin
// centre elsewhere; the lookup of a pair returns the value of its bin.
TEST(Merl, ReferenceTableAndLookup) {
  TabulateSpec s;
  s.model = BrdfModel::Lambert;
  s.layout = TableLayout::Merl;
  Material m;
  m.base_color = {0.5, 0.25, 1.0};
  s.materials = {NamedMaterial{"lambert", std::nullopt, m, {}, {}, {}}};
  const MerlTable t = tabulate_merl_reference(s);
  size_t below = 0;
  for (int i = 0; i < kMerlThetaH; i += 3)
    for (int j = 0; j < kMerlThetaD; j += 3)
      for (int k = 0; k < kMerlPhiD; k += 5) {
        const io::MerlAngles a = io::merl_bin_centre(i, j, k);
        Vec3 wi{}, wo{};
        io::half_diff_to_directions(a.theta_h, a.theta_d, a.phi_d, wi, wo);
        const size_t b = (size_t(i) * 90 + size_t(j)) * 180 + size_t(k);
        const Rgb f = merl_lookup(t, wi, wo);
        if (wi.z <= 0.0 || wo.z <= 0.0) {
          ++below;
          EXPECT_EQ(t.values[b], kMerlBelowHorizon);
          EXPECT_EQ(f.r, kMerlBelowHorizon);
        } else {
          EXPECT_NEAR(t.values[kMerlBins + b], 0.25 / M_PI, test::kUlpsOfOne);
          EXPECT_NEAR(f.b, 1.0 / M_PI, test::kUlpsOfOne);
        }
      }
  EXPECT_GT(below, 0u);
  for (const char* key : {"model", "materials", "layout", "resolution", "precision", "conventions", "generator"}) {
    bool found = false;
    for (const auto& kv : t.metadata) found |= kv.first == key;
    EXPECT_TRUE(found) << key;
  }
}

TEST(Merl, ReaderRejectsOtherFiles) {
  const fs::path dir = temp_dir();
  auto expect_error = [&](const std::string& name, const std::string& bytes, const std::string& needle) {
    const fs::path p = dir / name;
    std::ofstream(p, std::ios::binary) << bytes;
    try {
      read_merl(p.string());
      FAIL() << name;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_error("short.binary", "abc", "shorter than its header");
  std::string header(12, '\0');
  const std::int32_t dims[3] = {90, 90, 360};
  std::memcpy(header.data(), dims, 12);
  expect_error("dims.binary", header, "90 x 90 x 360");
  const std::int32_t good[3] = {90, 90, 180};
  std::memcpy(header.data(), good, 12);
  expect_error("truncated.binary", header + std::string(1000, '\0'), "bytes, expected");
  EXPECT_THROW(read_merl((dir / "missing.binary").string()), Error);
  // a table of the wrong size is not written, and nothing is left behind
  MerlTable bad;
  bad.values.resize(10);
  EXPECT_THROW(write_merl(bad, (dir / "bad.binary").string()), Error);
  EXPECT_FALSE(fs::exists(dir / "bad.binary"));
  EXPECT_FALSE(fs::exists(dir / "bad.binary.json"));
}

}  // namespace
}  // namespace brdfbake
