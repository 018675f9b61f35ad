// The error's two shares (docs/PREVIEW.md, "Engine share and bake share"): the target's shader
// rendered from an ideal bake (families/preview/ideal.hpp) splits split-sum - reference into the
// bake's share (split-sum - ideal) and the engine's (ideal - reference). In a white furnace the
// engine's share is the split sum's own exactness and the bake's the files' storage and resolution;
// degrading one input of a bake (its chain's resolution, its DFG table's) moves the bake's share
// and leaves the engine's as it was.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "brdfbake/backend.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/job.hpp"
#include "brdfbake/plan.hpp"
#include "brdfbake/preview.hpp"
#include "families/preview/bake_files.hpp"
#include "families/preview/ideal.hpp"
#include "families/preview/model.hpp"
#include "families/preview/render.hpp"
#include "families/preview/splitsum.hpp"
#include "support/device_fixture.hpp"
#include "support/preview_files.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;
using test::on_backend;
using test::shared_envmap;
using test::white_hdr;

// ---- Tolerances, each with its reason --------------------------------------------------------------

// generic in a white furnace: the split sum is exact for a constant environment, and what is left of the
// ideal render is the bilinear lookup of its 256^2 DFG table between exact texel centres (second
// order in the texel: 1/4 of the 128^2 table's, measured below 0.4 % at grazing n.v) and fp32.
constexpr double kIdealFurnace = 5e-3;
// A constant map's chain is 1.0 in every texel of every level, exact in binary16 and R11G11B10 (the
// white_hdr comment): where the DFG table is the engine's own (filament) the files add nothing but the
// fp32 rounding of the ideal's conversion and filtering sums.
constexpr double kExactFiles = 1e-5;
// The files' 128^2 DFG table looked up between texel centres: up to 1.75 % at grazing n.v
// (PreviewRender.WhiteFurnaceInBothPaths allows 2 %).
constexpr double kFilesDfgLookup = 0.02;
// The RMS norms of the two shares and of the error obey the triangle inequality up to the float
// images' rounding.
constexpr double kNormRounding = 1e-6;

// Gold, not a white metal: F0 = 1 takes the DFG table out of generic's compensated split sum
// (mix(bias, albedo, 1) (1 + (1 / albedo - 1)) = 1), so a table's resolution would not show on it.
const std::vector<PreviewMaterial> kMaterials = {
    {"gold r0", {1.0, 0.766, 0.336}, 1.0, 0.0, {}},
    {"gold r0.2", {1.0, 0.766, 0.336}, 1.0, 0.2, {}},
    {"gold r0.6", {1.0, 0.766, 0.336}, 1.0, 0.6, {}},
    {"dielectric r0.4", {0.8, 0.8, 0.8}, 0.0, 0.4, {}},
};

std::string bake_folder(Backend& backend, const EnvImage& env, EngineTarget target, const PlanOptions& o,
                        const fs::path& dir, const std::string& name) {
  Plan plan = detail::preview::first_bake_plan(env, target, false, o);
  plan.job.output_dir = (dir / name).string();
  run_job(plan.job, {}, on_backend(backend));
  return plan.job.output_dir;
}

PreviewResult render(Backend& backend, const EnvImage& env, EngineTarget target, const std::string& bake) {
  PreviewSpec spec;
  spec.target = target;
  spec.bake = bake;
  spec.width = spec.height = 96;
  spec.bound_stride = 64;
  spec.materials = kMaterials;
  return render_preview(backend, env, spec);
}

// Per sphere: the shares' norms and the error's obey the triangle inequality (the difference images
// add up exactly), and the groups are the spheres (one material each).
void expect_shares_add_up(const PreviewResult& r) {
  ASSERT_FALSE(r.ideal.rgb.empty());
  ASSERT_EQ(r.share_groups.size(), r.spheres.size());
  for (size_t s = 0; s < r.stats.size(); ++s) {
    const PreviewSphereStats& st = r.stats[s];
    EXPECT_LE(st.linear.rms, st.engine_share.rms + st.bake_share.rms + kNormRounding) << r.spheres[s].material.name;
    EXPECT_GE(st.linear.rms, std::fabs(st.engine_share.rms - st.bake_share.rms) - kNormRounding)
        << r.spheres[s].material.name;
    EXPECT_EQ(r.share_groups[s].bake_worst, st.bake_share.rms);
  }
}

