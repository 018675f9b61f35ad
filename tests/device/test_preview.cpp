// The preview family on the device: the reference render (kernels/preview.cl, the quadtree walk)
// against the double reference's brute force (host/reference/src/preview.cpp) and against closed
// forms (white furnace, the mirror), its stability (grazing rims, a 65,000 sun), its symmetry (a
// rotated environment), the split-sum render of every target from its bake, and the readers of the
// stored encodings.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <string>

#include "brdfbake/backend.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/job.hpp"
#include "brdfbake/plan.hpp"
#include "brdfbake/preview.hpp"
#include "brdfbake/reference/preview.hpp"
#include "brdfbake/view.hpp"
#include "engines/filament_dfg.hpp"
#include "families/preview/bake_files.hpp"
#include "families/preview/bake_preview.hpp"
#include "families/preview/kernel.hpp"
#include "families/preview/model.hpp"
#include "families/preview/output.hpp"
#include "families/preview/render.hpp"
#include "families/preview/shading.hpp"
#include "families/preview/splitsum.hpp"
#include "io/astc_ktx2.hpp"
#include "io/gpu_cube_read.hpp"
#include "io/packed_float.hpp"
#include "io/png_image.hpp"
#include "runtime/program.hpp"
#include "support/device_fixture.hpp"
#include "support/preview_files.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;
using test::on_backend;
using test::shared_envmap;
using test::white_hdr;
fs::path temp_dir(const std::string& name) { return test::temp_dir("preview", name); }
using json = nlohmann::json;

// ---- Tolerances, each with its reason --------------------------------------------------------------

// The target for the reference at default settings: relative RMS per sphere.
constexpr double kReferenceTarget = 5e-3;
// fp32 sums of a few thousand cells, normalised by an fp32 albedo: the furnace and the mirror come
// back to this.
constexpr double kFloatSums = 2e-5;
// A measured error may exceed the stated bound by the brute force's own convergence (subdivision 16
// against 32: below 2e-4 on these maps, tests/reference/test_preview_reference.cpp).
constexpr double kBruteForceSlack = 3e-4;
// EachSpheresBoundHoldsAgainstTheDoubleReference: the grid at its smallest (12 columns of 8-pixel
// cells), and how close to its bound's quadrature part the worst sphere must come: measured 0.57
// (dark r0.2; 0.43-0.57 on every material and roughness, 0.77 under the 256 x 128 map), so a factor
// 2 inflated to 4 fails, and a noisier device's rounding still passes.
constexpr int kBoundCheckSize = 96;
constexpr double kBoundTightness = 0.3;

EnvImage random_equirect(int width, unsigned seed, float scale = 1.0f) {
  EnvImage e;
  e.width = width;
  e.height = width / 2;
  e.source = "random";
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < 3 * e.width * e.height; ++i) e.rgb.push_back(scale * u(rng));
  return e;
}

EnvImage constant_equirect(int width, float value) {
  EnvImage e;
  e.width = width;
  e.height = width / 2;
  e.source = "constant";
  e.rgb.assign(size_t(3 * e.width * e.height), value);
  return e;
}

double rel(const double* a, const double* b) {
  double d = 0, n = 0;
  for (int c = 0; c < 3; ++c) {
    d += (a[c] - b[c]) * (a[c] - b[c]);
    n += b[c] * b[c];
  }
  return n > 0 ? std::sqrt(d / n) : std::sqrt(d);
}

Vec3 unit(double x, double y, double z) {
  const double l = std::sqrt(x * x + y * y + z * z);
  return {x / l, y / l, z / l};
}

detail::ReferencePixel pixel_of(const Vec3& n, double alpha, double albedo = 1.0, double bias = 0.0) {
  detail::ReferencePixel p;
  p.n[0] = float(n.x);
  p.n[1] = float(n.y);
  p.n[2] = float(n.z);
  p.alpha = float(alpha);
  p.albedo = float(albedo);
  p.bias = float(bias);
  return p;
}

// ---- The reference against the brute force ----------------------------------------------------------

// The spheres of the default grid (their normals at `size`), a sample of every sphere's pixels
// integrated by the kernel (at refinement 4, and 8 for the bound) and by the brute force, and the
// radiance of each material compared per sphere (Filament's BRDF: every term).
void expect_reference_agrees(const EnvImage& env, int size, int stride, const std::string& what) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  PreviewSpec spec;
  spec.width = spec.height = size;
  const PreviewSpec resolved = detail::preview::resolve_spec(spec);
  const detail::preview::Layout layout = detail::preview::make_layout(resolved);
  const auto pixels = detail::preview::sphere_pixels(layout);
  const Vec3 v = detail::preview::view_vector(layout.camera);
  std::vector<size_t> sample;  // pixels of the first row's spheres (the integrals do not depend on colour)
  for (size_t i = 0; i < pixels.size(); ++i)
    if (pixels[i].sphere < kPreviewDefaultColumns && i % size_t(stride) == 0) sample.push_back(i);
  std::vector<double> nvs, rs;
  for (size_t i : sample) nvs.push_back(std::max(pixels[i].n_dot_v, 1e-7));
  std::sort(nvs.begin(), nvs.end());
  nvs.erase(std::unique(nvs.begin(), nvs.end()), nvs.end());
  for (int j = 0; j < kPreviewDefaultColumns; ++j) rs.push_back(resolved.materials[size_t(j)].roughness);
  const std::vector<double> ab = detail::preview::exact_albedos(*backend, nvs, rs);
  detail::ReferenceTask task;
  task.environment = &env;
  task.view = v;
  task.radiance_scale = M_PI * detail::preview::median_luminance(env);
  for (size_t i : sample) {
    const auto& p = pixels[i];
    const size_t ni = size_t(std::lower_bound(nvs.begin(), nvs.end(), std::max(p.n_dot_v, 1e-7)) - nvs.begin());
    const size_t k = 2 * (size_t(p.sphere) * nvs.size() + ni);
    task.pixels.push_back(
        pixel_of(p.n, detail::preview::material_alpha(resolved.materials[size_t(p.sphere)]), ab[k], ab[k + 1]));
  }
  task.bound_pixels = task.pixels;
  const detail::ReferenceSums sums = detail::run_preview_reference(*backend, task);
  EXPECT_EQ(sums.overflows, 0u);
  const auto brdf = detail::preview::target_brdf(EngineTarget::Filament, true);
  std::vector<std::vector<double>> err(resolved.materials.size()), diff(resolved.materials.size());
  for (size_t k = 0; k < sample.size(); ++k) {
    const auto& p = pixels[sample[k]];
    const auto& t = task.pixels[k];
    const reference::PreviewIntegrals bf =
        reference::preview_integrals(env.rgb.data(), env.width, env.height, p.n, v, double(t.alpha));
    double s[9];
    for (size_t c = 0; c < 3; ++c) {
      s[c] = bf.s1[c];
      s[3 + c] = bf.s2[c];
      s[6 + c] = bf.irr[c];
    }
    for (int row = 0; row < 6; ++row) {
      const size_t sphere = size_t(row * kPreviewDefaultColumns + p.sphere);
      const PreviewMaterial& m = resolved.materials[sphere];
      const Rgb a = detail::preview::reference_radiance(brdf, m, t.albedo, t.bias, &sums.values[9 * k]);
      const Rgb b = detail::preview::reference_radiance(brdf, m, t.albedo, t.bias, s);
      const Rgb f = detail::preview::reference_radiance(brdf, m, t.albedo, t.bias, &sums.bound_values[9 * k]);
      const double x[3] = {a.r, a.g, a.b}, y[3] = {b.r, b.g, b.b}, z[3] = {f.r, f.g, f.b};
      err[sphere].push_back(rel(x, y));
      diff[sphere].push_back(rel(x, z));
    }
  }
  double worst = 0.0;
  for (size_t s = 0; s < err.size(); ++s) {
    const PreviewErrorStats e = detail::preview::error_stats(err[s]), d = detail::preview::error_stats(diff[s]);
    const double bound = kPreviewBoundFactor * d.rms;
    worst = std::max(worst, e.rms);
    EXPECT_LE(e.rms, kReferenceTarget) << what << ": " << resolved.materials[s].name;
    EXPECT_LE(e.rms, bound + kBruteForceSlack)
        << what << ": " << resolved.materials[s].name << ": the stated bound " << bound << " is below the error";
  }
  std::printf("%s: worst sphere %.2e RMS against the brute force (%zu pixels a sphere)\n", what.c_str(), worst,
              err[0].size());
}

TEST(PreviewReference, AgreesWithTheDoubleReference) {
  const std::string file = shared_envmap("derived/venice_sunset_256x128_derived.hdr");
  if (!fs::exists(file)) GTEST_SKIP() << "no " << file;
  expect_reference_agrees(load_environment(file), 256, 11, "venice 256x128");
}

TEST(PreviewReference, AgreesWithTheDoubleReferenceUnderASun) {
  // rooitou_park: a sun of luminance 65,000 carrying 65% of the energy in 30 pixels
  const std::string file = shared_envmap("rooitou_park_1k.hdr");
  if (!fs::exists(file)) GTEST_SKIP() << "no " << file;
  expect_reference_agrees(load_environment(file), 512, 211, "rooitou_park 1k");
}

// ---- Closed forms ------------------------------------------------------------------------------------

TEST(PreviewReference, WhiteFurnaceGivesTheAlbedos) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const EnvImage env = constant_equirect(128, 1.0f);
  const std::vector<double> nvs = {1e-3, 0.05, 0.3, 0.7, 1.0}, rs = {0.0, 0.05, 0.3, 1.0};
  const std::vector<double> ab = detail::preview::exact_albedos(*backend, nvs, rs);
  detail::ReferenceTask task;
  task.environment = &env;
  task.view = {0.0, 0.0, 1.0};
  for (size_t j = 0; j < rs.size(); ++j)
    for (size_t i = 0; i < nvs.size(); ++i) {
      const double s = std::sqrt(1.0 - nvs[i] * nvs[i]);
      const size_t k = 2 * (j * nvs.size() + i);
      task.pixels.push_back(pixel_of(unit(0.6 * s, 0.8 * s, nvs[i]), rs[j] * rs[j], ab[k], ab[k + 1]));
    }
  const detail::ReferenceSums sums = detail::run_preview_reference(*backend, task);
  for (size_t q = 0; q < task.pixels.size(); ++q) {
    const auto& p = task.pixels[q];
    const double* s = &sums.values[9 * q];
    const double fc = std::pow(1.0 - double(p.n[2]), 5.0);
    // the lobe's albedos (roughness 0: the mirror, 1 and Fc exactly) and pi
    const double a = p.alpha > 0.0f ? double(p.albedo) : 1.0, b = p.alpha > 0.0f ? double(p.bias) : fc;
    EXPECT_NEAR(s[0], a, kFloatSums) << "n.v " << p.n[2] << " alpha " << p.alpha;
    EXPECT_NEAR(s[3], b, kFloatSums) << "n.v " << p.n[2] << " alpha " << p.alpha;
    EXPECT_NEAR(s[6] / M_PI, 1.0, kFloatSums) << "n.v " << p.n[2];
    // a white metal with the compensation reflects all of it: (1 + (1 / A - 1)) A = 1
    PreviewMaterial white_metal;
    white_metal.base_color = {1.0, 1.0, 1.0};
    white_metal.metallic = 1.0;
    const Rgb r = detail::preview::reference_radiance(detail::preview::target_brdf(EngineTarget::Filament, true),
                                                      white_metal, a, b, s);
    EXPECT_NEAR(r.g, 1.0, 2 * kFloatSums);
  }
}

