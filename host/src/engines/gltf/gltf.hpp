// Internal: the `gltf` target, glTF 2.0 EXT_lights_image_based, as Babylon.js's glTF loader reads it: its descriptor
// (descriptor.cpp), its writer (writer.cpp), the preview's reader (reader.cpp) and split-sum shading (splitsum.cpp),
// registered in engines/registry.cpp.
#pragma once

#include <string>
#include <vector>

#include "engines/registry.hpp"
#include "families/preview/bake_files.hpp"
#include "families/preview/splitsum_sampling.hpp"

namespace brdfbake::detail::engines::gltf {

EngineSettings settings();
std::vector<OutFile> ext_lights_image_based(const EngineSettings& s, const EngineBake& bake, const std::string& name,
                                            const EngineWriteOptions& o, Metadata& delivered);
void load_light(const bake_read::Field& manifest, preview::BakeFiles& b);

// splitsum.cpp: Babylon.js's glTF loader and the PBRMaterial it makes (babylon/splitsum.hpp), the registry's
// shading row.
const preview::SplitSumShading& shading();

}  // namespace brdfbake::detail::engines::gltf
