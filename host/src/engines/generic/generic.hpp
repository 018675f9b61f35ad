// Internal: the `generic` target, brdfbake's own runtime convention (docs/CONVENTIONS.md): its descriptor
// (descriptor.cpp), its writer (writer.cpp) and the preview's reader (reader.cpp), registered in engines/registry.cpp.
#pragma once

#include <string>
#include <vector>

#include "engines/registry.hpp"
#include "families/preview/bake_files.hpp"

namespace brdfbake::detail::engines::generic {

EngineSettings settings();
std::vector<OutFile> write(const EngineSettings& s, const EngineBake& bake, const std::string& name,
                           const EngineWriteOptions& o, Metadata& delivered);
void read_prefiltered_and_sh(const bake_read::Field& manifest, preview::BakeFiles& b);
void read_charlie_chain(const bake_read::Field& manifest, preview::BakeFiles& b);

}  // namespace brdfbake::detail::engines::generic