TEST(PreviewReference, RoughnessZeroIsTheMirrorTimesFresnel) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const EnvImage env = random_equirect(256, 5);
  detail::ReferenceTask task;
  task.environment = &env;
  task.view = unit(0.2, -0.1, 1.0);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec3> normals;
  while (normals.size() < 64) {
    const Vec3 n = unit(u(rng), u(rng), u(rng));
    if (math::dot(n, task.view) > 0.01) normals.push_back(n);
  }
  for (const Vec3& n : normals) task.pixels.push_back(pixel_of(n, 0.0));
  const detail::ReferenceSums sums = detail::run_preview_reference(*backend, task);
  for (size_t q = 0; q < normals.size(); ++q) {
    const reference::PreviewIntegrals r =
        reference::preview_integrals(env.rgb.data(), env.width, env.height, normals[q], task.view, 0.0);
    for (size_t c = 0; c < 3; ++c) {
      EXPECT_NEAR(sums.values[9 * q + c], r.s1[c], 1e-6) << q;  // the same pixel's radiance
      EXPECT_NEAR(sums.values[9 * q + 3 + c], r.s2[c], 1e-6) << q;
    }
  }
}

// ---- Stability -----------------------------------------------------------------------------------------

TEST(PreviewReference, GrazingRimsStayFinite) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const EnvImage env = random_equirect(256, 7, 4.0f);
  const std::vector<double> nvs = {1e-6, 1e-4, 1e-2}, rs = {0.05, 0.5, 1.0};
  const std::vector<double> ab = detail::preview::exact_albedos(*backend, nvs, rs);
  detail::ReferenceTask task;
  task.environment = &env;
  task.view = {0.0, 0.0, 1.0};
  for (size_t j = 0; j < rs.size(); ++j)
    for (size_t i = 0; i < nvs.size(); ++i) {
      const size_t k = 2 * (j * nvs.size() + i);
      task.pixels.push_back(
          pixel_of(unit(std::sqrt(1.0 - nvs[i] * nvs[i]), 0.0, nvs[i]), rs[j] * rs[j], ab[k], ab[k + 1]));
    }
  const detail::ReferenceSums sums = detail::run_preview_reference(*backend, task);
  EXPECT_EQ(sums.overflows, 0u);
  for (size_t q = 0; q < task.pixels.size(); ++q)
    for (int c = 0; c < 9; ++c) {
      const double x = sums.values[9 * q + size_t(c)];
      EXPECT_TRUE(std::isfinite(x) && x >= 0.0) << q << ": " << x;
      // no integral exceeds the largest radiance times its albedo (A <= 1, the cosine's pi)
      EXPECT_LE(x, 4.0 * (c >= 6 ? M_PI : 1.0) * (1 + 1e-4)) << q;
    }
}

TEST(PreviewReference, RotatingTheEnvironmentRotatesTheRender) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  // a quarter turn about +Y is a shift by a quarter of the columns (longitude phi = 2 pi (0.5 - u))
  const EnvImage a = random_equirect(256, 11);
  EnvImage b = a;
  const int w = a.width, h = a.height;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) b.rgb[size_t(3 * (y * w + (x + w / 4) % w) + c)] = a.rgb[size_t(3 * (y * w + x) + c)];
  // the same spheres seen by a camera turned by the same quarter: phi decreases by pi / 2
  PreviewSpec spec;
  spec.width = spec.height = 128;
  spec.materials = {PreviewMaterial{"m", {0.5, 0.5, 0.5}, 0.0, 0.3, {}}};
  const auto la = detail::preview::make_layout(detail::preview::resolve_spec(spec));
  spec.yaw = -90.0;
  const auto lb = detail::preview::make_layout(detail::preview::resolve_spec(spec));
  const auto pa = detail::preview::sphere_pixels(la), pb = detail::preview::sphere_pixels(lb);
  ASSERT_EQ(pa.size(), pb.size());
  detail::ReferenceTask ta, tb;
  ta.environment = &a;
  tb.environment = &b;
  ta.view = detail::preview::view_vector(la.camera);
  tb.view = detail::preview::view_vector(lb.camera);
  for (size_t i = 0; i < pa.size(); i += 7) {
    ta.pixels.push_back(pixel_of(pa[i].n, 0.09, 0.98, 0.01));
    tb.pixels.push_back(pixel_of(pb[i].n, 0.09, 0.98, 0.01));
  }
  const auto sa = detail::run_preview_reference(*backend, ta), sb = detail::run_preview_reference(*backend, tb);
  double worst = 0.0;
  for (size_t q = 0; q < ta.pixels.size(); ++q)
    for (int k = 0; k < 3; ++k)
      worst = std::max(worst, rel(&sa.values[9 * q + 3 * size_t(k)], &sb.values[9 * q + 3 * size_t(k)]));
  // the quadtree of the shifted image is the same tree shifted (a quarter of 256 columns is a whole
  // number of cells of every level walked): only float rounding differs
  EXPECT_LT(worst, 1e-4);
}

TEST(PreviewReference, TheReferenceBackendAgrees) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto device_backend = Backend::open(*dev);
  auto reference_backend = Backend::open("reference");
  const EnvImage env = random_equirect(64, 13);
  detail::ReferenceTask task;
  task.environment = &env;
  task.view = {0.0, 0.0, 1.0};
  const std::vector<double> nvs = {0.3, 0.8}, rs = {0.2, 0.7};
  const std::vector<double> ab = detail::preview::exact_albedos(*device_backend, nvs, rs);
  for (size_t j = 0; j < rs.size(); ++j)
    for (size_t i = 0; i < nvs.size(); ++i) {
      const double s = std::sqrt(1.0 - nvs[i] * nvs[i]);
      const size_t k = 2 * (j * nvs.size() + i);
      task.pixels.push_back(pixel_of(unit(-0.8 * s, 0.6 * s, nvs[i]), rs[j] * rs[j], ab[k], ab[k + 1]));
    }
  const auto d = detail::run_preview_reference(*device_backend, task);
  const auto r = detail::run_preview_reference(*reference_backend, task);
  for (size_t q = 0; q < task.pixels.size(); ++q)
    for (size_t k = 0; k < 3; ++k)
      EXPECT_LT(rel(&d.values[9 * q + 3 * k], &r.values[9 * q + 3 * k]), kReferenceTarget) << q;
}

TEST(PreviewReference, KernelBuildsWithoutWarnings) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  for (Precision p : {Precision::Fp32, Precision::Fp64}) {
    if (p == Precision::Fp64 && !dev->info().fp64) continue;
    detail::ProgramSpec spec;
    spec.file = "preview.cl";
    spec.precision = p;
    const cl::Program program = detail::build_program(dev->impl(), spec);
    const std::string log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(dev->impl().device);
    EXPECT_EQ(log.find("warning"), std::string::npos) << precision_name(p) << ":\n" << log;
  }
}

// ---- The split-sum render of every target ---------------------------------------------------------------

TEST(PreviewRender, EveryTargetFromItsBakeWithTheLayoutInTheJson) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const EnvImage env = load_environment("builtin:sun", EnvLoadOptions{false, 256, 0});
  for (const std::string& name : engine_target_names()) {
    PreviewSpec spec;
    spec.target = engine_target_from_name(name);
    spec.width = 96;
    spec.height = 48;
    spec.bound_stride = 64;
    const PreviewResult r = render_preview(*backend, env, spec);
    ASSERT_EQ(r.stats.size(), r.spheres.size()) << name;
    // the split-sum render may go negative where an engine's SH rings (generic and Babylon.js do not
    // clamp it): finite is all it owes
    for (float x : r.splitsum.rgb) ASSERT_TRUE(std::isfinite(x)) << name;
    for (float x : r.reference.rgb) ASSERT_TRUE(std::isfinite(x) && x >= 0.0f) << name;
    for (const auto& s : r.stats) {
      EXPECT_GT(s.reference_rms_bound, 0.0) << name << ": a bound is never 0";
      EXPECT_LE(s.reference_rms_bound, kReferenceTarget) << name;
    }
    EXPECT_FALSE(r.shading.empty()) << name;
    // the JSON holds what recomputes a pixel: centre, radius, camera, BRDF, material
    const fs::path dir = temp_dir(name);
    detail::preview::write_preview(r, "builtin:sun", (dir / "p.png").string());
    std::ifstream in(dir / "p.json");
    const json j = json::parse(in);
    EXPECT_EQ(j["target"], name);
    EXPECT_EQ(j["spheres"].size(), r.spheres.size());
    EXPECT_TRUE(j["spheres"][0].contains("centre") && j["spheres"][0].contains("radius"));
    EXPECT_TRUE(j["camera"].contains("view_direction") && j["camera"].contains("up"));
    EXPECT_TRUE(j["spheres"][0]["error"]["linear"].contains("p99"));
    EXPECT_TRUE(fs::exists(dir / "p_splitsum.exr") && fs::exists(dir / "p_reference.exr") && fs::exists(dir / "p.png"));
  }
}

// A white furnace through a whole bake: a uniform environment (RGBE, flat scanlines) baked first for
// Filament, a white metal and a white dielectric. The metal reflects the environment exactly in both
// renders; the dielectric's split-sum render differs from the reference only by the DFG table's
// bilinear lookup (its metadata's interpolation_error: 1.75% at 128 x 128) and binary16.
TEST(PreviewRender, WhiteFurnaceInBothPaths) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const fs::path dir = temp_dir("furnace");
  {
    std::ofstream f(dir / "white.hdr", std::ios::binary);
    f << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 64 +X 128\n";
    for (int i = 0; i < 128 * 64; ++i) f.write("\x80\x80\x80\x81", 4);
  }
  const EnvImage env = load_environment((dir / "white.hdr").string());
  const double l = env.rgb[0];
  PreviewSpec spec;
  spec.target = EngineTarget::Filament;
  spec.width = 64;
  spec.height = 32;
  spec.materials = {PreviewMaterial{"metal", {1.0, 1.0, 1.0}, 1.0, 0.4, {}},
                    PreviewMaterial{"dielectric", {1.0, 1.0, 1.0}, 0.0, 0.4, {}}};
  const PreviewResult r = render_preview(*backend, env, spec);
  const auto pixels = detail::preview::sphere_pixels(detail::preview::make_layout(r.spec));
  for (const auto& p : pixels) {
    const size_t at = 3 * (size_t(p.y) * size_t(r.spec.width) + size_t(p.x));
    const double s = r.splitsum.rgb[at + 1], f = r.reference.rgb[at + 1];
    if (p.sphere == 0) {
      EXPECT_NEAR(s / l, 1.0, 2e-3) << "split-sum, n.v " << p.n_dot_v;  // binary16 and R11F_G11F_B10F (2^-7)
      EXPECT_NEAR(f / l, 1.0, 1e-4) << "reference, n.v " << p.n_dot_v;
    } else {
      EXPECT_NEAR(s / f, 1.0, 0.02) << "n.v " << p.n_dot_v;
    }
  }
}

TEST(PreviewRender, ASunClippedByTheStorageShowsInTheError) {
  // rooitou_park's sun (65,000) through Babylon.js's RGBD (at most 255): the rough metals lose the sun,
  // and the error says so; the reference's bound stays within target.
  const std::string file = shared_envmap("rooitou_park_1k.hdr");
  if (!fs::exists(file)) GTEST_SKIP() << "no " << file;
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  PreviewSpec spec;
  spec.target = EngineTarget::Babylon;
  spec.width = spec.height = 192;
  spec.bound_stride = 64;
  const PreviewResult r = render_preview(*backend, load_environment(file), spec);
  for (size_t s = 0; s < r.spheres.size(); ++s) {
    EXPECT_LE(r.stats[s].reference_rms_bound, kReferenceTarget) << r.spheres[s].material.name;
    if (r.spheres[s].material.name == "gold r0.5") {
      EXPECT_GT(r.stats[s].linear.rms, 0.2) << "the clipped sun is missing from the split-sum render";
    }
  }
}

// ---- bake --preview ---------------------------------------------------------------------------------

// A small bake for Filament (the plumbing, not the tables) with Job::preview.
Job small_preview_job(const fs::path& out) {
  PlanOptions o;
  o.environment = "builtin:sun";
  o.target = "filament";
  o.lut_size = 16;
  o.chain_size = 16;
  o.cube_min_size = 8;
  o.chain_max_error = 0.0;
  Plan plan = plan_default(o);
  plan.job.output_dir = out.string();
  plan.job.preview = true;
  return plan.job;
}

