// brdfbake prefilter and brdfbake irradiance, run as a user runs them: every output container,
// exit codes, one-line errors, and no partial output.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "brdfbake/environment.hpp"
#include "io/gpu_cube_read.hpp"
#include "io/ktx2.hpp"
#include "support/cli_runner.hpp"
#include "support/temp_dir.hpp"
#include "support/tolerances.hpp"
#include "view/load.hpp"

namespace {

namespace fs = std::filesystem;

using brdfbake::test::CliRun;
using brdfbake::test::count_lines;
CliRun run(const std::string& args) { return brdfbake::test::run_cli(args); }

// A fresh, empty folder `name` in the test's temporary folder (removed when the test ends).
fs::path temp_dir(const std::string& name) { return brdfbake::test::test_temp_dir(name); }

size_t entries(const fs::path& dir) {
  size_t n = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    (void)e;
    ++n;
  }
  return n;
}

// non-zero exit, one line on stderr naming the problem, nothing written in `dir`
void expect_clean_failure(const std::string& args, const fs::path& dir, const std::string& needle, int code = 2) {
  const size_t before = entries(dir);
  const CliRun r = run(args + " --quiet");
  EXPECT_EQ(r.code, code) << args << " -> " << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << args << " -> " << r.err;
  EXPECT_NE(r.err.find(needle), std::string::npos) << args << " -> " << r.err;
  EXPECT_EQ(entries(dir), before) << args << ": something was left behind";
}

void write_exr(const fs::path& p, int w, int h, const std::vector<float>& rgb) {
  auto out = OIIO::ImageOutput::create(p.string());
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::FLOAT);
  out->open(p.string(), spec);
  out->write_image(OIIO::TypeDesc::FLOAT, rgb.data());
  out->close();
}

// A cube output read back as `brdfbake view` reads it (KTX2, KTX1, DDS, folders of images).
brdfbake::CubeLevels cube_of(const fs::path& path) {
  try {
    const brdfbake::view::Item it = brdfbake::view::load(path.string());
    if (const auto* c = std::get_if<brdfbake::CubeLevels>(&it.content)) return *c;
    ADD_FAILURE() << path << " is not a cube: " << it.kind;
  } catch (const std::exception& e) {
    ADD_FAILURE() << e.what();
  }
  return {};
}

// `got` holds `want`'s levels: RGB within binary16's rounding (every container here stores half or
// float), or within RGBE's shared-exponent step of the texel's largest channel.
void expect_same_cube(const brdfbake::CubeLevels& got, const brdfbake::CubeLevels& want, const std::string& what,
                      bool rgbe) {
  SCOPED_TRACE(what);
  ASSERT_EQ(got.size, want.size);
  ASSERT_EQ(got.level_count(), want.level_count());
  for (int l = 0; l < want.level_count(); ++l) {
    const auto& g = got.levels[size_t(l)];
    const auto& w = want.levels[size_t(l)];
    ASSERT_EQ(g.size(), w.size()) << "level " << l;
    for (size_t t = 0; t < w.size(); t += 4) {
      const double largest = double(std::max({w[t], w[t + 1], w[t + 2]}));
      for (size_t c = 0; c < 3; ++c) {
        const double tol =
            rgbe ? brdfbake::test::kRgbeStepOfLargest * largest
                 : brdfbake::test::kBinary16Rounding * std::fabs(double(w[t + c])) + brdfbake::test::kBinary16Subnormal;
        ASSERT_NEAR(g[t + c], w[t + c], tol) << "level " << l << " texel " << t / 4 << " channel " << c;
      }
    }
  }
}

// A small equirect with some structure (cheaper to load than a builtin at 1024 x 512).
fs::path small_environment(const fs::path& dir) {
  std::vector<float> rgb;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x)
      rgb.insert(rgb.end(), {1.0f + float(x) / 16.0f, 0.5f + float(y) / 8.0f, x == 20 && y == 9 ? 500.0f : 1.0f});
  write_exr(dir / "small.exr", 64, 32, rgb);
  return dir / "small.exr";
}

