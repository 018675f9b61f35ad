// Internal: the `babylon` target, Babylon.js's .env (EnvironmentTextureTools): its descriptor (descriptor.cpp), its
// writer (writer.cpp) and the preview's reader (reader.cpp), registered in engines/registry.cpp.
#pragma once

#include <string>
#include <vector>

#include "engines/registry.hpp"
#include "families/preview/bake_files.hpp"
#include "families/preview/splitsum_sampling.hpp"

namespace brdfbake::detail::engines::babylon {

EngineSettings settings();
std::vector<OutFile> create_env_texture(const EngineSettings& s, const EngineBake& bake, const std::string& name,
                                        const EngineWriteOptions& o, Metadata& delivered);
void upload_env_levels(const bake_read::Field& manifest, preview::BakeFiles& b);

// splitsum.cpp: PBRMaterial (splitsum.hpp), the registry's shading row.
const preview::SplitSumShading& shading();

}  // namespace brdfbake::detail::engines::babylon
