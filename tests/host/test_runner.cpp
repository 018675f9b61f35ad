// The runner (brdfbake/runner.hpp): one request to its delivery. Each delivery gives the same file,
// the bound the file records and the warnings, named as the request names its output; a stop is
// honoured; the lookup error measured once per table gives the bytes a fresh measurement gives.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "brdfbake/cancel.hpp"
#include "brdfbake/runner.hpp"
#include "support/temp_dir.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;

// A fresh, empty folder `name` in the test's temporary folder (removed when the test ends).
fs::path temp_dir(const std::string& name) { return brdfbake::test::test_temp_dir(name); }

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The value of a key a KTX2 file records ("brdfbake:error_bound"), or "".
std::string ktx2_value(const std::string& file, const std::string& key) {
  const std::string k = "brdfbake:" + key + std::string(1, '\0');
  const size_t at = file.find(k);
  if (at == std::string::npos) return "";
  const size_t end = file.find('\0', at + k.size());
  return end == std::string::npos ? "" : file.substr(at + k.size(), end - at - k.size());
}

TableRequest dfg(const std::string& output, int size = 8, const std::string& pixel = "f16") {
  TableRequest t;
  t.kind = TableKind::Ggx;
  t.params = {{"size", double(size)}};
  t.output = output;
  t.pixel = pixel;
  validate_table(t);
  return t;
}

TEST(Runner, EveryDeliveryIsTheSameFileWithItsBound) {
  const fs::path dir = temp_dir("deliveries");
  const TableRequest file = dfg((dir / "dfg.ktx2").string());
  const TableRun written = run_table(file);
  ASSERT_TRUE(fs::exists(file.output));
  const std::string bytes = read_file(file.output);
  // The delivered bound is what the file records: the integration bound plus binary16's rounding.
  ASSERT_TRUE(written.delivery.error_bound && written.result.error_bound);
  EXPECT_EQ(written.delivery.error_bound_text, ktx2_value(bytes, "error_bound_mixed"));
  EXPECT_EQ(written.delivery.error_bound_text, error_bound_text(*written.delivery.error_bound));
  EXPECT_DOUBLE_EQ(*written.delivery.error_bound, *written.result.error_bound + written.delivery.report.storage_error);
  EXPECT_GT(written.delivery.report.storage_error, std::ldexp(1.0, -13)) << "binary16 rounds at 2^-12 near 1";
  EXPECT_TRUE(written.warnings.empty());

  // The file's bytes, from a scratch folder that goes, named as the request names its output.
  TableRunOptions o;
  o.delivery = TableDelivery::Bytes;
  o.scratch_dir = (dir / "scratch").string();
  fs::create_directories(o.scratch_dir);
  const TableRun handed = run_table(dfg("dfg.ktx2"), o);
  ASSERT_EQ(handed.delivery.files.size(), 1u);
  EXPECT_EQ(handed.delivery.files[0].name, "dfg.ktx2");
  EXPECT_EQ(handed.delivery.files[0].bytes, bytes);
  EXPECT_EQ(handed.delivery.error_bound_text, written.delivery.error_bound_text);
  EXPECT_TRUE(fs::is_empty(o.scratch_dir)) << "the scratch folder is removed";

  // In memory: nothing written, the result's own bound; then delivered to a file: the same bytes.
  o = {};
  o.delivery = TableDelivery::Memory;
  const TableRequest later = dfg((dir / "later.ktx2").string());
  const TableRun kept = run_table(later, o);
  EXPECT_FALSE(fs::exists(later.output));
  EXPECT_EQ(kept.delivery.error_bound, kept.result.error_bound);
  const Delivery d = deliver_result(kept.result, later, TableDelivery::File);
  EXPECT_EQ(read_file(later.output), bytes);
  EXPECT_EQ(d.error_bound_text, written.delivery.error_bound_text);
}