TEST(CliEnv, PrefilterEveryContainer) {
  const fs::path dir = temp_dir("containers");
  const fs::path inputs = temp_dir("containers-in");
  const std::string base = "prefilter --env " + small_environment(inputs).string() + " --size 8 --min-size 2 --quiet ";
  {
    const CliRun r = run(base + "-o " + (dir / "c.ktx2").string());
    ASSERT_EQ(r.code, 0) << r.err;
    const brdfbake::io::Ktx2Image k = brdfbake::io::read_ktx2((dir / "c.ktx2").string());
    EXPECT_EQ(k.faces, 6u);
    EXPECT_EQ(k.levels, 3u);
    EXPECT_EQ(k.vk_format, brdfbake::io::kVkFormatR16G16B16A16Sfloat);
    std::string lod, def;
    for (const auto& [key, value] : k.key_values) {
      if (key == "brdfbake:lod_from_roughness") lod = value;
      if (key == "brdfbake:definition") def = value;
    }
    EXPECT_EQ(lod, "lod = (levels - 1) * roughness (levels = 3)");
    EXPECT_NE(def.find("n = v = R"), std::string::npos);
  }
  for (const std::string& args : std::vector<std::string>{
           "--pixel f32 --distribution charlie --schedule sqrt -o " + (dir / "c32.ktx2").string(),
           "-o " + (dir / "c.ktx").string(), "-o " + (dir / "c.dds").string(),
           "--format dds-legacy -o " + (dir / "legacy.dds").string(),
           "--estimator sampling --samples 64 -o " + (dir / "s.ktx2").string(),
           "--max-error 0.02 -o " + (dir / "m.ktx2").string(),
           "--layout cross --image-format hdr -o " + (dir / "cross").string() + "/",
           "--layout equirect -o " + (dir / "eq").string() + "/", "-o " + (dir / "faces").string() + "/"}) {
    const CliRun r = run(base + args);
    EXPECT_EQ(r.code, 0) << args << ": " << r.err;
  }
  EXPECT_TRUE(fs::exists(dir / "c.dds.json"));
  EXPECT_TRUE(fs::exists(dir / "cross" / "level2.hdr"));
  EXPECT_TRUE(fs::exists(dir / "eq" / "level0.exr"));
  EXPECT_TRUE(fs::exists(dir / "faces" / "level1_nz.exr"));
  EXPECT_TRUE(fs::exists(dir / "faces" / "level.json"));
  // Every container read back holds the chain: the same texels as the float32 KTX2 of the same
  // bake, within what the container keeps.
  ASSERT_EQ(run(base + "--pixel f32 -o " + (dir / "ref.ktx2").string()).code, 0);
  const brdfbake::CubeLevels want = cube_of(dir / "ref.ktx2");
  ASSERT_EQ(want.level_count(), 3);
  for (const char* file : {"c.ktx2", "c.ktx", "c.dds", "legacy.dds", "cross", "faces"})
    expect_same_cube(cube_of(dir / file), want, file, std::string(file) == "cross");
  // the equirect folder, sampled back onto the cube, stays within each level's range (a resampling
  // averages texels); the other estimators record what they did, on the same level 0
  const brdfbake::CubeLevels eq = cube_of(dir / "eq");
  ASSERT_EQ(eq.level_count(), 3);
  for (int l = 0; l < 3; ++l) {
    const auto& w = want.levels[size_t(l)];
    float lo = w[0], hi = w[0];
    for (size_t t = 0; t < w.size(); ++t)
      if (t % 4 != 3) lo = std::min(lo, w[t]), hi = std::max(hi, w[t]);
    for (size_t t = 0; t < eq.levels[size_t(l)].size(); ++t)
      if (t % 4 != 3) {
        EXPECT_GE(double(eq.levels[size_t(l)][t]), double(lo) * (1 - brdfbake::test::kBinary16Rounding))
            << "eq level " << l;
        EXPECT_LE(double(eq.levels[size_t(l)][t]), double(hi) * (1 + brdfbake::test::kBinary16Rounding))
            << "eq level " << l;
      }
  }
  const brdfbake::CubeLevels sampled = cube_of(dir / "s.ktx2"), searched = cube_of(dir / "m.ktx2");
  EXPECT_EQ(sampled.meta("estimator"), "sampling");
  EXPECT_EQ(sampled.meta("samples_per_level"), "0,64,64");
  EXPECT_EQ(searched.meta("refinement_difference_per_level").rfind("source,", 0), 0u);
  EXPECT_LE(std::stod(searched.meta("refinement_difference")), 0.02);
  for (const brdfbake::CubeLevels* c : {&sampled, &searched}) {
    ASSERT_EQ(c->level_count(), 3);
    brdfbake::CubeLevels level0 = *c, want0 = want;
    level0.levels.resize(1);
    want0.levels.resize(1);
    expect_same_cube(level0, want0, c == &sampled ? "s.ktx2 level 0" : "m.ktx2 level 0", false);
  }
  // without --quiet: a summary line (the progress line shows on terminals only)
  const CliRun loud = run("prefilter --env builtin:sun --size 8 --min-size 4 -o " + (dir / "loud.ktx2").string());
  EXPECT_EQ(loud.code, 0) << loud.err;
  EXPECT_NE(loud.err.find("ggx, 2 levels 8^2 -> 4^2, linear schedule (lod = (levels - 1) * roughness"),
            std::string::npos)
      << loud.err;
  fs::remove_all(dir);
  fs::remove_all(inputs);
}