TEST(PreviewShares, WhiteFurnaceEngineShareIsTheSplitSumsExactness) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const fs::path dir = test::temp_dir("preview_shares", "furnace");
  const EnvImage env = load_environment(white_hdr(dir).string());
  PlanOptions o;
  o.chain_size = 16;  // a constant map: every level of every chain is 1.0 whatever its size
  for (EngineTarget target : {EngineTarget::Generic, EngineTarget::Filament}) {
    const std::string name = engine_target_name(target);
    const PreviewResult r = render(*backend, env, target, bake_folder(*backend, env, target, o, dir, name));
    expect_shares_add_up(r);
    for (size_t s = 0; s < r.stats.size(); ++s) {
      const PreviewSphereStats& st = r.stats[s];
      const std::string what = name + " " + r.spheres[s].material.name;
      if (target == EngineTarget::Generic) {
        // the engine's share: the split sum of a constant environment is exact
        EXPECT_LE(st.engine_share.max, kIdealFurnace) << what;
        // the bake's: its 128^2 table's lookup (its chain is exact)
        EXPECT_LE(st.bake_share.max, kFilesDfgLookup) << what;
        EXPECT_GT(st.bake_share.rms, 0.0) << what;
      } else {
        // Filament samples its own DFG table (the engine's share); the files are exact
        EXPECT_LE(st.bake_share.max, kExactFiles) << what;
      }
    }
  }
}

// One input of the bake degraded, the rest as they were: the bake's share rises and the engine's
// stays put to the last bit (the ideal bake depends on the files' level count and the target, not on
// their sizes or encodings).
TEST(PreviewShares, DegradingOneInputMovesTheBakeShareAlone) {
  const std::string file = shared_envmap("venice_sunset_1k.hdr");
  if (!fs::exists(file)) GTEST_SKIP() << "no " << file;
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const fs::path dir = test::temp_dir("preview_shares", "degrade");
  const EnvImage env = load_environment(file);
  const EngineTarget target = EngineTarget::Generic;
  // the same 4 levels: 64^2 .. 8^2 against 16^2 .. 2^2; the DFG table 128^2 against 8^2
  PlanOptions good;
  good.chain_size = 64;
  good.cube_min_size = 8;
  PlanOptions small_chain = good;
  small_chain.chain_size = 16;
  small_chain.cube_min_size = 2;
  PlanOptions small_table = good;
  small_table.lut_size = 8;
  const PreviewResult base = render(*backend, env, target, bake_folder(*backend, env, target, good, dir, "good"));
  const PreviewResult chain =
      render(*backend, env, target, bake_folder(*backend, env, target, small_chain, dir, "chain16"));
  const PreviewResult table =
      render(*backend, env, target, bake_folder(*backend, env, target, small_table, dir, "table8"));
  // measured under venice (error / engine / bake, relative RMS): gold r0 0.68 / 0.23 / 0.54 from the 64^2
  // chain, 1.75 / 0.23 / 1.67 from the 16^2; the dielectric 0.0180 / 0.0180 / 0.00019 with the 128^2
  // table, 0.0182 / 0.0180 / 0.00092 with the 8^2
  for (const PreviewResult* r : {&base, &chain, &table}) expect_shares_add_up(*r);
  for (size_t s = 0; s < base.stats.size(); ++s) {
    const std::string what = base.spheres[s].material.name;
    EXPECT_EQ(chain.stats[s].engine_share.rms, base.stats[s].engine_share.rms) << what;
    EXPECT_EQ(table.stats[s].engine_share.rms, base.stats[s].engine_share.rms) << what;
  }
  // the 16^2 mirror against the 64^2 one, and the 8^2 table's lookup on the dielectric's rims
  EXPECT_GT(chain.stats[0].bake_share.rms, 1.5 * base.stats[0].bake_share.rms);
  EXPECT_GT(chain.stats[1].bake_share.rms, base.stats[1].bake_share.rms);
  EXPECT_GT(table.stats[3].bake_share.rms, 1.5 * base.stats[3].bake_share.rms);
  for (size_t s : {size_t(1), size_t(2)}) EXPECT_GT(table.stats[s].bake_share.rms, base.stats[s].bake_share.rms);
  // the error moves with the bake's share (the engine's being the same)
  EXPECT_GT(chain.stats[0].linear.rms, base.stats[0].linear.rms);
}