// small_preview_job's files without the preview, in a fresh temp folder named `name`.
fs::path small_bake(Backend& backend, const std::string& name) {
  const fs::path out = temp_dir(name) / "filament";
  Job job = small_preview_job(out);
  job.preview = false;
  run_job(job, {}, on_backend(backend));
  return out;
}

// The preview of a bake's own files lands with them (named after the folder they land in, not the
// staging folder it was rendered from), and the manifest lists it with numbers that are the JSON's.
TEST(PreviewBake, ThePreviewLandsWithTheFilesAndTheManifestRecordsIt) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const fs::path out = temp_dir("bake") / "sun";
  fs::remove_all(out);
  const Manifest m = run_job(small_preview_job(out), {}, on_backend(*backend));
  for (const char* f : {"preview.png", "preview_splitsum.exr", "preview_reference.exr", "preview.json"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  std::ifstream min(out / "manifest.json");
  const json manifest = json::parse(min);
  ASSERT_TRUE(manifest.contains("preview"));
  EXPECT_EQ(manifest["preview"]["files"].size(), 4u);
  EXPECT_EQ(manifest["preview"]["target"], "filament");
  std::ifstream pin(out / "preview.json");
  const std::string text((std::istreambuf_iterator<char>(pin)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text.find(".tmp-"), std::string::npos) << "the staging folder's name leaked into preview.json";
  const json p = json::parse(text);
  EXPECT_EQ(p["bake"]["folder"], out.string());
  EXPECT_EQ(p["target"], "filament");
  ASSERT_EQ(p["spheres"].size(), 72u);  // the default grid
  double worst = 0.0, bound = 0.0;
  for (const auto& sphere : p["spheres"]) {
    worst = std::max(worst, sphere["error"]["linear"]["rms"].get<double>());
    bound = std::max(bound, sphere["reference_bound"]["rms"].get<double>());
  }
  // the manifest's numbers are printed with 4 significant digits
  EXPECT_NEAR(std::stod(manifest["preview"]["error_rms_max"].get<std::string>()), worst, 1e-3 * worst);
  EXPECT_NEAR(std::stod(manifest["preview"]["reference_bound_max"].get<std::string>()), bound, 1e-3 * bound);
  EXPECT_GT(worst, 0.0);
  EXPECT_LE(bound, kReferenceTarget);

  // `view` shows the preview's sheet as drawn: the folder (through its manifest), the JSON, the sheet.
  const io::PngImage png = io::read_png((out / "preview.png").string());
  ViewOptions vo;
  vo.max_width = png.width + 64;  // no scaling (the sheet has margins): the pixels are the preview sheet's
  for (const fs::path& given : {out, out / "preview.json", out / "preview.png"}) {
    const ContactSheet sheet = render_contact_sheet({given.string()}, vo);
    const auto region = std::find_if(sheet.regions.begin(), sheet.regions.end(),
                                     [](const SheetRegion& r) { return r.role == "preview sheet"; });
    ASSERT_NE(region, sheet.regions.end()) << given;
    ASSERT_EQ(region->width, png.width) << given;
    ASSERT_EQ(region->height, png.height) << given;
    int differ = 0;
    for (int y = 0; y < png.height; ++y)
      for (int x = 0; x < png.width; ++x)
        for (int c = 0; c < 3; ++c)
          differ += sheet.rgb[3 * (size_t(region->y + y) * size_t(sheet.width) + size_t(region->x + x)) + size_t(c)] !=
                    png.at(x, y, c);
    EXPECT_EQ(differ, 0) << given;
    const bool titled = std::any_of(sheet.regions.begin(), sheet.regions.end(), [](const SheetRegion& r) {
      return r.role == "file title" && r.label.find("(preview)") != std::string::npos;
    });
    EXPECT_TRUE(titled) << given;
  }
}

TEST(PreviewBake, AJobWithoutWhatThePreviewReadsFailsBeforeAnyBake) {
  const fs::path out = temp_dir("bake-refused") / "none";
  fs::remove_all(out);
  Job job = small_preview_job(out);
  job.tables.erase(std::remove_if(job.tables.begin(), job.tables.end(),
                                  [](const TableRequest& t) { return t.kind == TableKind::Irradiance; }),
                   job.tables.end());
  job.target = "generic";
  try {
    run_job(job);
    FAIL() << "a preview without an irradiance table";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no irradiance table"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(out));
  Job clash = small_preview_job(out);
  clash.tables.front().output = "preview.json";
  EXPECT_THROW(detail::preview::check_bake_preview(clash), Error);
}

// ---- The scene and the inputs ----------------------------------------------------------------------

// Every sphere whole (its disc inside the image, rims included) and inside its own cell, for the
// default grid and for a glTF scene's materials (one sphere each, in the file's order).
TEST(PreviewScene, EverySphereIsWholeAndEveryMaterialHasOne) {
  const std::string scene = (fs::path(BRDFBAKE_SHARED_DIR) / "scenes" / "SheenChair.gltf").string();
  std::vector<PreviewSpec> specs(2);
  specs[1].materials_file = scene;
  specs[1].width = 300;
  specs[1].height = 200;
  for (const PreviewSpec& spec : specs) {
    if (!spec.materials_file.empty() && !fs::exists(spec.materials_file)) continue;
    const PreviewSpec resolved = detail::preview::resolve_spec(spec);
    const auto layout = detail::preview::make_layout(resolved);
    for (size_t a = 0; a < layout.spheres.size(); ++a) {
      const PreviewSphere& s = layout.spheres[a];
      EXPECT_GE(s.centre_x - s.radius, 0.0) << s.material.name;
      EXPECT_LE(s.centre_x + s.radius, double(layout.width)) << s.material.name;
      EXPECT_GE(s.centre_y - s.radius, 0.0) << s.material.name;
      EXPECT_LE(s.centre_y + s.radius, double(layout.height)) << s.material.name;
      for (size_t b = a + 1; b < layout.spheres.size(); ++b) {
        const PreviewSphere& t = layout.spheres[b];
        EXPECT_GE(std::hypot(s.centre_x - t.centre_x, s.centre_y - t.centre_y), s.radius + t.radius)
            << s.material.name << " overlaps " << t.material.name;
      }
    }
    if (spec.materials_file.empty()) {
      ASSERT_EQ(layout.spheres.size(), 72u);
      EXPECT_EQ(layout.spheres[11].material.roughness, 1.0);
      EXPECT_EQ(layout.spheres[71].material.metallic, 1.0);
    } else {
      std::ifstream in(scene);
      const json gltf = json::parse(in);
      ASSERT_EQ(layout.spheres.size(), gltf["materials"].size());
      for (size_t k = 0; k < layout.spheres.size(); ++k)
        EXPECT_EQ(layout.spheres[k].material.name, gltf["materials"][k]["name"]) << k;
      // what the preview does not render is said: the velvets' sheen
      EXPECT_FALSE(layout.spheres[0].material.notes.empty());
    }
  }
}

// A bake folder for another target or from another environment is refused with what to do, and so
// is a material file that is not there.
TEST(PreviewScene, ABakeOfAnotherTargetOrEnvironmentIsRefused) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const fs::path out = small_bake(*backend, "other");
  auto message = [&](EngineTarget target, const std::string& env) {
    try {
      detail::preview::read_bake_files(out.string(), target, env);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(EngineTarget::Babylon, "builtin:sun").find("baked for target filament, not babylon"),
            std::string::npos);
  EXPECT_NE(message(EngineTarget::Filament, "builtin:studio").find("baked from 'builtin:sun'"), std::string::npos);
  EXPECT_EQ(message(EngineTarget::Filament, "builtin:sun"), "no error");
  PreviewSpec spec;
  spec.materials_file = (out / "none.json").string();
  EXPECT_THROW(detail::preview::resolve_spec(spec), Error);
}

// A sphere whose bound exceeds spec.bound_goal is integrated again at twice the refinement, alone: its
// pixels and bound are those of a render at the refinement it reached, while a sphere within the goal
// keeps the first pass. At refinement 1 under the built-in sun, the r0.3 metal's bound is above a goal
// of 0.2 % and the rough dielectric's below it.
TEST(PreviewReference, ASphereAboveTheBoundGoalIsIntegratedAgainFiner) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const fs::path out = small_bake(*backend, "goal");
  PreviewSpec spec;
  spec.target = EngineTarget::Filament;
  spec.bake = out.string();
  spec.width = 96;
  spec.height = 48;
  spec.refinement = 1.0;
  PreviewMaterial metal, rough;
  metal.name = "silver r0.3";
  metal.base_color = {0.97, 0.96, 0.91};
  metal.metallic = 1.0;
  metal.roughness = 0.3;
  rough.name = "white r1";
  rough.base_color = {0.8, 0.8, 0.8};
  rough.roughness = 1.0;
  spec.materials = {metal, rough};
  const EnvImage env = load_environment("builtin:sun");
  spec.bound_goal = 0.0;  // never refined: the first pass alone
  const PreviewResult first = render_preview(*backend, env, spec);
  spec.bound_goal = 0.002;
  const PreviewResult refined = render_preview(*backend, env, spec);
  ASSERT_EQ(first.stats.size(), 2u);
  ASSERT_EQ(refined.stats.size(), 2u);
  EXPECT_EQ(first.stats[0].refinement, 1.0);
  std::printf("bounds at refinement 1: %.2e (metal), %.2e (dielectric)\n", first.stats[0].reference_rms_bound,
              first.stats[1].reference_rms_bound);
  EXPECT_GT(first.stats[0].reference_rms_bound, spec.bound_goal) << "the test needs a sphere above the goal";
  EXPECT_LE(first.stats[1].reference_rms_bound, spec.bound_goal) << "the test needs a sphere within the goal";
  // the metal refined until within the goal (or as far as two doublings reach), the dielectric not
  EXPECT_GT(refined.stats[0].refinement, 1.0);
  EXPECT_TRUE(refined.stats[0].reference_rms_bound <= spec.bound_goal || refined.stats[0].refinement == 4.0)
      << refined.stats[0].reference_rms_bound;
  EXPECT_LT(refined.stats[0].reference_rms_bound, first.stats[0].reference_rms_bound);
  EXPECT_EQ(refined.stats[1].refinement, 1.0);
  EXPECT_EQ(refined.stats[1].reference_rms_bound, first.stats[1].reference_rms_bound);
  // the refined sphere's pixels are a render at its refinement (each pixel is integrated alone), the
  // other sphere's the first pass's
  spec.refinement = refined.stats[0].refinement;
  spec.bound_goal = 0.0;
  const PreviewResult direct = render_preview(*backend, env, spec);
  EXPECT_EQ(direct.stats[0].reference_rms_bound, refined.stats[0].reference_rms_bound);
  size_t metal_pixels = 0, rough_pixels = 0;
  const auto layout = detail::preview::make_layout(detail::preview::resolve_spec(spec));
  for (const auto& p : detail::preview::sphere_pixels(layout)) {
    const size_t at = 3 * (size_t(p.y) * size_t(spec.width) + size_t(p.x));
    const PreviewResult& expected = p.sphere == 0 ? direct : first;
    for (size_t c = 0; c < 3; ++c)
      ASSERT_EQ(refined.reference.rgb[at + c], expected.reference.rgb[at + c]) << p.x << ", " << p.y;
    ++(p.sphere == 0 ? metal_pixels : rough_pixels);
  }
  EXPECT_GT(metal_pixels, 100u);
  EXPECT_GT(rough_pixels, 100u);
}

// ---- Each sphere's stated bound against the double reference ---------------------------------------------

// `e` at half its width and height, each pixel the mean of 2 x 2 (the source's name kept: its bake
// is of the same map).
EnvImage half_equirect(const EnvImage& e) {
  EnvImage h = e;
  h.width = e.width / 2;
  h.height = e.height / 2;
  h.rgb.assign(size_t(3 * h.width * h.height), 0.0f);
  for (int y = 0; y < h.height; ++y)
    for (int x = 0; x < h.width; ++x)
      for (int c = 0; c < 3; ++c) {
        float sum = 0.0f;
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx)
            sum += e.rgb[3 * (size_t(2 * y + dy) * size_t(e.width) + size_t(2 * x + dx)) + size_t(c)];
        h.rgb[3 * (size_t(y) * size_t(h.width) + size_t(x)) + size_t(c)] = 0.25f * sum;
      }
  return h;
}

// Issue 35: the bound each sphere states (reference_rms_bound) holds against an independent
// computation on every sphere, and is not vacuous. The default grid (72 spheres) rendered at its
// smallest (96 x 96) on the device, and again on the reference backend: every pixel by the double
// brute force (host/reference/src/preview.cpp, subdivision 16) from the same bake, under venice at
// 128 x 64 (the brute force's work is the map's pixels: 14 s of CPU); per sphere the RMS over all
// its pixels of |device - double| / |double| (RGB norms). The brute force shares the environment's
// model (constant cells), so what it checks is the bound's quadrature part, 2 x the difference to
// twice the refinement: the stated bound less kPreviewBoundFloor (what only a check with another
// model of the map resolves, brdfbake/preview.hpp), and so the stated bound itself. A factor halved
// (issue 35: caught only by another test's precondition) fails on nearly every sphere; a bound
// inflated fails kBoundTightness.
TEST(PreviewReference, EachSpheresBoundHoldsAgainstTheDoubleReference) {
  const std::string file = shared_envmap("derived/venice_sunset_256x128_derived.hdr");
  if (!fs::exists(file)) GTEST_SKIP() << "no " << file;
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto device = Backend::open(*dev);
  auto reference = Backend::open("reference");
  // a small bake of the map's own (the split-sum render is not what is measured here)
  PlanOptions o;
  o.environment = file;
  o.target = "filament";
  o.lut_size = 16;
  o.chain_size = 16;
  o.cube_min_size = 8;
  o.chain_max_error = 0.0;
  Plan plan = plan_default(o);
  plan.job.output_dir = (temp_dir("bound-vs-double") / "filament").string();
  run_job(plan.job, {}, on_backend(*device));
  const EnvImage env = half_equirect(load_environment(file));
  PreviewSpec spec;
  spec.target = EngineTarget::Filament;
  spec.bake = plan.job.output_dir;
  spec.width = spec.height = kBoundCheckSize;
  spec.shares = false;
  const auto t0 = std::chrono::steady_clock::now();
  const PreviewResult d = render_preview(*device, env, spec);
  const auto t1 = std::chrono::steady_clock::now();
  // the brute force's own bound is not used: its fewest pixels (16 a sphere, at subdivision 32), and
  // no sphere integrated again (the brute force has no refinement to double)
  spec.bound_stride = 1 << 20;
  spec.bound_goal = 0.0;
  const PreviewResult r = render_preview(*reference, env, spec);
  const auto t2 = std::chrono::steady_clock::now();
  std::printf("device render %.1f s, double brute force %.1f s\n", std::chrono::duration<double>(t1 - t0).count(),
              std::chrono::duration<double>(t2 - t1).count());
  ASSERT_EQ(d.stats.size(), 72u);
  ASSERT_EQ(r.stats.size(), d.stats.size());

  const auto layout = detail::preview::make_layout(d.spec);
  std::vector<std::vector<double>> diff(d.spheres.size());
  for (const auto& p : detail::preview::sphere_pixels(layout)) {
    const size_t at = 3 * (size_t(p.y) * size_t(d.spec.width) + size_t(p.x));
    const double a[3] = {d.reference.rgb[at], d.reference.rgb[at + 1], d.reference.rgb[at + 2]};
    const double b[3] = {r.reference.rgb[at], r.reference.rgb[at + 1], r.reference.rgb[at + 2]};
    diff[size_t(p.sphere)].push_back(rel(a, b));
  }
  double worst = 0.0, worst_stated = 0.0;
  std::string worst_name;
  std::map<std::string, double> row_worst, column_worst;  // per material, per roughness
  for (size_t s = 0; s < d.spheres.size(); ++s) {
    const std::string& name = d.spheres[s].material.name;
    const double rms = detail::preview::error_stats(diff[s]).rms, stated = d.stats[s].reference_rms_bound;
    const double quadrature = stated - kPreviewBoundFloor;
    EXPECT_LE(rms, stated) << name << ": " << diff[s].size() << " pixels";
    EXPECT_LE(rms, quadrature) << name << ": the quadrature's part of the bound";
    const double ratio = rms / quadrature;
    std::printf("%-14s rms %.2e, bound %.2e (quadrature %.2e): %.2f of the quadrature's, %.2f of the bound\n",
                name.c_str(), rms, stated, quadrature, ratio, rms / stated);
    const std::string row = name.substr(0, name.find(' ')), column = name.substr(name.find(' ') + 1);
    row_worst[row] = std::max(row_worst[row], ratio);
    column_worst[column] = std::max(column_worst[column], ratio);
    worst_stated = std::max(worst_stated, rms / stated);
    if (ratio > worst) worst = ratio, worst_name = name;
  }
  for (const auto& [k, v] : row_worst) std::printf("worst of the quadrature's part, %s: %.2f\n", k.c_str(), v);
  for (const auto& [k, v] : column_worst) std::printf("worst of the quadrature's part, %s: %.2f\n", k.c_str(), v);
  std::printf("worst: %.2f of the quadrature's part (%s), %.2f of a stated bound\n", worst, worst_name.c_str(),
              worst_stated);
  EXPECT_GE(worst, kBoundTightness) << worst_name << ": the bound is far above the error on every sphere";
}

// ---- The stored encodings read back --------------------------------------------------------------------

CubeLevels random_cube(int size, int levels, float scale) {
  CubeLevels c;
  c.size = size;
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u(0.0f, scale);
  for (int l = 0; l < levels; ++l) {
    const size_t s = size_t(c.level_size(l));
    std::vector<float> v(4 * 6 * s * s);
    for (size_t t = 0; t < v.size(); ++t) v[t] = t % 4 == 3 ? 1.0f : u(rng);
    c.levels.push_back(v);
  }
  return c;
}

TEST(PreviewDecode, PackedFloatKtx1ReadsAsItWasEncoded) {
  const fs::path dir = temp_dir("r11");
  const CubeLevels cube = random_cube(8, 3, 100.0f);
  write_cubemap(cube, (dir / "c.ktx").string(), CubeFormat::Ktx1, CubeWriteOptions{PixelType::R11G11B10});
  std::string format;
  const CubeLevels back = io::read_gpu_cube((dir / "c.ktx").string(), &format);
  EXPECT_EQ(format, "R11F_G11F_B10F");
  ASSERT_EQ(back.level_count(), 3);
  for (int l = 0; l < 3; ++l)
    for (size_t t = 0; t < cube.levels[size_t(l)].size() / 4; ++t) {
      float expect[3];
      io::unpack_r11g11b10(io::pack_r11g11b10(cube.levels[size_t(l)][4 * t], cube.levels[size_t(l)][4 * t + 1],
                                              cube.levels[size_t(l)][4 * t + 2]),
                           expect);
      for (size_t c = 0; c < 3; ++c) ASSERT_EQ(back.levels[size_t(l)][4 * t + c], expect[c]) << l << " " << t;
    }
}

TEST(PreviewDecode, AstcReadsAsTheEncoderDecodedIt) {
  const fs::path dir = temp_dir("astc");
  const CubeLevels cube = random_cube(16, 2, 10.0f);
  const io::AstcCube stored = io::write_astc_ktx2_cube(cube, (dir / "c.ktx2").string(), 4, 10.0);
  const CubeLevels back = io::read_gpu_cube((dir / "c.ktx2").string());
  ASSERT_EQ(back.level_count(), 2);
  for (size_t l = 0; l < 2; ++l)
    for (size_t t = 0; t < back.levels[l].size(); ++t)
      if (t % 4 != 3) {
        ASSERT_EQ(back.levels[l][t], stored.decoded[l][t]) << l << " " << t;
      }
}

// ---- The extensions' lobes (KHR_materials_ior, _specular, ...) -------------------------------------

// What render_preview bakes first for `target` (detail::preview::first_bake_plan: the standard set;
// with `sheen` the Charlie chain and table too), with `o`'s settings, baked into `dir`/bake-TARGET
// on `backend`: a test passes the folder as PreviewSpec::bake to render twice from one bake.
std::string first_bake(Backend& backend, const EnvImage& env, EngineTarget target, bool sheen, const fs::path& dir,
                       const PlanOptions& o = {}) {
  Plan plan = detail::preview::first_bake_plan(env, target, sheen, o);
  plan.job.output_dir = (dir / ("bake-" + std::string(engine_target_name(target)))).string();
  run_job(plan.job, {}, on_backend(backend));
  return plan.job.output_dir;
}

// A white furnace's first bake with 16² chains instead of the default 256². The environment is
// uniform, so every texel of every level of every chain is the same radiance and a chain's size
// changes no pixel of the renders; the DFG and charlie tables keep their default 128² (the furnace
// tests' tolerances are its bilinear lookup). The default chains were three quarters of these
// tests' time (stop 31); the bake-first path itself is PreviewRender's (WhiteFurnaceInBothPaths,
// EveryTargetFromItsBake...).
std::string furnace_bake(Backend& backend, const EnvImage& white, EngineTarget target, bool sheen,
                         const fs::path& dir) {
  PlanOptions o;
  o.chain_size = 16;
  return first_bake(backend, white, target, sheen, dir, o);
}

PreviewMaterial specular_material(const std::string& name, double ior, double specular, Rgb colour) {
  PreviewMaterial m{name, {0.0, 0.0, 0.0}, 0.0, 0.3, {}};
  m.ior = ior;
  m.specular = specular;
  m.specular_color = colour;
  return m;
}

// In a white furnace the reference's integrals are the lobe's albedos A and B, so a black dielectric
// reflects F0 A + (F90 - F0) B with glTF's F0 = specular min(((ior - 1) / (ior + 1))^2 colour, 1) and
// F90 = specular (KHR_materials_specular's fresnel_mix), computed here from the extension's text.
TEST(PreviewLobes, SpecularAndIorInAWhiteFurnaceReflectTheirFresnel) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const EnvImage env = constant_equirect(128, 1.0f);
  const std::vector<double> nvs = {0.05, 0.4, 0.9}, rs = {0.3};
  const std::vector<double> ab = detail::preview::exact_albedos(*backend, nvs, rs);
  detail::ReferenceTask task;
  task.environment = &env;
  task.view = {0.0, 0.0, 1.0};
  for (size_t i = 0; i < nvs.size(); ++i) {
    const double s = std::sqrt(1.0 - nvs[i] * nvs[i]);
    task.pixels.push_back(pixel_of(unit(0.6 * s, 0.8 * s, nvs[i]), 0.09, ab[2 * i], ab[2 * i + 1]));
  }
  const detail::ReferenceSums sums = detail::run_preview_reference(*backend, task);
  struct Case {
    PreviewMaterial m;
    double f0[3], f90;
  };
  const double n3 = (3.0 - 1.0) / (3.0 + 1.0) * (3.0 - 1.0) / (3.0 + 1.0);  // 0.25
  const std::vector<Case> cases = {
      {specular_material("ior 3, coloured", 3.0, 0.7, {1.0, 0.5, 8.0}), {0.7 * n3, 0.7 * n3 * 0.5, 0.7}, 0.7},
      {specular_material("ior 1", 1.0, 1.0, {1.0, 1.0, 1.0}), {0.0, 0.0, 0.0}, 1.0},
      {specular_material("specular 0", 1.5, 0.0, {1.0, 1.0, 1.0}), {0.0, 0.0, 0.0}, 0.0},
      {specular_material("ior 0", 0.0, 0.5, {1.0, 1.0, 1.0}), {0.5, 0.5, 0.5}, 0.5}};
  for (const auto& brdf : {detail::preview::target_brdf(EngineTarget::Generic, false),
                           detail::preview::target_brdf(EngineTarget::Filament, true)})
    for (const Case& c : cases)
      for (size_t q = 0; q < task.pixels.size(); ++q) {
        const double a = ab[2 * q], b = ab[2 * q + 1];
        const Rgb r = detail::preview::reference_radiance(brdf, c.m, a, b, &sums.values[9 * q]);
        const double got[3] = {r.r, r.g, r.b};
        for (int k = 0; k < 3; ++k) {
          // the compensation (filament) multiplies by 1 + F0 (1 / A - 1)
          const double comp = brdf.compensation ? 1.0 + c.f0[k] * (1.0 / a - 1.0) : 1.0;
          EXPECT_NEAR(got[k], comp * (c.f0[k] * a + (c.f90 - c.f0[k]) * b), 4 * kFloatSums)
              << c.m.name << " n.v " << nvs[q] << " channel " << k;
        }
      }
  // at the defaults (ior 1.5, specular 1, white) the material is glTF 2.0's core to the last bit
  const PreviewMaterial core{"core", {0.3, 0.5, 0.7}, 0.4, 0.3, {}};
  const PreviewMaterial same = specular_material("same", 1.5, 1.0, {1.0, 1.0, 1.0});
  EXPECT_EQ(preview_f0(core).r, 0.04 * (1.0 - 0.4) + 0.3 * 0.4);
  EXPECT_EQ(preview_f90(core), 1.0);
  EXPECT_EQ(preview_f0(same).g, 0.04);
}

