// Internal: `brdfbake bake --preview` (Job::preview): the preview of a run's own files, rendered from
// its staging folder before the manifest is written, so that the preview lands with the files (all or
// nothing) and the manifest records it.
#pragma once

#include <string>

#include "brdfbake/backend.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/job.hpp"
#include "brdfbake/manifest.hpp"

namespace brdfbake::detail::preview {

// The sheet's name in the bake folder; its siblings are preview_splitsum.exr, preview_reference.exr
// and preview.json.
inline constexpr const char* kBakePreviewSheet = "preview.png";

// Throws Error (before any bake) when the job cannot have a preview: no GGX prefiltered chain, no
// irradiance table, or an output of its own named like the preview's files.
void check_bake_preview(const Job& job);
// The job's first GGX prefiltered chain: the preview renders on its device, from its environment.
const TableRequest& bake_preview_chain(const Job& job);

// Renders the preview of the files in `staging` (manifest.json, as the run has it so far, is written
// there first for the preview to read, and replaced by the run afterwards) for the job's target, the
// scene's materials (the default grid without a scene) at 512 x 512 with the reference, on `backend`, from
// `environment` (the chain's). Writes preview.png and its siblings into `staging` and records them in `manifest`
// (preview_files, preview: the sheet, the worst and median sphere's error, the reference's bound, the seconds).
void write_bake_preview(const Job& job, const std::string& staging, Manifest& manifest, Backend& backend,
                        const EnvImage& environment);

}  // namespace brdfbake::detail::preview