// KHR_materials_sheen: the ideal bake replaces the Charlie chain too (each level at the roughness the
// lookup asks of it, lod = sheenRoughness (levels - 1)). A sheen-only material (no specular lobe:
// KHR_materials_specular 0; a black base) sees nothing of the GGX chain, so a coarser bake moves its
// bake share through the Charlie chain alone, and its engine share not at all (the ideal Charlie
// chain's levels are the same for both bakes: level_size's floor and the lobe decide them). With the
// files' own Charlie chain in the ideal bake (before stop 35) its engine share moved with the bake.
TEST(PreviewShares, TheCharlieChainIsInTheBakeShare) {
  const std::string file = shared_envmap("venice_sunset_1k.hdr");
  if (!fs::exists(file)) GTEST_SKIP() << "no " << file;
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const fs::path dir = test::temp_dir("preview_shares", "sheen");
  const EnvImage env = load_environment(file);
  const EngineTarget target = EngineTarget::Generic;
  PreviewMaterial sheen_only{"sheen r0.5", {0.0, 0.0, 0.0}, 0.0, 0.5, {}};
  sheen_only.specular = 0.0;
  sheen_only.sheen_color = {1.0, 1.0, 1.0};
  sheen_only.sheen_roughness = 0.5;
  PlanOptions good;
  good.chain_size = 64;
  good.cube_min_size = 8;
  PlanOptions coarse = good;
  coarse.chain_size = 16;
  coarse.cube_min_size = 2;
  const auto bake_and_render = [&](const PlanOptions& o, const std::string& name) {
    Plan plan = detail::preview::first_bake_plan(env, target, true, o);
    plan.job.output_dir = (dir / name).string();
    run_job(plan.job, {}, on_backend(*backend));
    PreviewSpec spec;
    spec.target = target;
    spec.bake = plan.job.output_dir;
    spec.width = spec.height = 96;
    spec.bound_stride = 64;
    spec.materials = {sheen_only};
    return render_preview(*backend, env, spec);
  };
  const PreviewResult a = bake_and_render(good, "good"), b = bake_and_render(coarse, "coarse");
  for (const PreviewResult* r : {&a, &b}) {
    expect_shares_add_up(*r);
    const auto sheen =
        std::find_if(r->ideal_bake.begin(), r->ideal_bake.end(), [](const auto& kv) { return kv.first == "sheen"; });
    ASSERT_NE(sheen, r->ideal_bake.end());
    EXPECT_NE(sheen->second.find("Charlie"), std::string::npos) << sheen->second;
  }
  EXPECT_EQ(b.stats[0].engine_share.rms, a.stats[0].engine_share.rms);
  EXPECT_GT(a.stats[0].bake_share.rms, 0.0);
  EXPECT_GT(b.stats[0].bake_share.rms, 1.2 * a.stats[0].bake_share.rms)
      << "the 16^2 Charlie chain against the 64^2 one: " << b.stats[0].bake_share.rms << " against "
      << a.stats[0].bake_share.rms;
}