// POST /v1/tables's delivery makes a table's file in memory where the format is built there (.exr,
// .ktx2, .csv, .h): the bytes the file delivery writes, with no scratch folder at all (the scratch
// path here cannot be created: a run that needed it fails); .png still goes through the scratch
// folder.
TEST(Runner, BytesOfATableAreMadeInMemory) {
  const fs::path dir = temp_dir("in-memory");
  std::ofstream(dir / "a-file") << "not a folder";
  TableRunOptions o;
  o.delivery = TableDelivery::Bytes;
  o.scratch_dir = (dir / "a-file" / "scratch").string();
  for (const std::string ext : {".exr", ".ktx2", ".csv", ".h"}) {
    TableRequest t = dfg((dir / ("dfg" + ext)).string(), 8, "");
    t.kind = TableKind::GgxMultiscatter;
    validate_table(t);
    const TableRun file = run_table(t);
    const TableRun handed = run_table(t, o);
    ASSERT_EQ(handed.delivery.files.size(), 1u) << ext;
    EXPECT_EQ(handed.delivery.files[0].name, "dfg" + ext);
    EXPECT_EQ(handed.delivery.files[0].bytes, read_file(t.output)) << ext;
    EXPECT_EQ(handed.delivery.error_bound_text, file.delivery.error_bound_text) << ext;
    EXPECT_EQ(handed.delivery.report.encoding, file.delivery.report.encoding) << ext;
  }
  const TableRequest png = dfg((dir / "dfg.png").string(), 8, "");
  EXPECT_THROW(run_table(png, o), Error) << "a PNG is written to the scratch folder, which cannot be made here";
}

TEST(Runner, LookupErrorMeasuredOnceGivesTheSameBytes) {
  // The second bake of a table reuses the first's lookup error measurement: its file is the first's
  // byte for byte, and a bake of another size measures its own.
  const fs::path dir = temp_dir("measured-once");
  const TableRequest a = dfg((dir / "a.csv").string(), 12, ""), b = dfg((dir / "b.csv").string(), 12, "");
  const TableRun first = run_table(a), second = run_table(b);
  EXPECT_EQ(read_file(a.output), read_file(b.output));
  EXPECT_EQ(first.result.details, second.result.details);
  const TableRun other = run_table(dfg((dir / "c.ktx2").string(), 13));
  const auto interpolation = [](const TableRun& r) {
    for (const auto& [k, v] : r.result.details)
      if (k == "interpolation_error") return v;
    return std::string();
  };
  EXPECT_FALSE(interpolation(first).empty());
  EXPECT_NE(interpolation(other), interpolation(first));
}

TEST(Runner, ClampWarningsNameTheOutputAsRequested) {
  const fs::path dir = temp_dir("warnings");
  {
    std::ofstream m(dir / "sharp.json");
    m << R"({"materials": [{"name": "a", "model": "phong", "shininess": 1000000, "specularColor": [1, 1, 1]}]})";
  }
  TableRequest t;
  t.kind = TableKind::Tabulate;
  t.params = {{"material", (dir / "sharp.json").string()},
              {"layout", std::string("slice")},
              {"res", 64.0},
              {"clamp_f16", true}};
  t.pixel = "f16";
  t.output = "t.ktx2";
  validate_table(t);
  TableRunOptions o;
  o.delivery = TableDelivery::Bytes;
  o.scratch_dir = dir.string();
  const TableRun run = run_table(t, o);
  ASSERT_EQ(run.warnings.size(), 1u);
  EXPECT_EQ(run.warnings[0].rfind("'t.ktx2': ", 0), 0u) << run.warnings[0];
  EXPECT_NE(run.warnings[0].find("clamped to 65504"), std::string::npos) << run.warnings[0];
  EXPECT_EQ(run.delivery.warnings, run.warnings);
  // Refused without clamp_f16, the message naming the output as requested.
  t.params = {{"material", (dir / "sharp.json").string()}, {"layout", std::string("slice")}, {"res", 64.0}};
  validate_table(t);
  try {
    run_table(t, o);
    ADD_FAILURE() << "values beyond 65504 written as binary16";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("'t.ktx2': ", 0), 0u) << e.what();
  }
}

TEST(Runner, StopRequestedEndsTheRunAndWritesNothing) {
  const fs::path dir = temp_dir("stop");
  TableRunOptions o;
  int steps = 0;
  o.progress = [&](double, const std::string&) { ++steps; };
  o.stop_requested = [] { return true; };
  const TableRequest t = dfg((dir / "stopped.exr").string(), 64, "");
  EXPECT_THROW(run_table(t, o), Cancelled);
  EXPECT_FALSE(fs::exists(t.output));
  EXPECT_EQ(steps, 0) << "stopped at the first step, before reporting it";
  EXPECT_FALSE(cancel_requested()) << "one run's stop is not the process's";
}

}  // namespace
}  // namespace brdfbake
