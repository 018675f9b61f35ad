// Internal: the `khronos-viewer` target, the glTF-Sample-Viewer / glTF-IBL-Sampler convention: its descriptor
// (descriptor.cpp), its writer (writer.cpp) and the preview's reader (reader.cpp), registered in engines/registry.cpp.
#pragma once

#include <string>
#include <vector>

#include "engines/registry.hpp"
#include "families/preview/bake_files.hpp"

namespace brdfbake::detail::engines::khronos_viewer {

EngineSettings settings();
std::vector<OutFile> ibl_sampler_ktx2(const EngineSettings& s, const EngineBake& bake, const std::string& name,
                                      const EngineWriteOptions& o, Metadata& delivered);
void read_ggx_and_lambertian(const bake_read::Field& manifest, preview::BakeFiles& b);
void read_charlie(const bake_read::Field& manifest, preview::BakeFiles& b);

}  // namespace brdfbake::detail::engines::khronos_viewer
