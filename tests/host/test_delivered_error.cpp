// The error a file records is the error of the values it stores: each lossy format is written,
// read back with an independent reader (OpenImageIO for images, our KTX2 reader, the text of .h and
// .csv files), and the stored values are compared with the converged reference at the same cells.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "brdfbake/dfg_lut.hpp"
#include "brdfbake/tables.hpp"
#include "io/half.hpp"
#include "io/ktx2.hpp"
#include "support/cli_runner.hpp"
#include "support/device_fixture.hpp"
#include "support/temp_dir.hpp"
#include "support/tolerances.hpp"

namespace {

namespace fs = std::filesystem;
using namespace brdfbake;

// The test's temporary folder (removed when the test ends).
fs::path temp_dir() { return brdfbake::test::test_temp_root(); }

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The stored values of a file, texel-major with `channels` values a texel, read independently.
std::vector<float> read_back(const fs::path& p, int channels) {
  const std::string ext = p.extension().string();
  std::vector<float> v;
  if (ext == ".ktx2") {
    const io::Ktx2Image k = io::read_ktx2(p.string());
    const bool half = k.vk_format == io::kVkFormatR16G16B16A16Sfloat;
    const std::vector<uint8_t>& bytes = k.level_data.front();
    const size_t texels = bytes.size() / (half ? 8 : 16);
    for (size_t t = 0; t < texels; ++t)
      for (int c = 0; c < channels; ++c) {
        if (half) {
          uint16_t bits;
          std::memcpy(&bits, bytes.data() + (t * 4 + size_t(c)) * 2, 2);
          v.push_back(io::half_bits_to_float(bits));
        } else {
          float f;
          std::memcpy(&f, bytes.data() + (t * 4 + size_t(c)) * 4, 4);
          v.push_back(f);
        }
      }
    return v;
  }
  if (ext == ".h") {
    // the array's initialiser: 0x.... half bit patterns
    const std::string text = read_file(p);
    const std::regex hex("0x([0-9a-f]{4})");
    for (auto it = std::sregex_iterator(text.begin(), text.end(), hex); it != std::sregex_iterator(); ++it)
      v.push_back(io::half_bits_to_float(static_cast<uint16_t>(std::stoul((*it)[1].str(), nullptr, 16))));
    return v;
  }
  auto in = OIIO::ImageInput::open(p.string());
  if (!in) return v;
  const OIIO::ImageSpec& spec = in->spec();
  std::vector<float> all(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
  in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data());
  in->close();
  for (size_t t = 0; t < size_t(spec.width) * size_t(spec.height); ++t)
    for (int c = 0; c < channels; ++c) v.push_back(all[t * size_t(spec.nchannels) + size_t(c)]);
  return v;
}

double recorded_bound(const fs::path& p) {
  std::string text = p.extension() == ".hdr" ? read_file(p.string() + ".json") : read_file(p);
  const std::regex key(R"(error_bound_mixed[^_a-z][^0-9]*([0-9.eE+-]+))");
  std::smatch m;
  if (!std::regex_search(text, m, key)) return -1.0;
  return std::stod(m[1].str());
}

TEST(DeliveredError, RecordedBoundCoversTheStoredValues) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  const fs::path dir = temp_dir();
  auto device = Backend::open(*dev);
  auto reference = Backend::open("reference");
  for (TableKind kind : {TableKind::Ggx, TableKind::Charlie}) {
    TableRequest t;
    t.kind = kind;
    t.params = {{"size", 16.0}};
    validate_table(t);
    const BakeResult baked = bake_table(t, *device);
    const BakeResult converged = bake_table(t, *reference);
    const Table& ref = *converged.table();
    const int channels = ref.channel_count();
    for (const std::string file : {"t.ktx2", "t.h", "t.hdr", "t.exr", "t.png"}) {
      if (file == "t.png" && kind == TableKind::Ggx) continue;  // refused: the diffuse channel exceeds 1
      TableRequest o = t;
      o.output = (dir / file).string();
      if (file == "t.png") o.set("png_range", std::string("scale"));  // Charlie's albedo exceeds 1 too
      const WriteReport w = write_result(baked, o, o.output);
      ASSERT_TRUE(w.error_bound.has_value()) << file;
      const std::vector<float> stored = read_back(dir / file, channels);
      ASSERT_EQ(stored.size(), ref.data.size()) << file;
      std::vector<double> png_scale(size_t(channels), 1.0);
      if (file == "t.png") {
        // the file records its scale; the stored value times it is the table's value
        const std::string text = read_file(dir / file);
        const auto at = text.find("png_scale");
        ASSERT_NE(at, std::string::npos);
        std::stringstream s(text.substr(at + 10, 80));
        for (int c = 0; c < channels; ++c) {
          s >> png_scale[size_t(c)];
          s.ignore(1);
        }
      }
      double worst = 0.0;
      for (size_t k = 0; k < stored.size(); ++k) {
        const double value = double(stored[k]) * png_scale[k % size_t(channels)];
        worst = std::max(worst, std::fabs(value - double(ref.data[k])) / std::max(1.0, std::fabs(double(ref.data[k]))));
      }
      const double recorded = recorded_bound(dir / file);
      constexpr double kReferenceStorage = test::kReferenceStorage;
      EXPECT_GE(recorded + kReferenceStorage, worst) << table_kind_name(kind) << " " << file;
      EXPECT_GE(*w.error_bound + kReferenceStorage, worst) << table_kind_name(kind) << " " << file;
      // and the bound is not vacuous: within a factor of the storage error plus the integration bound
      EXPECT_LE(recorded, 3.0 * (worst + *baked.error_bound) + 1e-6) << table_kind_name(kind) << " " << file;
    }
  }
  fs::remove_all(dir);
}