TEST(CliEnv, Irradiance) {
  const fs::path dir = temp_dir("irradiance");
  const CliRun sh = run("irradiance --env builtin:sun --sh 5 --sh-window hanning --source-size 16 --quiet -o " +
                        (dir / "sh.json").string());
  ASSERT_EQ(sh.code, 0) << sh.err;
  const auto j = nlohmann::json::parse(std::ifstream(dir / "sh.json"));
  EXPECT_EQ(j["coefficients"], 25);
  EXPECT_EQ(j["window"], "hanning");
  const CliRun cube = run("irradiance --env builtin:studio --cube 4 --source-size 16 --quiet -o " +
                          (dir / "irr.ktx2").string() + " --sh-json " + (dir / "irr.json").string());
  ASSERT_EQ(cube.code, 0) << cube.err;
  const brdfbake::io::Ktx2Image k = brdfbake::io::read_ktx2((dir / "irr.ktx2").string());
  EXPECT_EQ(k.width, 4u);
  EXPECT_EQ(k.levels, 1u);
  EXPECT_TRUE(fs::exists(dir / "irr.json"));
  fs::remove_all(dir);
}

TEST(CliEnv, BadInputGivesOneLineAndNoOutput) {
  const fs::path dir = temp_dir("bad");
  const std::string out = " -o " + (dir / "x.ktx2").string();
  // No --env: the default environment, as in bake and in jobs.
  {
    const CliRun r = run("prefilter --size 4 --min-size 4 --quiet" + out);
    EXPECT_EQ(r.code, 0) << r.err;
    const brdfbake::io::Ktx2Image k = brdfbake::io::read_ktx2((dir / "x.ktx2").string());
    std::string source;
    for (const auto& [key, value] : k.key_values)
      if (key == "brdfbake:source") source = value;
    EXPECT_EQ(source, "builtin:studio");
    fs::remove(dir / "x.ktx2");
  }
  expect_clean_failure("prefilter --env builtin:studio --chain-size 0" + out, dir, "--chain-size");
  expect_clean_failure("prefilter --env builtin:studio --size 16 --min-size 32" + out, dir, "--min-size");
  // --size, --max-error: the old names (aliases), named canonically; both spellings together refused
  expect_clean_failure("prefilter --env builtin:studio --size abc" + out, dir, "--chain-size");
  expect_clean_failure("prefilter --env builtin:studio --chain-size 8 --size 8" + out, dir,
                       "--chain-size: given together with its alias --size (the same option): give one");
  expect_clean_failure("prefilter --env builtin:studio --distribution phong" + out, dir,
                       "--distribution: must be one of ggx, charlie (got 'phong')");
  expect_clean_failure("prefilter --env builtin:studio --schedule cubic" + out, dir,
                       "--schedule: must be one of linear, filament, sqrt, babylon (got 'cubic')");
  expect_clean_failure("prefilter --env builtin:studio --samples 64" + out, dir, "--estimator sampling");
  expect_clean_failure("prefilter --env builtin:studio --estimator sampling --samples 0" + out, dir, "--samples");
  expect_clean_failure("prefilter --env builtin:studio --max-error nan" + out, dir, "--chain-max-error");
  expect_clean_failure("prefilter --env builtin:moon" + out, dir, "builtin:moon");
  expect_clean_failure("prefilter --env builtin:studio -o " + (dir / "x.png").string(), dir, "output format");
  expect_clean_failure("prefilter --env builtin:studio --device no-such-device --size 4 --min-size 4" + out, dir,
                       "no-such-device");
  expect_clean_failure("irradiance --env builtin:studio --sh 4 -o " + (dir / "s.json").string(), dir, "--sh");
  // inputs
  const fs::path inputs = temp_dir("inputs");
  write_exr(inputs / "odd.exr", 10, 7, std::vector<float>(210, 1.0f));
  std::vector<float> nan(3 * 8 * 4, 1.0f);
  nan[3] = std::numeric_limits<float>::quiet_NaN();
  nan[7] = -1.0f;
  write_exr(inputs / "nan.exr", 8, 4, nan);
  std::ofstream(inputs / "text.hdr") << "not an image";
  expect_clean_failure("prefilter --env " + (inputs / "odd.exr").string() + out, dir, "2:1");
  expect_clean_failure("prefilter --env " + (inputs / "nan.exr").string() + out, dir,
                       "1 NaN, 0 infinite and 1 negative");
  expect_clean_failure("prefilter --env " + (inputs / "text.hdr").string() + out, dir, "cannot read environment");
  expect_clean_failure("prefilter --env " + (inputs / "missing.hdr").string() + out, dir, "no such file");
  // --sanitize accepts it and says so
  const CliRun ok = run("prefilter --env " + (inputs / "nan.exr").string() + " --sanitize --size 4 --min-size 4" + out);
  EXPECT_EQ(ok.code, 0) << ok.err;
  EXPECT_NE(ok.err.find("sanitized"), std::string::npos) << ok.err;
  fs::remove(dir / "x.ktx2");
  // unwritable output: a path through a regular file (an I/O failure: exit 1)
  std::ofstream(dir / "plain") << "x";
  const CliRun w =
      run("prefilter --env builtin:studio --size 4 --min-size 4 --quiet -o " + (dir / "plain" / "c.ktx2").string());
  EXPECT_EQ(w.code, 1);
  EXPECT_EQ(count_lines(w.err), 1) << w.err;
  EXPECT_NE(w.err.find("plain/c.ktx2"), std::string::npos) << w.err;
  EXPECT_EQ(entries(dir), 1u);
  fs::remove_all(dir);
  fs::remove_all(inputs);
}