// Both renders of a whole bake (generic, white furnace): a dielectric with specular 0 reflects nothing
// in either; ior 3 with a coloured specular agrees within the DFG table's bilinear lookup (1.75% at
// 128 x 128, as WhiteFurnaceInBothPaths) and binary16.
TEST(PreviewLobes, SpecularAndIorInBothRenders) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const fs::path dir = temp_dir("specular");
  const EnvImage env = load_environment(white_hdr(dir).string());
  for (EngineTarget target : {EngineTarget::Generic, EngineTarget::KhronosViewer}) {
    PreviewSpec spec;
    spec.target = target;
    spec.bake = furnace_bake(*backend, env, target, false, dir);
    spec.width = 64;
    spec.height = 32;
    spec.bound_stride = 64;
    spec.materials = {specular_material("off", 1.5, 0.0, {1.0, 1.0, 1.0}),
                      specular_material("ior 3", 3.0, 0.7, {1.0, 0.5, 2.0})};
    const PreviewResult r = render_preview(*backend, env, spec);
    const auto pixels = detail::preview::sphere_pixels(detail::preview::make_layout(r.spec));
    for (const auto& p : pixels) {
      const size_t at = 3 * (size_t(p.y) * size_t(r.spec.width) + size_t(p.x));
      for (size_t c = 0; c < 3; ++c) {
        const double s = r.splitsum.rgb[at + c], f = r.reference.rgb[at + c];
        if (p.sphere == 0) {
          EXPECT_EQ(f, 0.0) << "reference, n.v " << p.n_dot_v;
          // generic: nothing; the Sample Viewer's diffuse keeps its unweighted f_ab.y in FssEss, so its
          // multiple-scattering term FmsEms = Ems FssEss F_avg / (1 - F_avg Ems) is 0 by F_avg = 0
          EXPECT_EQ(s, 0.0) << engine_target_name(target) << " split-sum, n.v " << p.n_dot_v;
        } else if (target == EngineTarget::Generic) {
          EXPECT_NEAR(s / f, 1.0, 0.02) << "n.v " << p.n_dot_v << " channel " << c;
        }
      }
    }
    EXPECT_TRUE(std::isfinite(r.stats[1].linear.rms));
  }
}

