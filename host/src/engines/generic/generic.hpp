// Internal: the `generic` target, brdfbake's own runtime convention (docs/CONVENTIONS.md): its descriptor
// (descriptor.cpp), its writer (writer.cpp), the preview's reader (reader.cpp) and split-sum shading (splitsum.cpp),
// registered in engines/registry.cpp.
#pragma once

#include <string>
#include <vector>

#include "engines/registry.hpp"
#include "families/preview/bake_files.hpp"
#include "families/preview/splitsum_sampling.hpp"

namespace brdfbake::detail::engines::generic {

EngineSettings settings();
std::vector<OutFile> write(const EngineSettings& s, const EngineBake& bake, const std::string& name,
                           const EngineWriteOptions& o, Metadata& delivered);
void read_prefiltered_and_sh(const bake_read::Field& manifest, preview::BakeFiles& b);
void read_charlie_chain(const bake_read::Field& manifest, preview::BakeFiles& b);

// splitsum.cpp: docs/CONVENTIONS.md's runtime, the registry's shading row.
void split_sum_ibl(const preview::SplitSumSampler& s, const PreviewMaterial& m, const preview::BaseInputs& in,
                   float out[3]);
void charlie_sheen(const preview::SplitSumSampler& s, const Vec3& n, const Vec3& v, const PreviewMaterial& m,
                   float aa_alpha_g, float out[3]);
void fresnel_coat(const preview::SplitSumSampler& s, const Vec3& n, const Vec3& v, const PreviewMaterial& m,
                  float aa_alpha_g, float out[3]);
const preview::SplitSumShading& shading();

}  // namespace brdfbake::detail::engines::generic
