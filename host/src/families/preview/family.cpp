// The preview family (kind preview): material spheres lit by an environment, the split-sum render of
// a target engine against the converged reference render, and the error per sphere
// (brdfbake/preview.hpp, docs/PREVIEW.md). Its parts: model.cpp (materials, layout, camera),
// bake_files.cpp and splitsum.cpp (the target's files and shader), shading.cpp (the BRDF),
// tree.cpp, opencl.cpp and kernels/preview.cl (the reference on a device), reference.cpp and
// host/reference/src/preview.cpp (the brute force of the reference backend), render.cpp (the whole
// render), output.cpp (the sheet, the EXRs, the JSON). Tests: tests/device/test_preview.cpp,
// tests/reference/test_preview_reference.cpp.
//
// Outputs: NAME.png, and beside it NAME_splitsum.exr, NAME_reference.exr, NAME.json, always named
// after the sheet (not output-only path parameters): a job's files then all land in its staging
// folder and are committed together, and whoever reads the sheet finds the numbers by its name.
#include "families/family.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "brdfbake/engines.hpp"
#include "brdfbake/preview.hpp"
#include "families/kernels.hpp"
#include "families/preview/kernel.hpp"
#include "families/preview/model.hpp"
#include "families/preview/output.hpp"
#include "families/spec_schema.hpp"
#include "io/staging_dir.hpp"

