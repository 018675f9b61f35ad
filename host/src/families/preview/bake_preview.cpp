// bake --preview (bake_preview.hpp).
#include "families/preview/bake_preview.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "brdfbake/error.hpp"
#include "brdfbake/preview.hpp"
#include "families/preview/output.hpp"
#include "io/atomic_file.hpp"
#include "text.hpp"

namespace brdfbake::detail::preview {

namespace {

namespace fs = std::filesystem;

const char* const kSiblings[] = {"preview.png", "preview_splitsum.exr", "preview_reference.exr", "preview.json"};

}  // namespace

void check_bake_preview(const Job& job) {
  const std::string origin = job.source.empty() ? std::string("job") : job.source;
  bool chain = false, irradiance = false;
  for (const auto& t : job.tables) {
    chain = chain || (t.kind == TableKind::Prefilter && t.text("distribution") == "ggx");
    irradiance = irradiance || t.kind == TableKind::Irradiance;
    for (const char* name : kSiblings)
      if (fs::path(t.output).lexically_normal() == name)
        throw Error(origin + ": preview: the output '" + t.output + "' is the preview's own file");
  }
  // A scene of metals plans no irradiance: its preview shades them without one (generic target;
  // the engine targets' plans always hold one). Without a scene the preview's default grid needs it.
  if (!chain || (!irradiance && job.scene.empty()))
    throw Error(origin + ": preview: the bake has no " + (chain ? "irradiance table" : "GGX prefiltered chain") +
                " to render a preview from (the default plan has both)");
  // The preview's reference runs on the chain's device: the scalar reference would take hours for
  // the 512 x 512 grid (the same refusal from the command line, a job and POST /v1/bake).
  const std::string& device = bake_preview_chain(job).device;
  if ((device.empty() ? job.device : device) == "reference")
    throw Error(origin +
                ": preview: its reference render runs on the chain's device, and the scalar reference "
                "device would take hours for it: bake on an OpenCL device, or without the preview");
}

const TableRequest& bake_preview_chain(const Job& job) {
  for (const auto& t : job.tables)
    if (t.kind == TableKind::Prefilter && t.text("distribution") == "ggx") return t;
  throw Error(job.source + ": preview: the bake has no GGX prefiltered chain");
}

void write_bake_preview(const Job& job, const std::string& staging, Manifest& manifest, Backend& backend,
                        const EnvImage& environment) {
  const auto t0 = std::chrono::steady_clock::now();
  // The preview reads the bake as it will be: its manifest, so far.
  io::write_file_atomically((fs::path(staging) / "manifest.json").string(), manifest_to_json(manifest));
  PreviewSpec spec;
  spec.target = engine_target_from_name(job.target);
  spec.bake = staging;
  spec.precision = job.precision;
  // A scene's bake previews the scene's materials, one sphere each (issue 34: it rendered the
  // default grid); without a scene, the default grid.
  if (!job.scene.empty()) spec.materials_file = job.scene;
  PreviewResult r = render_preview(backend, environment, spec);
  // the JSON names the folder the files land in, not the staging one
  r.spec.bake = manifest.output_dir;
  for (Metadata* m : {&r.bake, &r.shading})
    for (auto& kv : *m)
      for (size_t at = kv.second.find(staging); at != std::string::npos;
           at = kv.second.find(staging, at + manifest.output_dir.size()))
        kv.second.replace(at, staging.size(), manifest.output_dir);
  write_preview(r, environment.source, (fs::path(staging) / kBakePreviewSheet).string());

  for (const char* name : kSiblings) manifest.preview_files.push_back(name);
  std::vector<double> rms;
  double bound = 0.0;
  for (const auto& s : r.stats) {
    rms.push_back(s.linear.rms);
    bound = std::max(bound, s.reference_rms_bound);
  }
  std::sort(rms.begin(), rms.end());
  manifest.preview.push_back({"sheet", kBakePreviewSheet});
  manifest.preview.push_back({"target", engine_target_name(spec.target)});
  manifest.preview.push_back({"held_to", engine_settings(spec.target).held_to});
  manifest.preview.push_back({"spheres", std::to_string(r.spheres.size())});
  if (!rms.empty()) {
    manifest.preview.push_back({"error_rms_median", detail::fmt_number(rms[rms.size() / 2], "%.4g")});
    manifest.preview.push_back({"error_rms_max", detail::fmt_number(rms.back(), "%.4g")});
    manifest.preview.push_back({"reference_bound_max", detail::fmt_number(bound, "%.4g")});
  }
  if (!r.ideal.rgb.empty() && !r.stats.empty()) {
    // the error's shares (docs/PREVIEW.md): the engine's (no file changes it) and the bake's
    std::vector<double> engine, bake;
    for (const auto& s : r.stats) {
      engine.push_back(s.engine_share.rms);
      bake.push_back(s.bake_share.rms);
    }
    std::sort(engine.begin(), engine.end());
    std::sort(bake.begin(), bake.end());
    manifest.preview.push_back({"engine_share_median", detail::fmt_number(engine[engine.size() / 2], "%.4g")});
    manifest.preview.push_back({"engine_share_max", detail::fmt_number(engine.back(), "%.4g")});
    manifest.preview.push_back({"bake_share_median", detail::fmt_number(bake[bake.size() / 2], "%.4g")});
    manifest.preview.push_back({"bake_share_max", detail::fmt_number(bake.back(), "%.4g")});
  }
  manifest.preview.push_back(
      {"error_definition",
       "per sphere, the relative RMS of |split-sum - reference| / |reference| in linear radiance (preview.json "
       "has every sphere's numbers)"});
  manifest.preview.push_back(
      {"seconds",
       detail::fmt_number(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), "%.4g")});
}

}  // namespace brdfbake::detail::preview
