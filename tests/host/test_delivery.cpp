// Delivery (host/src/families/delivery.cpp): the bound a file or a manifest records is never below
// the bound that was measured. Every recorded bound is rounded up to three significant digits;
// rounding to nearest (printf's %.3g) records less than was measured about half the time, so a
// file could promise more accuracy than it holds.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "brdfbake/job.hpp"
#include "brdfbake/tables.hpp"
#include "io/ktx2.hpp"
#include "support/device_fixture.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using namespace brdfbake;

// A fresh, empty folder `name` in the test's temporary folder (removed when the test ends).
fs::path temp_dir(const std::string& name) { return brdfbake::test::test_temp_dir(name); }

// A key of a KTX2 file's metadata (its key/value data, our keys prefixed "brdfbake:"), as text;
// empty when absent.
std::string ktx2_value(const fs::path& p, const std::string& key) {
  const io::Ktx2Image k = io::read_ktx2(p.string());
  for (const auto& [name, value] : k.key_values)
    if (name == "brdfbake:" + key) return value.substr(0, value.find('\0'));
  return {};
}

// A one-texel-a-face cube of `value`, written as a prefilter result with `bound` as its own bound.
WriteReport write_cube(const fs::path& path, double bound, float value, const std::string& pixel) {
  TableRequest t;
  t.kind = TableKind::Prefilter;
  t.output = path.string();
  t.pixel = pixel;
  validate_table(t);
  CubeLevels cube;
  cube.size = 1;
  cube.levels = {std::vector<float>(6 * 4, value)};
  for (size_t k = 3; k < cube.levels[0].size(); k += 4) cube.levels[0][k] = 1.0f;
  BakeResult r;
  r.kind = t.kind;
  r.artifact = cube;
  r.error_bound = bound;
  return write_result(r, t, path.string());
}

// 0.0012345 is recorded "0.00123" when rounded to nearest: below the bound. Float32 texels add no
// storage error, so the delivered bound is the result's own.
TEST(Delivery, CubeRecordsABoundNotBelowTheMeasuredOne) {
  const fs::path path = temp_dir("cube") / "cube.ktx2";
  const WriteReport w = write_cube(path, 0.0012345, 0.5f, "f32");
  ASSERT_TRUE(w.error_bound.has_value());
  EXPECT_EQ(*w.error_bound, 0.0012345);
  const std::string recorded = ktx2_value(path, "error_bound_rel");
  ASSERT_FALSE(recorded.empty());
  EXPECT_GE(std::stod(recorded), *w.error_bound) << "recorded '" << recorded << "'";
  EXPECT_EQ(recorded, "0.00124");  // up to three significant digits, not to nearest
}

// binary16 stores 0.3 as 0.2998046875: a storage error of 1.953125e-4, which rounds to nearest as
// "0.000195". Both the storage error and the delivered bound the file records cover what was
// measured.
TEST(Delivery, CubeRecordsAStorageErrorNotBelowTheMeasuredOne) {
  const fs::path path = temp_dir("cube_f16") / "cube.ktx2";
  const WriteReport w = write_cube(path, 1e-3, 0.3f, "f16");
  ASSERT_TRUE(w.error_bound.has_value());
  EXPECT_GT(w.storage_error, 0.0);
  EXPECT_GE(std::stod(ktx2_value(path, "storage_error")), w.storage_error);
  EXPECT_GE(std::stod(ktx2_value(path, "error_bound_rel")), *w.error_bound);
}

// A job's manifest records a table's delivered bound (a number) and its two parts as text: each part
// rounded up, so that they add up to at least the bound. The 16x16 Charlie table's binary16 storage
// error rounds down to nearest (its parts, rounded to nearest, add up to 0.000466 of a bound of
// 0.000466344).
TEST(Delivery, ManifestRecordsPartsNotBelowTheMeasuredOnes) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  (void)dev;
  Job job = parse_job(R"({"brdfbake_job": 1, "tables": [{"kind": "charlie", "size": 16, "output": "dfg.ktx2"}]})",
                      "job.json");
  job.output_dir = temp_dir("manifest").string();
  const Manifest m = run_job(job);
  ASSERT_EQ(m.files.size(), 1u);
  const ManifestFile& f = m.files[0];
  ASSERT_TRUE(f.error_bound.has_value());
  double integration = -1, storage = -1;
  for (const auto& [key, value] : f.details) {
    if (key == "integration_error_bound") integration = std::stod(value);
    if (key == "storage_error") storage = std::stod(value);
  }
  ASSERT_GE(integration, 0.0);
  ASSERT_GT(storage, 0.0);
  EXPECT_GE(integration + storage, *f.error_bound) << "integration " << integration << " + storage " << storage;
}

}  // namespace
