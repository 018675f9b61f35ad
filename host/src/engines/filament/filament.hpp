// Internal: the `filament` target, Filament, what cmgen -x DIR -f ktx writes and KtxUtility loads: its descriptor
// (descriptor.cpp), its writer (writer.cpp), the preview's reader (reader.cpp) and split-sum shading (splitsum.cpp),
// registered in engines/registry.cpp.
#pragma once

#include <string>
#include <vector>

#include "engines/registry.hpp"
#include "families/preview/bake_files.hpp"
#include "families/preview/splitsum_sampling.hpp"

namespace brdfbake::detail::engines::filament {

EngineSettings settings();
std::vector<OutFile> cmgen_ktx(const EngineSettings& s, const EngineBake& bake, const std::string& name,
                               const EngineWriteOptions& o, Metadata& delivered);
void create_indirect_light(const bake_read::Field& manifest, preview::BakeFiles& b);
void light_ibl_dfg(preview::BakeFiles& b);

// splitsum.cpp: light_indirect.fs, the registry's shading row.
float perceptual_roughness_to_lod(const preview::SplitSumSampler& s, float perceptual_roughness);
void prefiltered_radiance(const preview::SplitSumSampler& s, const Vec3& r, float perceptual_roughness, float out[3]);
float sheen_dfg(const preview::SplitSumSampler& s, float n_dot_v, float sheen_perceptual_roughness);
void evaluate_ibl(const preview::SplitSumSampler& s, const PreviewMaterial& m, const preview::BaseInputs& in,
                  float out[3]);
void evaluate_sheen_ibl(const preview::SplitSumSampler& s, const Vec3& n, const Vec3& v, const PreviewMaterial& m,
                        float aa_alpha_g, float out[3]);
void evaluate_clear_coat_ibl(const preview::SplitSumSampler& s, const Vec3& n, const Vec3& v, const PreviewMaterial& m,
                             float aa_alpha_g, float out[3]);
const preview::SplitSumShading& shading();

}  // namespace brdfbake::detail::engines::filament