// A shader's lookup: bilinear between texel centres (u = (i + 0.5) / n), clamp to edge.
double lookup(const Table& t, double u, double v, int c) {
  auto split = [](double uv, int n, int* i, double* f) {
    const double x = std::clamp(uv * n - 0.5, 0.0, double(n - 1));
    *i = std::min(int(x), n - 2);
    *f = x - *i;
  };
  int i = 0, j = 0;
  double fx = 0, fy = 0;
  split(u, t.width, &i, &fx);
  split(v, t.height, &j, &fy);
  return (1 - fy) * ((1 - fx) * double(t.at(i, j, c)) + fx * double(t.at(i + 1, j, c))) +
         fy * ((1 - fx) * double(t.at(i, j + 1, c)) + fx * double(t.at(i + 1, j + 1, c)));
}

TEST(DeliveredError, InterpolationErrorCoversLookupsAnywhere) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  for (const char* axis : {"uniform", "sqrt"}) {
    TableRequest t;
    t.kind = TableKind::GgxMultiscatter;
    t.params = {{"size", 12.0}, {"n_dot_v_axis", std::string(axis)}};
    validate_table(t);
    const BakeResult r = bake_table(t, *Backend::open(*dev));
    const Table& table = *r.table();
    const double interior = std::stod(table.meta("interpolation_error")), edge = std::stod(table.meta("edge_error"));
    // The converged values at pseudo-random lookup coordinates, inside and within half a texel of the edges.
    LutSpec probe;
    probe.kind = LutKind::GgxMultiscatter;
    std::vector<double> us, vs;
    for (int k = 0; k < 37; ++k) {
      us.push_back(std::fmod(0.6180339887 * (k + 1), 1.0));
      vs.push_back(std::fmod(0.7548776662 * (k + 1), 1.0));
    }
    us.push_back(0.0);
    vs.push_back(0.0);
    for (double u : us) probe.n_dot_v.push_back(std::string(axis) == "sqrt" ? u * u : u);
    for (double v : vs) probe.roughness.push_back(v);
    const Table truth = bake_lut_reference(probe);
    double worst_in = 0, worst_edge = 0;
    for (size_t a = 0; a < us.size(); ++a)
      for (size_t b = 0; b < vs.size(); ++b) {
        const bool on_edge = us[a] < 0.5 / 12 || us[a] > 1 - 0.5 / 12 || vs[b] < 0.5 / 12 || vs[b] > 1 - 0.5 / 12;
        for (int c = 0; c < 3; ++c) {
          const double want = double(truth.at(int(a), int(b), c));
          const double d = std::fabs(lookup(table, us[a], vs[b], c) - want) / std::max(1.0, std::fabs(want));
          (on_edge ? worst_edge : worst_in) = std::max(on_edge ? worst_edge : worst_in, d);
        }
      }
    // Bilinear error peaks on the lines between centres, where the bound is measured; points off
    // those lines see less (up to the curvature across the other axis: a 10% allowance).
    EXPECT_LE(worst_in, 1.1 * interior) << axis;
    EXPECT_LE(worst_edge, 1.1 * edge) << axis;
    EXPECT_GT(worst_in, 0.1 * interior) << axis << ": the bound is not vacuous";
  }
}