// A shared sample scene's materials rendered small under builtin:sun for the Sample Viewer's target;
// nothing (the caller skips) when the scene is missing.
std::optional<PreviewResult> render_shared_scene(Device& dev, const std::string& name, std::string* why) {
  const std::string scene = (fs::path(BRDFBAKE_SHARED_DIR) / "scenes" / name).string();
  if (!fs::exists(scene)) {
    *why = "no " + scene + " (the shared scenes)";
    return std::nullopt;
  }
  auto backend = Backend::open(dev);
  const EnvImage env = load_environment("builtin:sun", EnvLoadOptions{false, 128, 0});
  PreviewSpec spec;
  spec.target = EngineTarget::KhronosViewer;
  spec.materials_file = scene;
  spec.width = 96;
  spec.height = 64;
  spec.bound_stride = 64;
  return render_preview(*backend, env, spec);
}

// The Khronos sample scene of KHR_materials_specular: every sphere renders its specular, the notes
// say nothing is left out but the textures, and the error per sphere is finite.
TEST(PreviewLobes, SpecularTestSceneRendersItsSpecular) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  std::string why;
  const std::optional<PreviewResult> rendered = render_shared_scene(*dev, "SpecularTest.gltf", &why);
  if (!rendered) GTEST_SKIP() << why;
  const PreviewResult& r = *rendered;
  ASSERT_EQ(r.spheres.size(), 24u);
  int with_extension = 0;
  for (size_t s = 0; s < r.spheres.size(); ++s) {
    const PreviewMaterial& m = r.spheres[s].material;
    for (const std::string& n : m.notes) {
      EXPECT_EQ(n.find("not rendered"), std::string::npos) << m.name << ": " << n;
      // the extension's textures are the only part left out, and said so
      if (n.find("KHR_materials_specular") != std::string::npos) {
        EXPECT_NE(n.find("textures are not read"), std::string::npos) << m.name << ": " << n;
      }
    }
    with_extension += preview_has_specular_extension(m);
    EXPECT_TRUE(std::isfinite(r.stats[s].linear.rms) && std::isfinite(r.stats[s].linear.max)) << m.name;
    std::printf("%-16s specular %.3f colour %.3f: split-sum vs reference %.3f RMS\n", m.name.c_str(), m.specular,
                m.specular_color.r, r.stats[s].linear.rms);
  }
  EXPECT_GE(with_extension, 18);  // all but the label, the two textured ones and the factor-1 ones
  // specularFactor 0 on black: no reflection at all in the reference
  EXPECT_EQ(r.spheres[1].material.specular, 0.0);
}

PreviewMaterial coated_material(const std::string& name, Rgb base, double clearcoat, double coat_roughness) {
  PreviewMaterial m{name, base, 0.0, 0.5, {}};
  m.clearcoat = clearcoat;
  m.clearcoat_roughness = coat_roughness;
  return m;
}

// In a white furnace the coat's integral is its lobe's albedo A_coat, so a coated dielectric reflects
// (1 - c Fcoat(n.v)) (F0 A + (1 - F0) B + diffuse colour) + c Fcoat(n.v) A_coat, Fcoat = 0.04 + 0.96
// (1 - n.v)^5 (KHR_materials_clearcoat's fresnel_coat), computed here from the extension's text.
TEST(PreviewLobes, ClearcoatInAWhiteFurnaceIsTheLayeredAlbedo) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const EnvImage env = constant_equirect(128, 1.0f);
  const std::vector<double> nvs = {0.05, 0.4, 0.9}, rs = {0.1, 0.5};  // the coat's, the base's
  const std::vector<double> ab = detail::preview::exact_albedos(*backend, nvs, rs);
  detail::ReferenceTask task;
  task.environment = &env;
  task.view = {0.0, 0.0, 1.0};
  for (size_t j = 0; j < rs.size(); ++j)
    for (size_t i = 0; i < nvs.size(); ++i) {
      const double s = std::sqrt(1.0 - nvs[i] * nvs[i]);
      const size_t k = j * nvs.size() + i;
      task.pixels.push_back(pixel_of(unit(0.6 * s, 0.8 * s, nvs[i]), rs[j] * rs[j], ab[2 * k], ab[2 * k + 1]));
    }
  const detail::ReferenceSums sums = detail::run_preview_reference(*backend, task);
  const auto brdf = detail::preview::target_brdf(EngineTarget::Generic, false);
  const PreviewMaterial m = coated_material("coated", {0.5, 0.2, 0.1}, 0.8, 0.1);
  for (size_t i = 0; i < nvs.size(); ++i) {
    const size_t coat = i, base = nvs.size() + i;
    const double a = ab[2 * base], b = ab[2 * base + 1], a_coat = ab[2 * coat];
    const Rgb r =
        detail::preview::reference_radiance(brdf, m, a, b, &sums.values[9 * base], nvs[i], &sums.values[9 * coat]);
    const double fcoat = 0.04 + 0.96 * std::pow(1.0 - nvs[i], 5.0), t = 0.8 * fcoat;
    const double got[3] = {r.r, r.g, r.b}, cd[3] = {0.5, 0.2, 0.1};
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(got[k], (1.0 - t) * (0.04 * a + 0.96 * b + cd[k]) + t * a_coat, 4 * kFloatSums)
          << "n.v " << nvs[i] << " channel " << k;
    // clearcoat 0 is the base to the last bit, whatever its roughness
    const PreviewMaterial off = coated_material("off", {0.5, 0.2, 0.1}, 0.0, 0.1);
    const PreviewMaterial plain{"plain", {0.5, 0.2, 0.1}, 0.0, 0.5, {}};
    const Rgb x =
        detail::preview::reference_radiance(brdf, off, a, b, &sums.values[9 * base], nvs[i], &sums.values[9 * coat]);
    const Rgb y = detail::preview::reference_radiance(brdf, plain, a, b, &sums.values[9 * base]);
    EXPECT_EQ(x.r, y.r);
    EXPECT_EQ(x.b, y.b);
  }
}

// Both renders of a whole bake (white furnace): the generic split-sum layers the coat over the base
// as the reference does, within the DFG table's bilinear lookup (2%, as WhiteFurnaceInBothPaths); a
// coat of weight 0 leaves both renders as the uncoated sphere's, bit for bit; every target's coated
// sphere is finite. Filament's coat is layered over the plain sphere's base, its F0 not remapped
// (gltfio builds its materials with clearCoatIorChange false: docs/ENGINES.md, the clearcoat table):
// coated = (1 - Fc) plain + Fc L, Fc = F_Schlick(0.04, 1, NoV) clearCoat, L the chain at the coat's
// LOD, 1 in a white furnace (f16 stores it exactly); within 1e-4 for the fp32 layering (measured
// 1.2e-7). Filament's f0ClearCoatToSurface(0.04) is 0: with that remap put in, all 2064 values were
// off, by 0.2 % (the rims, where Fc is nearly 1) to 19 %, median 9.4 %.
TEST(PreviewLobes, ClearcoatInBothRenders) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const fs::path dir = temp_dir("clearcoat");
  const EnvImage env = load_environment(white_hdr(dir).string());
  for (EngineTarget target : {EngineTarget::Generic, EngineTarget::Filament, EngineTarget::KhronosViewer}) {
    PreviewSpec spec;
    spec.target = target;
    spec.bake = furnace_bake(*backend, env, target, false, dir);
    spec.width = 96;
    spec.height = 32;
    spec.bound_stride = 64;
    spec.materials = {coated_material("coated", {0.5, 0.2, 0.1}, 1.0, 0.2),
                      coated_material("weight 0", {0.5, 0.2, 0.1}, 0.0, 0.2),
                      PreviewMaterial{"plain", {0.5, 0.2, 0.1}, 0.0, 0.5, {}}};
    const PreviewResult r = render_preview(*backend, env, spec);
    const auto pixels = detail::preview::sphere_pixels(detail::preview::make_layout(r.spec));
    const double shift = r.spheres[2].centre_x - r.spheres[1].centre_x;
    std::vector<double> nvs;
    for (const auto& p : pixels)
      if (p.sphere == 0) nvs.push_back(std::max(p.n_dot_v, 1e-7));
    std::sort(nvs.begin(), nvs.end());
    nvs.erase(std::unique(nvs.begin(), nvs.end()), nvs.end());
    const std::vector<double> coat_ab = detail::preview::exact_albedos(*backend, nvs, {0.2});
    double filament_worst = 0.0;
    int filament_checked = 0;
    for (const auto& p : pixels) {
      const size_t at = 3 * (size_t(p.y) * size_t(r.spec.width) + size_t(p.x));
      if (p.sphere == 0) {
        // the coat over the plain sphere (the same normal, 2 cells to the right): (1 - Fcoat) plain +
        // Fcoat A_coat, exactly in the reference, within the table's lookup in generic's split sum
        const size_t plain = at + 3 * size_t(2 * shift);
        const size_t i = size_t(std::lower_bound(nvs.begin(), nvs.end(), std::max(p.n_dot_v, 1e-7)) - nvs.begin());
        const double t = 0.04 + 0.96 * std::pow(1.0 - p.n_dot_v, 5.0), a_coat = coat_ab[2 * i];
        for (size_t c = 0; c < 3; ++c) {
          const double f = (1.0 - t) * double(r.reference.rgb[plain + c]) + t * a_coat;
          EXPECT_NEAR(double(r.reference.rgb[at + c]) / f, 1.0, 1e-4) << "reference, n.v " << p.n_dot_v;
          if (target == EngineTarget::Generic) {
            const double s = (1.0 - t) * double(r.splitsum.rgb[plain + c]) + t * a_coat;
            EXPECT_NEAR(double(r.splitsum.rgb[at + c]) / s, 1.0, 0.02) << "split-sum, n.v " << p.n_dot_v;
            EXPECT_NEAR(double(r.splitsum.rgb[at + c]) / double(r.reference.rgb[at + c]), 1.0, 0.02)
                << "n.v " << p.n_dot_v << " channel " << c;
          }
          if (target == EngineTarget::Filament) {
            const double fc = 0.04 + 0.96 * std::pow(1.0 - std::max(p.n_dot_v, 1e-4), 5.0);
            const double s = (1.0 - fc) * double(r.splitsum.rgb[plain + c]) + fc;
            const double d = double(r.splitsum.rgb[at + c]) / s - 1.0;
            EXPECT_NEAR(d, 0.0, 1e-4) << "filament, n.v " << p.n_dot_v << " channel " << c;
            filament_worst = std::max(filament_worst, std::fabs(d));
            ++filament_checked;
          }
        }
      }
      if (p.sphere == 1) {
        const size_t there = at + 3 * size_t(shift);
        for (size_t c = 0; c < 3; ++c) {
          EXPECT_EQ(r.splitsum.rgb[at + c], r.splitsum.rgb[there + c]) << engine_target_name(target);
          EXPECT_EQ(r.reference.rgb[at + c], r.reference.rgb[there + c]) << engine_target_name(target);
        }
      }
    }
    EXPECT_TRUE(std::isfinite(r.stats[0].linear.rms) && r.stats[0].linear.rms < 0.5) << engine_target_name(target);
    if (target == EngineTarget::Filament) {
      EXPECT_GT(filament_checked, 300);
      std::printf("filament coat over the unremapped base: within %.2e (%d values)\n", filament_worst,
                  filament_checked);
    }
  }
}