// --pixel astc4x4 | astc6x6 (issue 24 item 9): a prefilter chain as ASTC HDR KTX2. Decoded by
// astcenc (io::read_gpu_cube, as a GPU decodes it), every level is within the storage error the
// file records of the same chain stored as f32 (the RMS relative difference over the channels
// above 0: the measure it records), and its error_bound holds both parts. A job's table reaches it
// (tables[].pixel) and bake --target khronos-viewer writes its KTX2 as ASTC; a kind, container or
// target that cannot hold ASTC is refused with exit 2 and nothing written.
TEST(CliEnv, AstcChains) {
  const fs::path dir = temp_dir("astc");
  const std::string chain = "prefilter --env builtin:sun --size 32 --min-size 4 ";
  const CliRun f32 = run(chain + "--pixel f32 --quiet -o " + (dir / "f32.ktx2").string());
  ASSERT_EQ(f32.code, 0) << f32.err;
  const brdfbake::CubeLevels want = brdfbake::io::read_gpu_cube((dir / "f32.ktx2").string());
  for (const char* block : {"astc4x4", "astc6x6"}) {
    SCOPED_TRACE(block);
    const fs::path out = dir / (std::string(block) + ".ktx2");
    const CliRun r = run(chain + "--pixel " + block + " -o " + out.string());
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE((r.out + r.err).find("ASTC"), std::string::npos) << "the summary names the encoding: " << r.out << r.err;
    std::string format;
    std::vector<std::pair<std::string, std::string>> kv;
    const brdfbake::CubeLevels got = brdfbake::io::read_gpu_cube(out.string(), &format, &kv);
    EXPECT_EQ(format, std::string(block) == "astc4x4" ? "ASTC 4x4 SFLOAT" : "ASTC 6x6 SFLOAT");
    std::map<std::string, std::string> meta(kv.begin(), kv.end());
    ASSERT_TRUE(meta.count("brdfbake:storage_error") && meta.count("brdfbake:error_bound_rel"));
    const double storage = std::stod(meta["brdfbake:storage_error"]),
                 bound = std::stod(meta["brdfbake:error_bound_rel"]);
    EXPECT_GT(storage, 0.0);
    EXPECT_GE(bound, storage);
    ASSERT_EQ(got.level_count(), want.level_count());
    for (int l = 0; l < got.level_count(); ++l) {
      double sum = 0.0;
      size_t n = 0;
      const auto& a = got.levels[size_t(l)];
      const auto& b = want.levels[size_t(l)];
      for (size_t t = 0; t < a.size(); t += 4)
        for (size_t c = 0; c < 3; ++c)
          if (b[t + c] > 0.0f) {
            const double d = (double(a[t + c]) - double(b[t + c])) / double(b[t + c]);
            sum += d * d;
            ++n;
          }
      EXPECT_LE(std::sqrt(sum / double(std::max<size_t>(n, 1))), storage) << "level " << l;
    }
  }
  // a job's table, and the target that loads ASTC
  const fs::path job = dir / "job.json";
  std::ofstream(job) << R"({"brdfbake_job": 1, "environment": "builtin:sun", "tables": [)"
                        R"({"kind": "prefilter", "size": 16, "min_size": 4, "pixel": "astc6x6", "output": "c.ktx2"}]})";
  const CliRun j = run("run " + job.string() + " -o " + (dir / "job").string() + " --quiet");
  ASSERT_EQ(j.code, 0) << j.err;
  std::string format;
  brdfbake::io::read_gpu_cube((dir / "job" / "c.ktx2").string(), &format);
  EXPECT_EQ(format, "ASTC 6x6 SFLOAT");
  const CliRun k = run("bake --env builtin:sun --target khronos-viewer --cube-size 32 --pixel astc4x4 --quiet -o " +
                       (dir / "kv").string());
  ASSERT_EQ(k.code, 0) << k.err;
  brdfbake::io::read_gpu_cube((dir / "kv" / "kv_ggx.ktx2").string(), &format);
  EXPECT_EQ(format, "ASTC 4x4 SFLOAT");
  // refused: a kind that is no chain, a container without ASTC, targets that cannot load it
  for (const std::string& args :
       {std::string("lut --size 8 --pixel astc4x4 -o ") + (dir / "x.ktx2").string(),
        chain + "--pixel astc4x4 -o " + (dir / "x.dds").string(),
        std::string("bake --env builtin:sun --target filament --pixel astc4x4 -o ") + (dir / "x").string(),
        std::string("bake --env builtin:sun --target babylon --pixel astc6x6 -o ") + (dir / "x").string()}) {
    const CliRun bad = run(args + " --quiet");
    EXPECT_EQ(bad.code, 2) << args << " -> " << bad.err;
    EXPECT_EQ(count_lines(bad.err), 1) << args << " -> " << bad.err;
    EXPECT_NE(bad.err.find("pixel"), std::string::npos) << bad.err;
  }
  std::ofstream(job) << R"({"brdfbake_job": 1, "environment": "builtin:sun", "target": "gltf", "tables": [)"
                        R"({"kind": "prefilter", "size": 16, "pixel": "astc4x4", "output": "c.ktx2"}]})";
  const CliRun bad_job = run("run " + job.string() + " -o " + (dir / "badjob").string() + " --quiet");
  EXPECT_EQ(bad_job.code, 2) << bad_job.err;
  EXPECT_NE(bad_job.err.find("tables[0].pixel"), std::string::npos) << bad_job.err;
  for (const char* left : {"x.ktx2", "x.dds", "x", "badjob"}) EXPECT_FALSE(fs::exists(dir / left)) << left;
  fs::remove_all(dir);
}

}  // namespace