// khronos-viewer's Lambertian cube: the ideal bake's is the irradiance family's at 128^2, so the
// files' cube resolution is the bake's share. A diffuse-only material (KHR_materials_specular 0) sees
// nothing but the cube: an 8^2 cube against the default 32^2 raises its bake share, and its engine
// share stays to the bit (the ideal cube is 128^2 for both).
TEST(PreviewShares, TheLambertianCubeIsInTheBakeShare) {
  const std::string file = shared_envmap("venice_sunset_1k.hdr");
  if (!fs::exists(file)) GTEST_SKIP() << "no " << file;
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const fs::path dir = test::temp_dir("preview_shares", "lambertian");
  const EnvImage env = load_environment(file);
  const EngineTarget target = EngineTarget::KhronosViewer;
  PreviewMaterial diffuse_only{"white diffuse", {0.8, 0.8, 0.8}, 0.0, 1.0, {}};
  diffuse_only.specular = 0.0;
  PlanOptions o;
  o.chain_size = 32;
  o.cube_min_size = 4;
  const auto bake_and_render = [&](int irradiance_size, const std::string& name) {
    Plan plan = detail::preview::first_bake_plan(env, target, false, o);
    plan.job.output_dir = (dir / name).string();
    bool found = false;
    for (TableRequest& t : plan.job.tables)
      if (t.kind == TableKind::Irradiance) {
        // the plan names the cube's size (32, the table's default for a cube): replaced
        t.params.erase(std::remove_if(t.params.begin(), t.params.end(),
                                      [](const Param& p) { return p.name == "irradiance_size"; }),
                       t.params.end());
        t.params.push_back({"irradiance_size", double(irradiance_size)});
        found = true;
      }
    EXPECT_TRUE(found) << "khronos-viewer's bake has no irradiance table";
    run_job(plan.job, {}, on_backend(*backend));
    PreviewSpec spec;
    spec.target = target;
    spec.bake = plan.job.output_dir;
    spec.width = spec.height = 96;
    spec.bound_stride = 64;
    spec.materials = {diffuse_only};
    return render_preview(*backend, env, spec);
  };
  const PreviewResult a = bake_and_render(32, "cube32"), b = bake_and_render(8, "cube8");
  for (const PreviewResult* r : {&a, &b}) {
    expect_shares_add_up(*r);
    const auto diffuse =
        std::find_if(r->ideal_bake.begin(), r->ideal_bake.end(), [](const auto& kv) { return kv.first == "diffuse"; });
    ASSERT_NE(diffuse, r->ideal_bake.end());
    EXPECT_NE(diffuse->second.find("Lambertian cube 128^2"), std::string::npos) << diffuse->second;
  }
  EXPECT_EQ(b.stats[0].engine_share.rms, a.stats[0].engine_share.rms);
  EXPECT_GT(a.stats[0].bake_share.rms, 0.0);
  EXPECT_GT(b.stats[0].bake_share.rms, 1.5 * a.stats[0].bake_share.rms)
      << "the 8^2 cube against the 32^2 one: " << b.stats[0].bake_share.rms << " against " << a.stats[0].bake_share.rms;
}