// Filament makes a coated base at least as rough as its coat (getRoughnessPixelParams: mix(r, max(r,
// coat's r), clearCoat)): in a white furnace (every level of the chain 1, exactly in f16) the coated
// sphere's split sum is (1 - Fc) x the plain sphere of the raised roughness at the same normal + Fc,
// Fc = F_Schlick(0.04, 1, NoV) clearCoat. Bases 0.3 under a coat of 0.8: raised to 0.8 (clearCoat 1)
// and 0.55 (clearCoat 0.5).
TEST(PreviewLobes, FilamentRaisesACoatedBaseToTheCoatsRoughness) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const fs::path dir = temp_dir("coat_roughness");
  PreviewSpec spec;
  spec.target = EngineTarget::Filament;
  spec.width = 128;
  spec.height = 32;
  spec.columns = 4;
  spec.reference = false;  // the split-sum render alone
  const Rgb base{0.5, 0.2, 0.1};
  PreviewMaterial full = coated_material("coat 1", base, 1.0, 0.8), half = coated_material("coat 0.5", base, 0.5, 0.8);
  full.roughness = half.roughness = 0.3;
  spec.materials = {full, PreviewMaterial{"plain r0.8", base, 0.0, 0.8, {}}, half,
                    PreviewMaterial{"plain r0.55", base, 0.0, 0.55, {}}};
  const PreviewResult r = render_preview(*backend, load_environment(white_hdr(dir).string()), spec);
  const auto pixels = detail::preview::sphere_pixels(detail::preview::make_layout(r.spec));
  const double shift = r.spheres[1].centre_x - r.spheres[0].centre_x;
  ASSERT_EQ(shift, r.spheres[3].centre_x - r.spheres[2].centre_x);
  ASSERT_EQ(r.spheres[0].centre_y, r.spheres[3].centre_y);
  double worst = 0.0;
  int checked = 0;
  for (const auto& p : pixels) {
    if (p.sphere != 0 && p.sphere != 2) continue;
    const double cc = p.sphere == 0 ? 1.0 : 0.5;
    const size_t at = 3 * (size_t(p.y) * size_t(r.spec.width) + size_t(p.x)), plain = at + 3 * size_t(shift);
    const double fc = (0.04 + 0.96 * std::pow(1.0 - std::max(p.n_dot_v, 1e-4), 5.0)) * cc;
    for (size_t c = 0; c < 3; ++c) {
      const double expected = (1.0 - fc) * double(r.splitsum.rgb[plain + c]) + fc;
      const double d = double(r.splitsum.rgb[at + c]) / expected - 1.0;
      EXPECT_NEAR(d, 0.0, 1e-4) << "clearCoat " << cc << ", n.v " << p.n_dot_v << " channel " << c;
      worst = std::max(worst, std::fabs(d));
      ++checked;
    }
  }
  EXPECT_GT(checked, 300);
  std::printf("filament's coated base at the raised roughness: within %.2e (%d values)\n", worst, checked);
}

// The Khronos sample scene of KHR_materials_clearcoat: the coated materials render their coat (the
// notes say only the textures are left out), and the error per sphere is finite.
TEST(PreviewLobes, ClearCoatTestSceneRendersItsCoat) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  std::string why;
  const std::optional<PreviewResult> rendered = render_shared_scene(*dev, "ClearCoatTest.gltf", &why);
  if (!rendered) GTEST_SKIP() << why;
  const PreviewResult& r = *rendered;
  ASSERT_EQ(r.spheres.size(), 19u);
  int coated = 0;
  for (size_t s = 0; s < r.spheres.size(); ++s) {
    const PreviewMaterial& m = r.spheres[s].material;
    for (const std::string& n : m.notes) EXPECT_EQ(n.find("not rendered"), std::string::npos) << m.name << ": " << n;
    coated += m.clearcoat > 0.0;
    EXPECT_TRUE(std::isfinite(r.stats[s].linear.rms) && std::isfinite(r.stats[s].linear.max)) << m.name;
    std::printf("%-24s clearcoat %.2f roughness %.2f: split-sum vs reference %.3f RMS\n", m.name.c_str(), m.clearcoat,
                m.clearcoat_roughness, r.stats[s].linear.rms);
  }
  EXPECT_EQ(coated, 6);
  // a coat adds reflection: the coated sphere is brighter than its base in the reference
  double base = 0, coat = 0;
  const auto pixels = detail::preview::sphere_pixels(detail::preview::make_layout(r.spec));
  for (const auto& p : pixels) {
    const float* q = &r.reference.rgb[3 * (size_t(p.y) * size_t(r.spec.width) + size_t(p.x))];
    if (p.sphere == 0) base += double(q[0]) + double(q[1]) + double(q[2]);
    if (p.sphere == 1) coat += double(q[0]) + double(q[1]) + double(q[2]);
  }
  EXPECT_GT(coat, base) << r.spheres[0].material.name << " vs " << r.spheres[1].material.name;
}

// The device's reference against the double reference's brute force with the lobes on: a coated
// material of coloured specular and ior 2, on a sample of a sphere's pixels under venice (the base and
// the coat are each an integral of the kernel; their layering is the host's).
TEST(PreviewLobes, TheLobesAgreeWithTheDoubleReference) {
  const std::string file = shared_envmap("derived/venice_sunset_256x128_derived.hdr");
  if (!fs::exists(file)) GTEST_SKIP() << "no " << file;
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const EnvImage env = load_environment(file);
  PreviewMaterial m = coated_material("coated", {0.6, 0.3, 0.2}, 0.7, 0.15);
  m.roughness = 0.4;
  m.ior = 2.0;
  m.specular = 0.8;
  m.specular_color = {1.0, 0.7, 0.4};
  PreviewSpec spec;
  spec.width = spec.height = 64;
  spec.materials = {m};
  const auto layout = detail::preview::make_layout(detail::preview::resolve_spec(spec));
  const auto pixels = detail::preview::sphere_pixels(layout);
  const Vec3 v = detail::preview::view_vector(layout.camera);
  std::vector<size_t> sample;
  for (size_t i = 0; i < pixels.size(); i += 61) sample.push_back(i);
  std::vector<double> nvs;
  for (size_t i : sample) nvs.push_back(std::max(pixels[i].n_dot_v, 1e-7));
  const std::vector<double> ab = detail::preview::exact_albedos(*backend, nvs, {m.roughness, m.clearcoat_roughness});
  detail::ReferenceTask task;
  task.environment = &env;
  task.view = v;
  task.radiance_scale = M_PI * detail::preview::median_luminance(env);
  const size_t n = sample.size();
  for (size_t j = 0; j < 2; ++j)
    for (size_t k = 0; k < n; ++k) {
      const double r = j == 0 ? m.roughness : m.clearcoat_roughness;
      task.pixels.push_back(pixel_of(pixels[sample[k]].n, r * r, ab[2 * (j * n + k)], ab[2 * (j * n + k) + 1]));
    }
  const detail::ReferenceSums sums = detail::run_preview_reference(*backend, task);
  std::vector<double> err;
  for (const auto& brdf : {detail::preview::target_brdf(EngineTarget::Filament, true),
                           detail::preview::target_brdf(EngineTarget::KhronosViewer, true)})
    for (size_t k = 0; k < n; ++k) {
      double s[2][9];
      for (size_t j = 0; j < 2; ++j) {
        const auto& t = task.pixels[j * n + k];
        const reference::PreviewIntegrals bf = reference::preview_integrals(env.rgb.data(), env.width, env.height,
                                                                            pixels[sample[k]].n, v, double(t.alpha));
        for (size_t c = 0; c < 3; ++c) {
          s[j][c] = bf.s1[c];
          s[j][3 + c] = bf.s2[c];
          s[j][6 + c] = bf.irr[c];
        }
      }
      const auto& t = task.pixels[k];
      const double nv = pixels[sample[k]].n_dot_v;
      const Rgb a = detail::preview::reference_radiance(brdf, m, t.albedo, t.bias, &sums.values[9 * k], nv,
                                                        &sums.values[9 * (n + k)]);
      const Rgb b = detail::preview::reference_radiance(brdf, m, t.albedo, t.bias, s[0], nv, s[1]);
      const double x[3] = {a.r, a.g, a.b}, y[3] = {b.r, b.g, b.b};
      err.push_back(rel(x, y));
    }
  const PreviewErrorStats e = detail::preview::error_stats(err);
  std::printf("lobes under venice: %.2e RMS, %.2e max against the brute force (%zu pixels)\n", e.rms, e.max, n);
  EXPECT_LE(e.rms, kReferenceTarget);
}

// ---- KHR_materials_sheen -------------------------------------------------------------------------

PreviewMaterial sheened_material(const std::string& name, const Rgb& base, const Rgb& sheen, double sheen_roughness) {
  PreviewMaterial m{name, base, 0.0, 0.5, {}};
  m.sheen_color = sheen;
  m.sheen_roughness = sheen_roughness;
  return m;
}

detail::ReferencePixel sheen_pixel_of(const Vec3& n, double sheen_roughness, double e) {
  detail::ReferencePixel p = pixel_of(n, detail::preview::preview_sheen_alpha(sheen_roughness), e, 0.0);
  p.sheen = true;
  return p;
}