namespace brdfbake::detail {
namespace {

namespace fs = std::filesystem;

SpecSchema<PreviewSpec> preview_schema() {
  static const PreviewSpec d;
  using T = ParamType;
  SpecSchema<PreviewSpec> s;
  s.bind(&PreviewSpec::target, "target",
         ParamDef("target", T::Name, "the engine whose shader the split-sum render emulates (docs/ENGINES.md)")
             .one_of(engine_target_names())
             .def(std::string(engine_target_name(d.target))),
         by_name(engine_target_from_name))
      .bind(&PreviewSpec::bake, "bake",
            ParamDef("bake", T::Path,
                     "a bake's output folder (brdfbake bake --target T -o DIR); default: baked first with the target's "
                     "settings"))
      .bind(&PreviewSpec::keep_bake, "keep_bake",
            ParamDef("keep_bake", T::Path,
                     "without bake: keep the first bake's files in this new (or empty) folder; default: a temporary "
                     "folder removed after the render"))
      .bind("materials_file",
            // "material", as eval and tabulate name a material file ("materials" is a table's
            // informative list of the materials that asked for it): its old name is an alias
            ParamDef("material", T::Path,
                     "the spheres: a material file (ours or glTF, as eval and tabulate read; one sphere "
                     "a material); default: roughness 0..1 x white, grey, dark, gold, copper, silver")
                .alias("materials"),
            [](PreviewSpec& p, const TableRequest& t) {
              if (t.find("material"))
                p.materials_file = t.text("material");
              else if (t.find("scene"))
                p.materials_file = t.text("scene");
            })
      .param(ParamDef("scene", T::Path, "the spheres: a glTF scene's materials, one sphere each (not with material)"))
      .internal("materials", "in-memory materials (API callers); the command line and jobs give a file")
      .bind(&PreviewSpec::width, "width",
            ParamDef("width", T::Int, "image width in pixels").range(16, kPreviewMaxSize).def(double(d.width)))
      .bind(&PreviewSpec::height, "height",
            ParamDef("height", T::Int, "image height in pixels").range(16, kPreviewMaxSize).def(double(d.height)))
      .bind(&PreviewSpec::columns, "columns",
            ParamDef("columns", T::Int, "spheres a row; 0: 12 for the default grid, else about square cells")
                .range(0, kPreviewMaxSpheres)
                .def(double(d.columns)))
      .bind(&PreviewSpec::background, "background",
            ParamDef("background", T::Name, "behind the spheres: the environment, or flat grey 0.18")
                .one_of(enum_names(preview::kBackgroundNames))
                .def(std::string(preview_background_name(d.background))),
            by_name(preview_background_from_name))
      .bind(&PreviewSpec::yaw, "yaw",
            ParamDef("yaw", T::Number, "camera yaw about +Y, degrees (0: looking down -Z)").range(-360, 360).def(d.yaw))
      .bind(&PreviewSpec::pitch, "pitch",
            ParamDef("pitch", T::Number, "camera pitch, degrees (positive: looking up)").range(-89, 89).def(d.pitch))
      .bind(&PreviewSpec::reference, "reference",
            ParamDef("reference", T::Flag, "render the reference and the error (off: the split-sum render alone)")
                .def(d.reference))
      .bind(&PreviewSpec::refinement, "refinement",
            ParamDef("refinement", T::Number,
                     "the reference quadrature's refinement (its bound is measured against twice it)")
                .range(1, 64)
                .def(d.refinement))
      .bind(&PreviewSpec::bound_goal, "bound_goal",
            ParamDef("bound_goal", T::Number,
                     "a sphere whose reference bound (relative RMS) exceeds this is integrated again at twice the "
                     "refinement, at most twice (0: never)")
                .range(0, 1)
                .def(d.bound_goal))
      .bind(&PreviewSpec::bound_stride, "bound_stride",
            ParamDef("bound_stride", T::Int,
                     "every this many pixels of a sphere (at least 16 a sphere) measure the reference's bound")
                .range(1, 1 << 20)
                .def(double(d.bound_stride)))
      .bind(&PreviewSpec::mix_ibl_radiance_with_irradiance, "mix_ibl_radiance_with_irradiance",
            ParamDef("mix_ibl_radiance_with_irradiance", T::Flag,
                     "gltf, babylon: Babylon.js's PBRBRDFConfiguration.DEFAULT_MIX_IBL_RADIANCE_WITH_IRRADIANCE, on in "
                     "8.46.2 (--no-mix-ibl-radiance-with-irradiance: as a scene that turned it off)")
                .def(d.mix_ibl_radiance_with_irradiance))
      .bind(&PreviewSpec::shares, "shares",
            ParamDef("shares", T::Flag,
                     "split the error into the engine's share and the bake's: the target's shader rendered once more "
                     "from an ideal bake made in memory (with the reference; --no-shares: not computed)")
                .def(d.shares))
      .common("precision", "precision", [](PreviewSpec& p, const TableRequest& t) { p.precision = t.precision; });
  return s;
}

const SpecSchema<PreviewSpec>& schema_of() {
  static const SpecSchema<PreviewSpec> s = preview_schema();
  return s;
}

PreviewSpec spec_of(const TableRequest& t) { return schema_of().fill(t); }

std::string summary_of(const PreviewResult& r) {
  char b[512];
  std::string s = std::string("preview ") + engine_target_name(r.spec.target) + " " + std::to_string(r.spec.width) +
                  "x" + std::to_string(r.spec.height) + ", " + std::to_string(r.spheres.size()) + " spheres";
  if (!r.stats.empty()) {
    std::vector<double> rms;
    double bound = 0.0;
    for (const auto& st : r.stats) {
      rms.push_back(st.linear.rms);
      bound = std::max(bound, st.reference_rms_bound);
    }
    std::sort(rms.begin(), rms.end());
    s += ": split-sum vs reference RMS " + percent_text(rms[rms.size() / 2]) + " median, " + percent_text(rms.back()) +
         " worst sphere; reference within " + percent_text(bound) + " RMS";
  }
  if (!r.ideal.rgb.empty() && !r.stats.empty()) {
    std::vector<double> engine, bake;
    for (const auto& st : r.stats) {
      engine.push_back(st.engine_share.rms);
      bake.push_back(st.bake_share.rms);
    }
    std::sort(engine.begin(), engine.end());
    std::sort(bake.begin(), bake.end());
    s += "; engine share " + percent_text(engine[engine.size() / 2]) + " median, " + percent_text(engine.back()) +
         " worst; bake share " + percent_text(bake[bake.size() / 2]) + " median, " + percent_text(bake.back()) +
         " worst";
  }
  std::snprintf(b, sizeof b,
                "; %.2f s (bake %.2f, split-sum %.3f, reference %.2f, device %.2f, bound %.2f, ideal bake %.2f)",
                r.times.total, r.times.bake, r.times.splitsum, r.times.reference, r.times.reference_device,
                r.times.bound, r.times.ideal);
  return s + b;
}

class PreviewFamily final : public Family {
 public:
  std::vector<TableKind> kinds() const override { return {TableKind::Preview}; }
  std::string command() const override { return "preview"; }
  CommandText command_text() const override {
    return {"render material spheres: a target's split-sum render against the converged reference",
            "Render material spheres lit by an environment: what a target engine computes from a bake's files, against "
            "the converged reference, and the error per sphere",
            "brdfbake preview --env venice_sunset_1k.hdr --target filament -o venice.png"};
  }
  std::string summary(TableKind) const override {
    return "material spheres: a target's split-sum render against the reference, the error per sphere";
  }
  const std::vector<ParamDef>& schema(TableKind) const override { return schema_of().schema(); }
  std::vector<SpecField> spec_fields(TableKind) const override { return schema_of().fields(); }
  std::string default_pixel() const override { return "f32"; }
  bool uses_environment() const override { return true; }
  // The split-sum render alone from a bake folder runs on the host.
  bool needs_device(const TableRequest& t) const override { return t.flag("reference", true) || !t.find("bake"); }

