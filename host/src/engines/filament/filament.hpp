// Internal: the `filament` target, Filament, what cmgen -x DIR -f ktx writes and KtxUtility loads: its descriptor
// (descriptor.cpp), its writer (writer.cpp) and the preview's reader (reader.cpp), registered in engines/registry.cpp.
#pragma once

#include <string>
#include <vector>

#include "engines/registry.hpp"
#include "families/preview/bake_files.hpp"

namespace brdfbake::detail::engines::filament {

EngineSettings settings();
std::vector<OutFile> cmgen_ktx(const EngineSettings& s, const EngineBake& bake, const std::string& name,
                               const EngineWriteOptions& o, Metadata& delivered);
void create_indirect_light(const bake_read::Field& manifest, preview::BakeFiles& b);
void light_ibl_dfg(preview::BakeFiles& b);

}  // namespace brdfbake::detail::engines::filament