// In a white furnace the sheen lobe's integral is its albedo E(n.v), so a sheened dielectric reflects
// (1 - max(c) E(n.v)) (F0 A + (1 - F0) B + diffuse colour) + c E(n.v) (KHR_materials_sheen's albedo
// scaling). E itself is checked against the double reference's brute force of the Charlie lobe under
// the same white environment (an integral that shares no code with the charlie table's quadrature):
// within 1% (the brute force's sum over 128 x 64 pixels at the horizon, where the lobe lies).
TEST(PreviewSheen, SheenInAWhiteFurnaceIsTheScaledAlbedo) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const EnvImage env = constant_equirect(128, 1.0f);
  const std::vector<double> nvs = {0.05, 0.4, 0.9};
  const double base_r = 0.5, sheen_r = 0.6;
  const std::vector<double> ab = detail::preview::exact_albedos(*backend, nvs, {base_r});
  const std::vector<double> es = detail::preview::sheen_albedos(*backend, nvs, {sheen_r});
  detail::ReferenceTask task;
  task.environment = &env;
  task.view = {0.0, 0.0, 1.0};
  std::vector<Vec3> normals;
  for (size_t i = 0; i < nvs.size(); ++i) {
    const double s = std::sqrt(1.0 - nvs[i] * nvs[i]);
    normals.push_back(unit(0.6 * s, 0.8 * s, nvs[i]));
  }
  for (size_t i = 0; i < nvs.size(); ++i)
    task.pixels.push_back(pixel_of(normals[i], base_r * base_r, ab[2 * i], ab[2 * i + 1]));
  for (size_t i = 0; i < nvs.size(); ++i) task.pixels.push_back(sheen_pixel_of(normals[i], sheen_r, es[i]));
  const detail::ReferenceSums sums = detail::run_preview_reference(*backend, task);
  const auto brdf = detail::preview::target_brdf(EngineTarget::Generic, false);
  const Rgb c{1.0, 0.4, 0.2};
  const PreviewMaterial m = sheened_material("sheen", {0.5, 0.2, 0.1}, c, sheen_r);
  for (size_t i = 0; i < nvs.size(); ++i) {
    const size_t base = i, sheen = nvs.size() + i;
    const double a = ab[2 * base], b = ab[2 * base + 1], e = es[i];
    EXPECT_GT(e, 0.01) << "n.v " << nvs[i];
    const reference::PreviewIntegrals bf =
        reference::preview_integrals(env.rgb.data(), env.width, env.height, normals[i], task.view,
                                     detail::preview::preview_sheen_alpha(sheen_r), 16.0, true);
    EXPECT_NEAR(bf.s1[0] / e, 1.0, 0.01) << "n.v " << nvs[i] << ": the brute force's E vs the charlie table's";
    const Rgb r = detail::preview::reference_radiance(brdf, m, a, b, &sums.values[9 * base], nvs[i], nullptr,
                                                      &sums.values[9 * sheen], double(task.pixels[sheen].albedo));
    const double got[3] = {r.r, r.g, r.b}, cd[3] = {0.5, 0.2, 0.1}, sc[3] = {c.r, c.g, c.b};
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(got[k], (1.0 - e) * (0.04 * a + 0.96 * b + cd[k]) + sc[k] * e, 4 * kFloatSums)
          << "n.v " << nvs[i] << " channel " << k;
    // sheen colour 0 is the base to the last bit, whatever its roughness
    const PreviewMaterial off = sheened_material("off", {0.5, 0.2, 0.1}, {0.0, 0.0, 0.0}, sheen_r);
    const PreviewMaterial plain{"plain", {0.5, 0.2, 0.1}, 0.0, 0.5, {}};
    const Rgb x = detail::preview::reference_radiance(brdf, off, a, b, &sums.values[9 * base], nvs[i], nullptr,
                                                      &sums.values[9 * sheen], e);
    const Rgb y = detail::preview::reference_radiance(brdf, plain, a, b, &sums.values[9 * base]);
    EXPECT_EQ(x.r, y.r);
    EXPECT_EQ(x.g, y.g);
    EXPECT_EQ(x.b, y.b);
  }
}

// A whole render (white furnace): the reference's sheened sphere is (1 - max(c) E(n.v)) plain + c E(n.v)
// per pixel against the plain sphere; a sheen colour of 0 leaves both renders as the plain sphere's,
// bit for bit.
TEST(PreviewSheen, SheenInTheRender) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const fs::path dir = temp_dir("sheen");
  const EnvImage env = load_environment(white_hdr(dir).string());
  PreviewSpec spec;
  spec.target = EngineTarget::Generic;
  spec.bake = furnace_bake(*backend, env, spec.target, true, dir);
  spec.width = 96;
  spec.height = 32;
  spec.bound_stride = 64;
  const Rgb c{0.9, 0.5, 0.2};
  spec.materials = {sheened_material("sheen", {0.5, 0.2, 0.1}, c, 0.3),
                    sheened_material("colour 0", {0.5, 0.2, 0.1}, {0.0, 0.0, 0.0}, 0.3),
                    PreviewMaterial{"plain", {0.5, 0.2, 0.1}, 0.0, 0.5, {}}};
  const PreviewResult r = render_preview(*backend, env, spec);
  const auto pixels = detail::preview::sphere_pixels(detail::preview::make_layout(r.spec));
  const double shift = r.spheres[2].centre_x - r.spheres[1].centre_x;
  std::vector<double> nvs;
  for (const auto& p : pixels)
    if (p.sphere == 0) nvs.push_back(std::max(p.n_dot_v, 1e-7));
  std::sort(nvs.begin(), nvs.end());
  nvs.erase(std::unique(nvs.begin(), nvs.end()), nvs.end());
  const std::vector<double> es = detail::preview::sheen_albedos(*backend, nvs, {0.3});
  const double sc[3] = {c.r, c.g, c.b};
  for (const auto& p : pixels) {
    const size_t at = 3 * (size_t(p.y) * size_t(r.spec.width) + size_t(p.x));
    if (p.sphere == 0) {
      const size_t plain = at + 3 * size_t(2 * shift);
      const size_t i = size_t(std::lower_bound(nvs.begin(), nvs.end(), std::max(p.n_dot_v, 1e-7)) - nvs.begin());
      for (size_t k = 0; k < 3; ++k) {
        const double f = (1.0 - 0.9 * es[i]) * double(r.reference.rgb[plain + k]) + sc[k] * es[i];
        EXPECT_NEAR(double(r.reference.rgb[at + k]) / f, 1.0, 1e-4) << "reference, n.v " << p.n_dot_v;
      }
    }
    if (p.sphere == 1) {
      const size_t there = at + 3 * size_t(shift);
      for (size_t k = 0; k < 3; ++k) {
        EXPECT_EQ(r.splitsum.rgb[at + k], r.splitsum.rgb[there + k]);
        EXPECT_EQ(r.reference.rgb[at + k], r.reference.rgb[there + k]);
      }
    }
  }
  EXPECT_TRUE(std::isfinite(r.stats[0].linear.rms));
  const std::string out_json = detail::preview::preview_json(r, "white", "");
  EXPECT_NE(out_json.find("\"sheen_roughness\""), std::string::npos);
  EXPECT_NE(out_json.find("\"sheen_color\""), std::string::npos);
}

// The split-sum sheen of every target in a white furnace: the chains and the irradiance are uniform
// (1.0, exact in RGBA16F and RGBD), so a sheened sphere is c E(n.v, r) + plain (1 - max(c) E) per
// pixel, plain the same sphere without sheen (each target's sheen IBL: docs/ENGINES.md), E the charlie
// table's bilinear lookup. Each pixel's E is solved from the channel of max(c) and must explain the
// other channels (float rounding), and match the quadrature's E at the pixel's own n.v within the
// 128^2 table's bilinear error: 1% of E + 0.004 (measured: under 0.3% + 0.001 over n.v in
// 0.03..1 at r 0.8). gltf and babylon (Babylon.js's sheen block) are tested in
// tests/device/test_preview_babylon.cpp (their RGBD chain is 1 only to 8 bits at the sheen's LOD).
// A sheen colour of 0 is the plain sphere to the last bit.
TEST(PreviewSheen, SplitSumSheenInAWhiteFurnaceIsTheClosedForm) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const fs::path dir = temp_dir("sheen_splitsum");
  const EnvImage env = load_environment(white_hdr(dir).string());
  const double sheen_r = 0.8;
  const Rgb c{0.9, 0.5, 0.2};
  for (EngineTarget target : {EngineTarget::Generic, EngineTarget::KhronosViewer, EngineTarget::Filament}) {
    PreviewSpec spec;
    spec.target = target;
    spec.bake = furnace_bake(*backend, env, target, true, dir);
    spec.width = 96;
    spec.height = 32;
    spec.reference = false;
    spec.materials = {sheened_material("sheen", {0.5, 0.2, 0.1}, c, sheen_r),
                      sheened_material("colour 0", {0.5, 0.2, 0.1}, {0.0, 0.0, 0.0}, sheen_r),
                      PreviewMaterial{"plain", {0.5, 0.2, 0.1}, 0.0, 0.5, {}}};
    const PreviewResult r = render_preview(*backend, env, spec);
    const std::string name = engine_target_name(target);
    const std::vector<std::string>& notes = r.spheres[0].material.notes;
    ASSERT_FALSE(notes.empty()) << name;
    EXPECT_EQ(notes.back().find("KHR_materials_sheen: in the split-sum render"), 0u) << name << ": " << notes.back();
    const auto pixels = detail::preview::sphere_pixels(detail::preview::make_layout(r.spec));
    const double shift = r.spheres[1].centre_x - r.spheres[0].centre_x;
    std::vector<double> nvs;
    for (const auto& p : pixels)
      if (p.sphere == 0 && p.n_dot_v >= 0.03) nvs.push_back(p.n_dot_v);
    std::sort(nvs.begin(), nvs.end());
    nvs.erase(std::unique(nvs.begin(), nvs.end()), nvs.end());
    // Filament's sheenPerceptualRoughness is clamped at 0.045 only: 0.8 as it is. Filament's sheenDFG is
    // its own table's third channel (Ashikhmin's visibility, engines/filament_dfg.hpp; the table held to
    // Filament 1.76's by tests/python/test_engine_filament.py), looked up here bilinearly at texel
    // centres, clamp to edge; the other targets' E is the bake's charlie table, held to the quadrature.
    std::vector<double> es = detail::preview::sheen_albedos(*backend, nvs, {sheen_r});
    if (target == EngineTarget::Filament) {
      const Table& t = detail::filament_dfg_table();
      auto axis = [](double uv, int n, int* i0, double* f) {
        const double x = std::clamp(uv * n - 0.5, 0.0, double(n - 1));
        *i0 = std::min(int(x), n - 2);
        *f = x - *i0;
      };
      for (size_t i = 0; i < nvs.size(); ++i) {
        int i0 = 0, j0 = 0;
        double fx = 0, fy = 0;
        axis(std::max(nvs[i], 1e-4), t.width, &i0, &fx);
        axis(sheen_r, t.height, &j0, &fy);
        auto at = [&](int ii, int jj) { return double(t.at(ii, jj, 2)); };
        es[i] = (at(i0, j0) * (1 - fx) + at(i0 + 1, j0) * fx) * (1 - fy) +
                (at(i0, j0 + 1) * (1 - fx) + at(i0 + 1, j0 + 1) * fx) * fy;
      }
    }
    const double sc[3] = {c.r, c.g, c.b};
    double worst = 0.0;
    int checked = 0;
    for (const auto& p : pixels) {
      if (p.sphere != 0) continue;
      const size_t at = 3 * (size_t(p.y) * size_t(r.spec.width) + size_t(p.x));
      const size_t off = at + 3 * size_t(shift), plain = at + 3 * size_t(2 * shift);
      for (size_t k = 0; k < 3; ++k) ASSERT_EQ(r.splitsum.rgb[off + k], r.splitsum.rgb[plain + k]) << name;
      if (p.n_dot_v < 0.03) continue;  // the rim: E's steepest, the lookup's clamp to edge
      const float* s = &r.splitsum.rgb[at];
      const float* b = &r.splitsum.rgb[plain];
      // channel 0 carries max(c): s0 = c0 E + b0 (1 - c0 E)
      const double e = (double(s[0]) - double(b[0])) / (sc[0] * (1.0 - double(b[0])));
      for (size_t k = 1; k < 3; ++k)
        EXPECT_NEAR(double(s[k]), sc[k] * e + double(b[k]) * (1.0 - sc[0] * e), 2e-6 * (1.0 + double(s[k])))
            << name << " n.v " << p.n_dot_v << " channel " << k;
      const size_t i = size_t(std::lower_bound(nvs.begin(), nvs.end(), p.n_dot_v) - nvs.begin());
      ASSERT_LT(i, nvs.size());
      EXPECT_NEAR(e, es[i], 0.01 * es[i] + 0.004) << name << " n.v " << p.n_dot_v;
      worst = std::max(worst, std::fabs(e - es[i]));
      ++checked;
    }
    EXPECT_GT(checked, 50) << name;
    std::printf("%-15s split-sum sheen in a white furnace: E within %.2e of the quadrature (%d pixels)\n", name.c_str(),
                worst, checked);
  }
}