// The sharp-reflection probe (render.hpp, sharp_probe): the bake's share of the spheres below
// roughness 0.1 drawn at 2 x the files' level-0 size in pixels. Its drawn pixels stand for all of the
// sphere's: the RMS over every pixel of that sphere, computed here by brute force, agrees with it; it
// is 0 for files against themselves, not drawn for the rougher spheres, and a 4x coarser chain of the
// same level count reads clearly worse (the resolution it is there to see).
TEST(PreviewShares, SharpProbeSeesTheChainsResolution) {
  using namespace detail::preview;
  const std::string file = shared_envmap("venice_sunset_1k.hdr");
  if (!fs::exists(file)) GTEST_SKIP() << "no " << file;
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const fs::path dir = test::temp_dir("preview_shares", "probe");
  const EnvImage env = load_environment(file);
  const EngineTarget target = EngineTarget::Generic;
  PlanOptions good;
  good.chain_size = 64;
  good.cube_min_size = 8;
  PlanOptions coarse = good;
  coarse.chain_size = 16;
  coarse.cube_min_size = 2;
  const std::string good_folder = bake_folder(*backend, env, target, good, dir, "good");
  const std::string coarse_folder = bake_folder(*backend, env, target, coarse, dir, "coarse");
  const PreviewResult base = render(*backend, env, target, good_folder);
  const Layout layout = make_layout(base.spec);
  const auto split_and_ideal = [&](const std::string& folder) {
    BakeFiles files = read_bake_files(folder, target, env.source);
    SplitSum ideal(ideal_bake(*backend, env, files).files);
    return std::make_pair(SplitSum(std::move(files)), std::move(ideal));
  };
  const auto [good_files, good_ideal] = split_and_ideal(good_folder);
  const auto [coarse_files, coarse_ideal] = split_and_ideal(coarse_folder);
  const std::vector<double> p_good = sharp_probe(layout, good_files, good_ideal);
  const std::vector<double> p_coarse = sharp_probe(layout, coarse_files, coarse_ideal);
  const std::vector<double> p_self = sharp_probe(layout, good_files, good_files);
  ASSERT_EQ(p_good.size(), kMaterials.size());
  for (size_t s = 0; s < kMaterials.size(); ++s) {
    const bool probed = kMaterials[s].roughness < kProbeMaxRoughness;
    EXPECT_EQ(p_good[s] >= 0.0, probed) << kMaterials[s].name;
    EXPECT_EQ(p_self[s], probed ? 0.0 : -1.0) << kMaterials[s].name;
  }
  // measured: gold r0 19.5 % from the 64^2 chain (against the ideal's 512^2 mirror), 29.2 % from the
  // 16^2 (each pixel's error counted up to 100 %: the coarse chain's saturate)
  EXPECT_GT(p_coarse[0], 1.3 * p_good[0]);
  // Every pixel of the probe's sphere (radius 2 x 16 = 32 pixels for the coarse chain, 128 for the
  // good one), shaded from both: the drawn pixels' RMS is theirs to the sampling's few percent (16384
  // low-discrepancy draws; 5 % allows for the pixels drawn twice on the 3,200-pixel sphere).
  for (const auto* pair : {&good_files, &coarse_files}) {
    const bool is_good = pair == &good_files;
    const SplitSum& f = is_good ? good_files : coarse_files;
    const SplitSum& i = is_good ? good_ideal : coarse_ideal;
    const double radius = 2.0 * f.files().specular.size;
    const PreviewCamera& c = layout.camera;
    const Vec3 v = view_vector(c);
    double sum = 0.0;
    long n = 0;
    for (int y = 0; y < int(2 * radius); ++y)
      for (int x = 0; x < int(2 * radius); ++x) {
        const double dx = (x + 0.5 - radius) / radius, dy = (y + 0.5 - radius) / radius, d2 = dx * dx + dy * dy;
        if (!(d2 < 1.0)) continue;
        const double nz = std::sqrt(1.0 - d2);
        Vec3 nn{dx * c.right.x - dy * c.up.x + nz * v.x, dx * c.right.y - dy * c.up.y + nz * v.y,
                dx * c.right.z - dy * c.up.z + nz * v.z};
        const double l = std::sqrt(nn.x * nn.x + nn.y * nn.y + nn.z * nn.z);
        nn = {nn.x / l, nn.y / l, nn.z / l};
        const float slope2 = float((1.0 + std::max(dx * dx, dy * dy) / std::max(nz * nz, 1e-12)) / (radius * radius));
        const Rgb a = f.shade(nn, v, kMaterials[0], slope2), b = i.shade(nn, v, kMaterials[0], slope2);
        const double fa[3] = {double(float(a.r)), double(float(a.g)), double(float(a.b))};
        const double fb[3] = {double(float(b.r)), double(float(b.g)), double(float(b.b))};
        const double d = std::sqrt((fa[0] - fb[0]) * (fa[0] - fb[0]) + (fa[1] - fb[1]) * (fa[1] - fb[1]) +
                                   (fa[2] - fb[2]) * (fa[2] - fb[2]));
        const double norm = std::sqrt(fb[0] * fb[0] + fb[1] * fb[1] + fb[2] * fb[2]);
        const double rel = std::min(detail::preview::kProbeMaxPixelError, d / norm);
        sum += rel * rel;
        ++n;
      }
    const double all = std::sqrt(sum / double(n));
    const double probe = is_good ? p_good[0] : p_coarse[0];
    EXPECT_NEAR(probe, all, 0.05 * all) << (is_good ? "64^2 chain" : "16^2 chain") << ", " << n << " pixels";
  }
}

// --no-shares: no ideal bake, no shares.
TEST(PreviewShares, OffMeansNone) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  auto backend = Backend::open(*dev);
  const fs::path dir = test::temp_dir("preview_shares", "off");
  const EnvImage env = load_environment(white_hdr(dir).string());
  PlanOptions o;
  o.chain_size = 16;
  PreviewSpec spec;
  spec.bake = bake_folder(*backend, env, EngineTarget::Generic, o, dir, "generic");
  spec.width = spec.height = 32;
  spec.materials = {kMaterials[0]};
  spec.shares = false;
  const PreviewResult r = render_preview(*backend, env, spec);
  EXPECT_TRUE(r.ideal.rgb.empty());
  EXPECT_TRUE(r.share_groups.empty());
  EXPECT_EQ(r.times.ideal, 0.0);
  ASSERT_EQ(r.stats.size(), 1u);
  EXPECT_EQ(r.stats[0].bake_share.rms, 0.0);
}

}  // namespace
}  // namespace brdfbake