  void check(TableRequest& t, const FieldName& name) const override {
    if (t.find("material") && t.find("scene"))
      throw FieldError("scene", "give " + name("material") + " or " + name("scene") + ", not both");
    if (t.find("keep_bake")) {
      if (t.find("bake"))
        throw FieldError("keep_bake", "give " + name("bake") + " or " + name("keep_bake") + ", not both");
      if (!io::is_new_or_empty_folder(t.text("keep_bake")))
        throw FieldError("keep_bake", "'" + t.text("keep_bake") +
                                          "' exists and is not an empty folder: give a new one (the first bake is "
                                          "written there as a bake's output folder)");
    }
    if (t.find("bake")) {
      std::error_code ec;
      if (!fs::is_regular_file(fs::path(t.text("bake")) / "manifest.json", ec))
        throw FieldError("bake", "'" + t.text("bake") +
                                     "' holds no manifest.json (a bake's output folder: brdfbake bake --target " +
                                     t.text("target") + " -o DIR)");
    }
    try {
      preview::resolve_spec(spec_of(t));
    } catch (const Error& e) {
      const std::string what = e.what();
      const std::string field = t.find("material") && what.find(t.text("material")) != std::string::npos ? "material"
                                : t.find("scene") && what.find(t.text("scene")) != std::string::npos     ? "scene"
                                : what.find("material") != std::string::npos ? (t.find("scene") ? "scene" : "material")
                                : what.find("refinement") != std::string::npos ? "refinement"
                                                                               : "width";
      throw FieldError(field, what);
    }
  }
  std::string default_output(const TableRequest& t) const override { return "preview_" + t.text("target") + ".png"; }
  OutputFormats formats(const TableRequest&) const override {
    return {{".png"}, "a contact sheet (.png; NAME_splitsum.exr, NAME_reference.exr and NAME.json beside it)"};
  }
  // The sheet's siblings are outputs as the sheet is (issue 34, class 1: `-o p.png` beside
  // `--material p.json`, `-o BAKE/manifest.png`).
  std::vector<RequestFile> outputs_beside(const TableRequest& t) const override {
    std::vector<RequestFile> out;
    for (const char* suffix : {".json", "_splitsum.exr", "_reference.exr"}) {
      const std::string path = preview::sibling(t.output, suffix);
      out.push_back({"output", path, false, fs::path(path).filename().string()});
    }
    return out;
  }
  // A bake folder's files are inputs: the manifest and the files it names (the first 4096 regular
  // files of the folder and its sub-folders, which is more than any bake writes).
  std::vector<RequestFile> inputs_beside(const TableRequest& t) const override {
    std::vector<RequestFile> in;
    if (!t.find("bake")) return in;
    std::error_code ec;
    fs::recursive_directory_iterator it(t.text("bake"), fs::directory_options::none, ec), end;
    for (; !ec && it != end && in.size() < 4096; it.increment(ec)) {
      if (it.depth() > 2) it.disable_recursion_pending();
      if (it->is_regular_file(ec)) in.push_back({"bake", it->path().string(), false, it->path().filename().string()});
    }
    return in;
  }
  TableExample example(TableKind) const override {
    TableExample e;
    e.request.environment = "builtin:sun";
    e.request.params = {{"width", 96.0}, {"height", 48.0}, {"bound_stride", 64.0}};
    return e;
  }
  void register_kernels(KernelRegistry& r) const override {
    r.add<PreviewKernel>(Platform::OpenCl, [](Backend& b) { return make_opencl_preview(*b.device()); });
    r.add<PreviewKernel>(Platform::Reference, [](Backend&) { return make_reference_preview(); });
  }
  BakeResult bake(const TableRequest& t, Backend& backend, const BakeInputs& in,
                  const BakeProgress& progress) const override {
    PreviewResult res = render_preview(backend, *in.environment, spec_of(t), progress, in.scratch_dir);
    BakeResult r;
    if (!res.stats.empty()) {
      double bound = 0.0;
      for (const auto& st : res.stats) bound = std::max(bound, st.reference_rms_bound);
      r.error_bound = bound;
      r.error_bound_definition = "the reference render's: " + res.bound_definition + "; the largest over the spheres";
      double worst = 0.0;
      for (const auto& st : res.stats) worst = std::max(worst, st.linear.rms);
      r.details.push_back({"splitsum_rms_worst_sphere", fmt_number(worst, "%.4g")});
    }
    r.details.push_back({"spheres", std::to_string(res.spheres.size())});
    r.details.push_back({"exposure_ev", fmt_number(res.exposure, "%.3f")});
    r.device_seconds = res.times.reference_device;
    r.summary = summary_of(res);
    r.artifact = std::move(res);
    return r;
  }
  WriteReport write(const BakeResult& r, const TableRequest& t, const std::string& path) const override {
    if (path == "-") throw Error("a preview is written to files: give -o NAME.png");
    preview::write_preview(*r.preview(), t.environment, path);
    WriteReport w;
    w.encoding = "8-bit sRGB PNG (the sheet), float32 OpenEXR (the renders), JSON (the numbers)";
    w.error_bound = r.error_bound;
    return w;
  }
  std::uint64_t estimated_bytes(const TableRequest& t) const override {
    // two float images and the error, the sheet, and the environment's quadtree (44 bytes a pixel of
    // the map and 4/3 for its levels: 31 MiB for a 1k map; 4k maps take 0.5 GiB)
    const double pixels = t.number("width") * t.number("height");
    return static_cast<std::uint64_t>(pixels * (3 * 12 + 4 + 3 * 3) + 64.0 * 1024 * 1024);
  }
};

}  // namespace

const Family& preview_family() {
  static const PreviewFamily f;
  return f;
}

}  // namespace brdfbake::detail