// The device's reference against the double reference's brute force with the sheen on: a sheened
// dielectric on a sample of a sphere's pixels under venice (the base and the sheen are each an
// integral of the kernel; their scaling is the host's).
TEST(PreviewSheen, TheSheenAgreesWithTheDoubleReference) {
  const std::string file = shared_envmap("derived/venice_sunset_256x128_derived.hdr");
  if (!fs::exists(file)) GTEST_SKIP() << "no " << file;
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const EnvImage env = load_environment(file);
  for (double sheen_r : {0.3, 0.8}) {
    PreviewMaterial m = sheened_material("sheen", {0.6, 0.3, 0.2}, {1.0, 0.5, 0.3}, sheen_r);
    m.roughness = 0.4;
    PreviewSpec spec;
    spec.width = spec.height = 64;
    spec.materials = {m};
    const auto layout = detail::preview::make_layout(detail::preview::resolve_spec(spec));
    const auto pixels = detail::preview::sphere_pixels(layout);
    const Vec3 v = detail::preview::view_vector(layout.camera);
    std::vector<size_t> sample;
    for (size_t i = 0; i < pixels.size(); i += 61) sample.push_back(i);
    std::vector<double> nvs;
    for (size_t i : sample) nvs.push_back(std::max(pixels[i].n_dot_v, 1e-7));
    const std::vector<double> ab = detail::preview::exact_albedos(*backend, nvs, {m.roughness});
    const std::vector<double> es = detail::preview::sheen_albedos(*backend, nvs, {sheen_r});
    detail::ReferenceTask task;
    task.environment = &env;
    task.view = v;
    task.radiance_scale = M_PI * detail::preview::median_luminance(env);
    const size_t n = sample.size();
    for (size_t k = 0; k < n; ++k)
      task.pixels.push_back(pixel_of(pixels[sample[k]].n, m.roughness * m.roughness, ab[2 * k], ab[2 * k + 1]));
    for (size_t k = 0; k < n; ++k) task.pixels.push_back(sheen_pixel_of(pixels[sample[k]].n, sheen_r, es[k]));
    const detail::ReferenceSums sums = detail::run_preview_reference(*backend, task);
    EXPECT_EQ(sums.overflows, 0u);
    std::vector<double> err, sheen_err;
    const auto brdf = detail::preview::target_brdf(EngineTarget::KhronosViewer, true);
    for (size_t k = 0; k < n; ++k) {
      double s[2][9];
      for (size_t j = 0; j < 2; ++j) {
        const auto& t = task.pixels[j * n + k];
        const reference::PreviewIntegrals bf = reference::preview_integrals(
            env.rgb.data(), env.width, env.height, pixels[sample[k]].n, v, double(t.alpha), 16.0, t.sheen);
        for (size_t c = 0; c < 3; ++c) {
          s[j][c] = bf.s1[c];
          s[j][3 + c] = bf.s2[c];
          s[j][6 + c] = bf.irr[c];
        }
      }
      const auto& t = task.pixels[k];
      const double nv = pixels[sample[k]].n_dot_v, e = es[k];
      const Rgb a = detail::preview::reference_radiance(brdf, m, t.albedo, t.bias, &sums.values[9 * k], nv, nullptr,
                                                        &sums.values[9 * (n + k)], e);
      const Rgb b = detail::preview::reference_radiance(brdf, m, t.albedo, t.bias, s[0], nv, nullptr, s[1], e);
      const double x[3] = {a.r, a.g, a.b}, y[3] = {b.r, b.g, b.b};
      err.push_back(rel(x, y));
      sheen_err.push_back(rel(&sums.values[9 * (n + k)], s[1]));
    }
    const PreviewErrorStats e = detail::preview::error_stats(err), es_ = detail::preview::error_stats(sheen_err);
    std::printf(
        "sheen roughness %.1f under venice: %.2e RMS, %.2e max against the brute force; the sheen lobe alone "
        "%.2e RMS, %.2e max (%zu pixels)\n",
        sheen_r, e.rms, e.max, es_.rms, es_.max, n);
    EXPECT_LE(e.rms, kReferenceTarget);
    EXPECT_LE(es_.rms, 2 * kReferenceTarget);
  }
}

// The Khronos sample scene of KHR_materials_sheen: the fabrics render their sheen in the reference
// (no "sheen: not rendered" note), every sphere's error is finite, and a sheened fabric's rim (n.v
// below 0.3) is brighter in the reference than the same fabric without its sheen.
TEST(PreviewSheen, SheenChairSceneRendersItsSheen) {
  const std::string scene = (fs::path(BRDFBAKE_SHARED_DIR) / "scenes" / "SheenChair.gltf").string();
  if (!fs::exists(scene)) GTEST_SKIP() << "no " << scene << " (the shared scenes)";
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const EnvImage env = load_environment("builtin:sun", EnvLoadOptions{false, 128, 0});
  PreviewSpec spec;
  spec.target = EngineTarget::KhronosViewer;
  spec.materials_file = scene;
  spec.width = 96;
  spec.height = 64;
  spec.bound_stride = 64;
  // the bake render_preview makes first, once for both renders (the references do not read it)
  spec.bake = first_bake(*backend, env, spec.target, true, temp_dir("sheen_chair"));
  const PreviewResult r = render_preview(*backend, env, spec);
  ASSERT_EQ(r.spheres.size(), 6u);
  PreviewSpec bare = spec;
  bare.materials_file.clear();
  int sheened = 0;
  for (size_t s = 0; s < r.spheres.size(); ++s) {
    const PreviewMaterial& m = r.spheres[s].material;
    for (const std::string& n : m.notes)
      EXPECT_EQ(n.find("sheen: not rendered"), std::string::npos) << m.name << ": " << n;
    sheened += preview_has_sheen(m);
    EXPECT_TRUE(std::isfinite(r.stats[s].linear.rms) && std::isfinite(r.stats[s].linear.max)) << m.name;
    PreviewMaterial off = m;
    off.sheen_color = {0.0, 0.0, 0.0};
    off.notes.clear();
    bare.materials.push_back(off);
  }
  EXPECT_EQ(sheened, 2);
  const PreviewResult q = render_preview(*backend, env, bare);
  const auto pixels = detail::preview::sphere_pixels(detail::preview::make_layout(r.spec));
  for (size_t s = 0; s < r.spheres.size(); ++s) {
    if (!preview_has_sheen(r.spheres[s].material)) continue;
    double with = 0, without = 0;
    for (const auto& p : pixels) {
      if (size_t(p.sphere) != s || p.n_dot_v >= 0.3) continue;
      const size_t at = 3 * (size_t(p.y) * size_t(r.spec.width) + size_t(p.x));
      for (size_t k = 0; k < 3; ++k) {
        with += double(r.reference.rgb[at + k]);
        without += double(q.reference.rgb[at + k]);
      }
    }
    std::printf("%-32s rim: %.4f with the sheen, %.4f without\n", r.spheres[s].material.name.c_str(), with, without);
    EXPECT_GT(with, without) << r.spheres[s].material.name;
    const std::vector<std::string>& notes = r.spheres[s].material.notes;
    EXPECT_TRUE(std::any_of(notes.begin(), notes.end(), [](const std::string& n) {
      return n.rfind("KHR_materials_sheen: in the split-sum render", 0) == 0;
    })) << r.spheres[s].material.name;
  }
}

// The split-sum's sheen lobe for the Sample Viewer (getIBLRadianceCharlie, albedoSheenScaling) under
// venice (the 256 x 128 derived map), SheenChair's two velvets: their split-sum error against the
// reference with the lobe, and without it (the same spheres' split-sum with sheenColor 0, as before
// the lobe, against the same sheened reference). Their mean error must drop by a fifth at least, and
// each stay under 40% (measured here: Mango 21.8% with the lobe, 15.5% without: its red base
// dominates and the Charlie split sum along reflect(-v, n) misses the grazing lobe; Peacock 33.2%
// against 62.0%; docs/PREVIEW.md has the 512 x 512 figures). Under a
// sun the Charlie split sum is no better than without it (its prefiltered lobe along reflect(-v, n)
// is far from the sheen's grazing lobe): that is the engines' approximation, not checked here.
TEST(PreviewSheen, SheenChairSplitSumErrorDropsWithTheLobe) {
  const std::string scene = (fs::path(BRDFBAKE_SHARED_DIR) / "scenes" / "SheenChair.gltf").string();
  const std::string file = shared_envmap("derived/venice_sunset_256x128_derived.hdr");
  if (!fs::exists(scene)) GTEST_SKIP() << "no " << scene << " (the shared scenes)";
  if (!fs::exists(file)) GTEST_SKIP() << "no " << file;
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const EnvImage env = load_environment(file);
  PreviewSpec spec;
  spec.target = EngineTarget::KhronosViewer;
  spec.materials_file = scene;
  spec.width = 96;
  spec.height = 64;
  spec.bound_stride = 64;
  // the bake render_preview makes first for the sheened spheres, once for both renders: the same GGX
  // chain, DFG table and irradiance serve the spheres without their sheen (as before the lobe)
  spec.bake = first_bake(*backend, env, spec.target, true, temp_dir("sheen_chair_lobe"));
  const PreviewResult r = render_preview(*backend, env, spec);
  ASSERT_EQ(r.spheres.size(), 6u);
  PreviewSpec bare = spec;
  bare.materials_file.clear();
  bare.reference = false;
  for (const PreviewSphere& sp : r.spheres) {
    PreviewMaterial off = sp.material;
    off.sheen_color = {0.0, 0.0, 0.0};
    off.notes.clear();
    bare.materials.push_back(off);
  }
  const PreviewResult q = render_preview(*backend, env, bare);
  const auto pixels = detail::preview::sphere_pixels(detail::preview::make_layout(r.spec));
  int sheened = 0;
  double with_sum = 0.0, without_sum = 0.0;
  for (size_t s = 0; s < r.spheres.size(); ++s) {
    if (!preview_has_sheen(r.spheres[s].material)) continue;
    ++sheened;
    std::vector<double> err_with, err_without;
    for (const auto& p : pixels) {
      if (size_t(p.sphere) != s) continue;
      const size_t at = 3 * (size_t(p.y) * size_t(r.spec.width) + size_t(p.x));
      double ref[3], a[3], b[3];
      for (size_t k = 0; k < 3; ++k) {
        ref[k] = double(r.reference.rgb[at + k]);
        a[k] = double(r.splitsum.rgb[at + k]);
        b[k] = double(q.splitsum.rgb[at + k]);
      }
      err_with.push_back(rel(a, ref));
      err_without.push_back(rel(b, ref));
    }
    const double e_with = detail::preview::error_stats(err_with).rms;
    const double e_without = detail::preview::error_stats(err_without).rms;
    std::printf("%-32s split-sum vs reference: %.1f%% RMS with the sheen lobe, %.1f%% without\n",
                r.spheres[s].material.name.c_str(), 100 * e_with, 100 * e_without);
    EXPECT_NEAR(e_with, r.stats[s].linear.rms, 1e-9) << "the stats' own definition";
    EXPECT_LT(e_with, 0.40) << r.spheres[s].material.name;
    with_sum += e_with;
    without_sum += e_without;
  }
  EXPECT_EQ(sheened, 2);
  EXPECT_LT(with_sum, 0.8 * without_sum) << "the velvets' mean split-sum error";
}

}  // namespace
}  // namespace brdfbake
