// Every program variant the product can request builds without a compiler warning (issue 18).
//
// The variants: each kernel family with each combination of #defines its host code (the planner,
// the evaluator, the bake commands) can produce, in fp32 and fp64, with and without
// -cl-fast-relaxed-math. The enumeration below mirrors the host's choices;
// KernelBuild.EveryKernelSwitchIsEnumerated guards it against drift by scanning the kernel sources
// for the BRDFBAKE_* switches they test, and the host sources for the ones they set, and requiring
// each to be covered here.
//
// Builds go through the product's one build path (detail::build_program) with brdfbake's on-disk
// cache off, so each is a build from source whose log the driver fills, the program text written as
// the host writes it (in_host_order). PoCL's own cache may answer a build that another test of the
// run made first: it keeps the build log with the binary and returns it (a warning planted in
// kernels/dfg_lut.cl fails DfgLutVariantsAreWarningFree from PoCL's cache as from a fresh build).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "brdfbake/brdf.hpp"
#include "families/brdf_eval/model.hpp"
#include "runtime/cl.hpp"
#include "runtime/program.hpp"
#include "support/device_fixture.hpp"

namespace brdfbake {
namespace {

using Defines = std::vector<std::pair<std::string, std::string>>;

struct Variant {
  std::string file;
  Defines defines;
  bool fast_math_too = true;  // also built with -cl-fast-relaxed-math
};

// Subsets of `flags`, as define lists.
std::vector<Defines> subsets(const std::vector<std::string>& flags) {
  std::vector<Defines> out;
  for (unsigned mask = 0; mask < (1u << flags.size()); ++mask) {
    Defines d;
    for (size_t k = 0; k < flags.size(); ++k)
      if (mask & (1u << k)) d.push_back({flags[k], "1"});
    out.push_back(d);
  }
  return out;
}

bool has(const Defines& d, const std::string& name) {
  return std::any_of(d.begin(), d.end(), [&](const auto& p) { return p.first == name; });
}

Defines join(Defines a, const Defines& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// host/src/families/dfg_lut/opencl.cpp: one table kind, one estimator (resolve_lut_spec: GGX takes quadrature, vndf
// or ndf; Charlie quadrature, ndf or uniform), and for Charlie the sheen visibility.
std::vector<Variant> dfg_variants() {
  std::vector<Variant> v;
  for (const char* kind : {"BRDFBAKE_LUT_GGX", "BRDFBAKE_LUT_GGX_MULTISCATTER"})
    for (const char* est : {"BRDFBAKE_EST_QUADRATURE", "BRDFBAKE_EST_VNDF", "BRDFBAKE_EST_NDF"})
      v.push_back({"dfg_lut.cl", {{kind, "1"}, {est, "1"}}});
  for (const char* est : {"BRDFBAKE_EST_QUADRATURE", "BRDFBAKE_EST_NDF", "BRDFBAKE_EST_UNIFORM"})
    for (bool neubelt : {false, true}) {
      Defines d = {{"BRDFBAKE_LUT_CHARLIE", "1"}, {est, "1"}};
      if (neubelt) d.push_back({"BRDFBAKE_SHEEN_NEUBELT", "1"});
      v.push_back({"dfg_lut.cl", d});
    }
  return v;
}

// The GPU shape of host/src/families/dfg_lut/opencl.cpp: the same variants, a work-group of 32 a cell.
std::vector<Variant> gpu_dfg_variants() {
  std::vector<Variant> v = dfg_variants();
  for (Variant& d : v) {
    d.defines.push_back({"BRDFBAKE_DFG_GROUPS", "1"});
    d.defines.push_back({"BRDFBAKE_DFG_GROUP", "32"});
  }
  return v;
}

// host/src/families/fresnel/opencl.cpp: one model, 1-D or 2-D; the lane count is set per precision below.
std::vector<Variant> fresnel_variants() {
  std::vector<Variant> v;
  for (const char* model : {"BRDFBAKE_FRESNEL_SCHLICK", "BRDFBAKE_FRESNEL_SCHLICK_METALLIC",
                            "BRDFBAKE_FRESNEL_SCHLICK_IOR", "BRDFBAKE_FRESNEL_DIELECTRIC", "BRDFBAKE_FRESNEL_CONDUCTOR",
                            "BRDFBAKE_FRESNEL_F82_TINT", "BRDFBAKE_FRESNEL_EMPIRICAL"})
    for (bool two_d : {false, true}) {
      Defines d = {{model, "1"}, {"BRDFBAKE_FRESNEL_CHUNKS", "8"}};
      if (two_d) d.push_back({"BRDFBAKE_FRESNEL_2D", "1"});
      v.push_back({"fresnel.cl", d});
    }
  return v;
}

// host/src/families/brdf_eval/names.cpp (lobes_used): the lobes a set of materials can switch on. Disney's
// subsurface and sheen come only with its diffuse lobe (metallic < 1); glTF has a diffuse or a
// metal lobe or both, its specular colour only with the diffuse lobe; Cook-Torrance uses Beckmann,
// GGX or both. The lane width (8 or 16) is an option of the evaluator's API.
std::vector<Variant> brdf_variants() {
  std::vector<Variant> v;
  auto add = [&](const char* model, const Defines& lobes) {
    v.push_back({"brdf_eval.cl", join({{model, "1"}}, lobes)});
  };
  for (const Defines& l : subsets({"BRDFBAKE_LOBE_DIFFUSE", "BRDFBAKE_LOBE_SUBSURFACE", "BRDFBAKE_LOBE_SHEEN",
                                   "BRDFBAKE_LOBE_CLEARCOAT", "BRDFBAKE_LOBE_ANISOTROPIC"})) {
    const bool diffuse = has(l, "BRDFBAKE_LOBE_DIFFUSE");
    if (!diffuse && (has(l, "BRDFBAKE_LOBE_SUBSURFACE") || has(l, "BRDFBAKE_LOBE_SHEEN"))) continue;
    add("BRDFBAKE_MODEL_DISNEY", l);
  }
  for (const char* model : {"BRDFBAKE_MODEL_GLTF", "BRDFBAKE_MODEL_GLTF_CORRELATED"})
    for (const Defines& l : subsets({"BRDFBAKE_LOBE_DIFFUSE", "BRDFBAKE_LOBE_METAL", "BRDFBAKE_LOBE_SPECULAR_COLOR",
                                     "BRDFBAKE_LOBE_SHEEN", "BRDFBAKE_LOBE_CLEARCOAT"})) {
      const bool diffuse = has(l, "BRDFBAKE_LOBE_DIFFUSE"), metal = has(l, "BRDFBAKE_LOBE_METAL");
      if (!diffuse && !metal) continue;
      if (!diffuse && has(l, "BRDFBAKE_LOBE_SPECULAR_COLOR")) continue;
      add(model, l);
    }
  for (const Defines& l : subsets({"BRDFBAKE_CT_BECKMANN", "BRDFBAKE_CT_GGX"}))
    if (!l.empty()) add("BRDFBAKE_MODEL_COOK_TORRANCE", l);
  for (const char* model : {"BRDFBAKE_MODEL_LAMBERT", "BRDFBAKE_MODEL_PHONG", "BRDFBAKE_MODEL_BLINN_PHONG",
                            "BRDFBAKE_MODEL_BLINN_PHONG_FROM_PBR"})
    add(model, {});
  return v;
}

// host/src/prefilter.cpp (the lobe, and kStripRows = 4 rows per strip), environment.cpp,
// irradiance.cpp, thin_film.cpp, report/kernels.cpp (the device's peaks).
std::vector<Variant> environment_variants() {
  return {{"cubemap.cl", {}},
          {"prefilter.cl", {{"BRDFBAKE_ENV_GGX", "1"}, {"BRDFBAKE_STRIP_ROWS", "4"}}},
          {"prefilter.cl", {{"BRDFBAKE_ENV_CHARLIE", "1"}, {"BRDFBAKE_STRIP_ROWS", "4"}}},
          {"irradiance.cl", {{"BRDFBAKE_SH_ORDER", "3"}, {"BRDFBAKE_ENV_COSINE", "1"}}},
          {"irradiance.cl", {{"BRDFBAKE_SH_ORDER", "5"}, {"BRDFBAKE_ENV_COSINE", "1"}}},
          {"thin_film.cl", {}},
          {"device_peak.cl", {}}};  // report --kinds kernels' peaks (host/src/report/kernels.cpp)
}

// The program text the host writes for a variant: its defines in the host's order (a lane count
// after the model, for brdf_eval.cl the lobes in detail::brdf_program_spec's order, for fresnel.cl the
// lanes before the 2-D switch as bake_fresnel writes them). The same defines in another order would
// be the same program but another text: PoCL caches a build (with its log) under a hash of the text,
// so built in the host's order each variant here and the product's build of it in another test of
// the same run are one compile, whichever comes first (stop 31: ~1 min of CPU a run).
Defines in_host_order(const Variant& v, Precision p, const Defines& lanes, bool fresnel_lanes) {
  Defines d = v.defines;
  if (fresnel_lanes) d.insert(d.begin() + 2, {"BRDFBAKE_LANES", p == Precision::Fp64 ? "8" : "16"});
  if (v.file != "brdf_eval.cl") return join(d, lanes);
  const auto model = std::find_if(brdf_models().begin(), brdf_models().end(),
                                  [&](BrdfModel m) { return d.at(0).first == detail::brdf_model_define(m); });
  if (model == brdf_models().end()) {
    ADD_FAILURE() << d.at(0).first << " is no model of brdf_eval.cl";
    return join(d, lanes);
  }
  const std::pair<const char*, bool Lobes::*> switches[] = {{"BRDFBAKE_LOBE_DIFFUSE", &Lobes::diffuse},
                                                            {"BRDFBAKE_LOBE_SUBSURFACE", &Lobes::subsurface},
                                                            {"BRDFBAKE_LOBE_SHEEN", &Lobes::sheen},
                                                            {"BRDFBAKE_LOBE_CLEARCOAT", &Lobes::clearcoat},
                                                            {"BRDFBAKE_LOBE_ANISOTROPIC", &Lobes::anisotropic},
                                                            {"BRDFBAKE_LOBE_METAL", &Lobes::metal},
                                                            {"BRDFBAKE_LOBE_SPECULAR_COLOR", &Lobes::specular_color},
                                                            {"BRDFBAKE_CT_BECKMANN", &Lobes::beckmann},
                                                            {"BRDFBAKE_CT_GGX", &Lobes::ggx}};
  Lobes lobes;
  for (const auto& [name, member] : switches)
    if (has(d, name)) lobes.*member = true;
  EvalOptions o;
  o.precision = p;
  const Defines host = detail::brdf_program_spec(*model, lobes, o, std::stoi(lanes.at(0).second)).defines;
  // the same defines, only their order changed: nothing of the variant lost or added
  using DefineSet = std::multiset<std::pair<std::string, std::string>>;
  const Defines ours = join(d, lanes);
  EXPECT_EQ(DefineSet(host.begin(), host.end()), DefineSet(ours.begin(), ours.end()));
  return host;
}

// Builds each variant in both precisions (and fast math where asked) and collects every log that
// mentions a warning.
void expect_warning_free(const std::vector<Variant>& variants, const std::vector<Defines>& lane_choices = {{}},
                         bool per_precision_fresnel_lanes = false,
                         const std::vector<Precision>& precisions = {Precision::Fp32, Precision::Fp64}) {
  BRDFBAKE_REQUIRE_DEVICE(device);
  detail::set_program_cache_dir("");  // real builds from source
  auto& dev = device->impl();
  const auto t0 = std::chrono::steady_clock::now();
  int built = 0;
  for (Precision p : precisions) {
    if (p == Precision::Fp64 && !device->info().fp64) continue;
    for (const Variant& v : variants)
      for (const Defines& lanes : lane_choices)
        for (bool fast : {false, true}) {
          if (fast && !v.fast_math_too) continue;
          detail::ProgramSpec spec;
          spec.file = v.file;
          spec.precision = p;
          spec.defines = in_host_order(v, p, lanes, per_precision_fresnel_lanes);
          if (fast) spec.options = "-cl-fast-relaxed-math";
          std::string what = v.file + " " + precision_name(p) + (fast ? " fast-math" : "");
          for (const auto& [name, value] : spec.defines) what += " " + name + "=" + value;
          cl::Program program;
          try {
            program = detail::build_program(dev, spec);
          } catch (const Error& e) {
            ADD_FAILURE() << what << ": " << e.what();
            continue;
          }
          ++built;
          const std::string log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(dev.device);
          const bool warned = log.find("warning") != std::string::npos || log.find("error") != std::string::npos;
          EXPECT_FALSE(warned) << what << ":\n" << log;
        }
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("built %d programs in %.1f s\n", built, s);
}

TEST(KernelBuild, DfgLutVariantsAreWarningFree) { expect_warning_free(dfg_variants()); }
TEST(KernelBuild, FresnelVariantsAreWarningFree) { expect_warning_free(fresnel_variants(), {{}}, true); }
// Each model's largest variant: every lobe its materials can switch on together.
std::vector<Variant> largest_brdf_variants() {
  std::vector<Variant> out;
  for (const Variant& v : brdf_variants()) {
    const auto same_model =
        std::find_if(out.begin(), out.end(), [&](const Variant& b) { return b.defines.at(0) == v.defines.at(0); });
    if (same_model == out.end())
      out.push_back(v);
    else if (v.defines.size() > same_model->defines.size())
      *same_model = v;
  }
  return out;
}

// Every lobe subset once (fp32, 16 lanes, IEEE maths): what a subset alone can raise is about which
// lobes' code is compiled (an unused variable or function), the same in either precision and with
// fast maths. Each model's largest variant (every lobe's code) then in both precisions, at both CPU
// widths (16 and 8: an evaluator's `lanes`), with and without -cl-fast-relaxed-math: what the
// precision, the lane width or fast maths can raise (a conversion, a vector type, the fast-maths
// macros) is in code every lobe's variant shares or in a lobe's own code, which the largest compiles.
// (Every variant in both precisions, both maths and both widths was 187 s of the suite's CPU at stop
// 34, every variant in both precisions and maths ~95 s at stop 40: the test command's budget.)
TEST(KernelBuild, BrdfEvalVariantsAreWarningFree) {
  std::vector<Variant> subsets = brdf_variants();
  for (Variant& v : subsets) v.fast_math_too = false;
  expect_warning_free(subsets, {{{"BRDFBAKE_LANES", "16"}}}, false, {Precision::Fp32});
  expect_warning_free(largest_brdf_variants(), {{{"BRDFBAKE_LANES", "16"}}, {{"BRDFBAKE_LANES", "8"}}}, false,
                      {Precision::Fp32, Precision::Fp64});
}
TEST(KernelBuild, EnvironmentVariantsAreWarningFree) { expect_warning_free(environment_variants()); }
// The GPU shape's programs (docs/DEVICES.md, "Kernel shapes"; the prefilter's per-texel walk is in
// prefilter.cl whatever the shape, built above): brdf_eval.cl at 4 lanes, every model with every lobe
// its materials can switch on together (the largest program of each model: the lanes change the
// vector types, which every lobe's code meets), fresnel.cl at one chunk of 8 lanes a work-item, and
// dfg_lut.cl at a work-group a cell.
TEST(KernelBuild, GpuShapeVariantsAreWarningFree) {
  std::vector<Variant> brdf = largest_brdf_variants();
  for (Variant& v : brdf) v.fast_math_too = false;
  expect_warning_free(brdf, {{{"BRDFBAKE_LANES", "4"}}});
  std::vector<Variant> fresnel = fresnel_variants();
  for (Variant& v : fresnel) {
    for (auto& d : v.defines)
      if (d.first == "BRDFBAKE_FRESNEL_CHUNKS") d.second = "1";
    v.defines.insert(v.defines.begin() + 2, {"BRDFBAKE_LANES", "8"});
  }
  expect_warning_free(fresnel);
  expect_warning_free(gpu_dfg_variants());
}

// ---- The enumeration against the sources --------------------------------------------------------

#ifndef BRDFBAKE_SOURCE_DIR
#define BRDFBAKE_SOURCE_DIR "."
#endif

std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The files under `dir` (recursively) whose extension is one of `exts`.
std::vector<std::filesystem::path> sources(const std::filesystem::path& dir, const std::set<std::string>& exts) {
  std::vector<std::filesystem::path> out;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    if (e.is_regular_file() && exts.count(e.path().extension().string())) out.push_back(e.path());
  return out;
}

struct KernelNames {
  std::set<std::string> tested;     // in #if, #ifdef, #ifndef, #elif lines: the switches
  std::set<std::string> defined;    // given a value by a #define of the kernels themselves
  std::set<std::string> mentioned;  // anywhere in the kernel sources
};

KernelNames kernel_names() {
  KernelNames k;
  const std::regex name(R"(BRDFBAKE_[A-Z0-9_]*[A-Z0-9])");
  const std::regex conditional(R"(^\s*#\s*(if|ifdef|ifndef|elif)\b)");
  const std::regex define(R"(^\s*#\s*define\s+(BRDFBAKE_[A-Z0-9_]+))");
  for (const auto& file : sources(std::filesystem::path(BRDFBAKE_SOURCE_DIR) / "kernels", {".cl", ".clh"})) {
    std::istringstream in(read_text(file));
    for (std::string line; std::getline(in, line);) {
      const bool tests = std::regex_search(line, conditional);
      for (auto it = std::sregex_iterator(line.begin(), line.end(), name); it != std::sregex_iterator(); ++it) {
        k.mentioned.insert(it->str());
        if (tests) k.tested.insert(it->str());
      }
      std::smatch m;
      if (std::regex_search(line, m, define)) k.defined.insert(m[1].str());
    }
  }
  return k;
}

// The BRDFBAKE_* names the host code writes as string literals and the kernels mention: the
// switches it can set (environment variables such as BRDFBAKE_CACHE_DIR are never in a kernel).
std::set<std::string> host_switches(const std::set<std::string>& in_kernels) {
  std::set<std::string> out;
  auto name_char = [](char c) { return (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_'; };
  for (const auto& file :
       sources(std::filesystem::path(BRDFBAKE_SOURCE_DIR) / "host" / "src", {".cpp", ".hpp", ".inc"})) {
    const std::string text = read_text(file);
    for (size_t at = text.find("\"BRDFBAKE_"); at != std::string::npos; at = text.find("\"BRDFBAKE_", at + 1)) {
      size_t end = at + 1;
      while (end < text.size() && name_char(text[end])) ++end;
      const std::string s = text.substr(at + 1, end - at - 1);
      if (end < text.size() && text[end] == '"' && in_kernels.count(s)) out.insert(s);
    }
  }
  return out;
}

// What the builds above cover: every define of every variant, the lane counts they pass, and
// BRDFBAKE_FP64, which build_program sets for Precision::Fp64 (both precisions are built).
std::set<std::string> enumerated_switches() {
  std::set<std::string> out = {"BRDFBAKE_FP64", "BRDFBAKE_LANES"};
  for (const auto& variants :
       {dfg_variants(), gpu_dfg_variants(), fresnel_variants(), brdf_variants(), environment_variants()})
    for (const Variant& v : variants)
      for (const auto& d : v.defines) out.insert(d.first);
  return out;
}

// Every switch a kernel tests is built here, unless the kernels give it a default (#ifndef X /
// #define X) and the host never sets it: then the product only ever builds that default, which the
// builds above do too. And every switch the host sets is built here. A new #ifdef in a kernel, or
// a new define in the host, fails this test until the enumeration names it.
TEST(KernelBuild, EveryKernelSwitchIsEnumerated) {
  const KernelNames k = kernel_names();
  const std::set<std::string> host = host_switches(k.mentioned);
  const std::set<std::string> enumerated = enumerated_switches();
  // the scans found the sources (a wrong folder would find nothing and pass)
  ASSERT_TRUE(k.tested.count("BRDFBAKE_LUT_CHARLIE")) << "no kernel sources under " << BRDFBAKE_SOURCE_DIR;
  ASSERT_TRUE(host.count("BRDFBAKE_FRESNEL_2D")) << "no host sources under " << BRDFBAKE_SOURCE_DIR;
  ASSERT_TRUE(k.defined.count("BRDFBAKE_PYRAMID_CAPACITY"));
  for (const std::string& s : k.tested) {
    const bool default_only = k.defined.count(s) && !host.count(s);
    EXPECT_TRUE(enumerated.count(s) || default_only)
        << s << " is tested by a kernel but built by no variant of this file";
  }
  for (const std::string& s : host)
    EXPECT_TRUE(enumerated.count(s)) << s << " is set by the host but built by no variant of this file";
}

}  // namespace
}  // namespace brdfbake
