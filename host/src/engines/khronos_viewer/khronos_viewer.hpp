// Internal: the `khronos-viewer` target, the glTF-Sample-Viewer / glTF-IBL-Sampler convention: its descriptor
// (descriptor.cpp), its writer (writer.cpp), the preview's reader (reader.cpp) and split-sum shading (splitsum.cpp),
// registered in engines/registry.cpp.
#pragma once

#include <string>
#include <vector>

#include "engines/registry.hpp"
#include "families/preview/bake_files.hpp"
#include "families/preview/splitsum_sampling.hpp"

namespace brdfbake::detail::engines::khronos_viewer {

EngineSettings settings();
std::vector<OutFile> ibl_sampler_ktx2(const EngineSettings& s, const EngineBake& bake, const std::string& name,
                                      const EngineWriteOptions& o, Metadata& delivered);
void read_ggx_and_lambertian(const bake_read::Field& manifest, preview::BakeFiles& b);
void read_charlie(const bake_read::Field& manifest, preview::BakeFiles& b);

// splitsum.cpp: ibl.glsl and pbr.frag, the registry's shading row.
void get_ibl_radiance_ggx(const preview::SplitSumSampler& s, const PreviewMaterial& m, const preview::BaseInputs& in,
                          float out[3]);
void get_ibl_radiance_charlie(const preview::SplitSumSampler& s, const Vec3& n, const Vec3& v, const PreviewMaterial& m,
                              float aa_alpha_g, float out[3]);
void clearcoat_ibl(const preview::SplitSumSampler& s, const Vec3& n, const Vec3& v, const PreviewMaterial& m,
                   float aa_alpha_g, float out[3]);
const preview::SplitSumShading& shading();

}  // namespace brdfbake::detail::engines::khronos_viewer