TEST(DeliveredError, MaxErrorCoversTheDelivery) {
  const fs::path dir = temp_dir() / "max-error";
  fs::create_directories(dir);
  auto run = [&](const std::string& args) { return brdfbake::test::run_cli(args + " --quiet"); };
  // binary16 alone rounds by up to 4.9e-4: refused before any work, naming what would meet it
  const auto f16 = run("lut --max-error 1e-4 -o " + (dir / "a.ktx2").string());
  EXPECT_EQ(f16.code, 2);
  EXPECT_NE(f16.err.find("--pixel f32"), std::string::npos) << f16.err;
  EXPECT_FALSE(fs::exists(dir / "a.ktx2"));
  // float32 delivers it: the recorded bound is at most the request
  const auto f32 = run("lut --max-error 1e-4 --pixel f32 --size 16 -o " + (dir / "b.ktx2").string());
  ASSERT_EQ(f32.code, 0) << f32.err;
  // beyond the calibration in fp32, fp64 is named when it reaches the target
  const auto deep = run("lut --max-error 4e-7 --size 8 -o " + (dir / "c.exr").string());
  EXPECT_EQ(deep.code, 2);
  EXPECT_NE(deep.err.find("--precision fp64"), std::string::npos) << deep.err;
  // a prefiltered chain that cannot reach its target fails without a file
  const auto chain =
      run("prefilter --env builtin:sun --size 64 --min-size 8 --max-error 1e-6 -o " + (dir / "d.ktx2").string());
  EXPECT_EQ(chain.code, 2);
  EXPECT_NE(chain.err.find("is not reached"), std::string::npos) << chain.err;
  EXPECT_FALSE(fs::exists(dir / "d.ktx2"));
  fs::remove_all(dir);
}

TEST(DeliveredError, ValuesAFormatCannotHoldAreRefused) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  const fs::path dir = temp_dir() / "refused";
  fs::create_directories(dir);
  TableRequest t;
  t.kind = TableKind::Ggx;
  t.params = {{"size", 8.0}};
  validate_table(t);
  const BakeResult baked = bake_table(t, *Backend::open(*dev));
  TableRequest png = t;
  png.output = (dir / "t.png").string();
  try {
    write_result(baked, png, png.output);
    ADD_FAILURE() << "a diffuse channel above 1 went into a 16-bit PNG";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("outside [0, 1]"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("png_range"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "t.png"));
  // clamping is an explicit choice, and recorded
  png.set("png_range", std::string("clamp"));
  const WriteReport w = write_result(baked, png, png.output);
  EXPECT_GT(w.storage_error, 0.1) << "the clamping is part of the measured storage error";
  EXPECT_NE(read_file(dir / "t.png").find("png_clamped"), std::string::npos);
  // binary16 beyond 65504
  BakeResult big = baked;
  std::get<Table>(big.artifact).data[0] = 1e5f;
  TableRequest ktx = t;
  ktx.output = (dir / "t.ktx2").string();
  try {
    write_result(big, ktx, ktx.output);
    ADD_FAILURE() << "1e5 written as binary16";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--pixel f32"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "t.ktx2"));
  // non-finite values are never written, whatever the format
  std::get<Table>(big.artifact).data[0] = std::nanf("");
  TableRequest exr = t;
  exr.output = (dir / "t.exr").string();
  EXPECT_THROW(write_result(big, exr, exr.output), Error);
  EXPECT_FALSE(fs::exists(dir / "t.exr"));
  fs::remove_all(dir);
}

}  // namespace
