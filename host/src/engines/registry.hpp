// Internal: the engine targets, one folder each (docs/ENGINES.md, "Adding a target"). A target's
// folder host/src/engines/<target>/ holds its descriptor (descriptor.cpp: what the engine loads and
// how, EngineSettings), its writer (writer.cpp: the file set as the engine's own tool writes it) and
// the preview's reader (reader.cpp: the files as the engine's loader reads them) and its split-sum shading
// (splitsum.cpp: the engine's shader functions, on what families/preview/splitsum_sampling.hpp shares); registry.cpp
// lists the targets and is the only other file that names one. The shared parts: write_common (the folder, storage
// errors, RGBD faces, KTX2 chains), bake_read (checked reads of a bake folder), babylon_frame (Babylon.js's rows and
// frame) and filament_dfg (Filament's built-in DFG table).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "brdfbake/engines.hpp"
#include "engines/bake_read.hpp"

namespace brdfbake::detail::preview {
struct BakeFiles;
struct SplitSumShading;
}  // namespace brdfbake::detail::preview

namespace brdfbake::detail::engines {

// One file of a target's set, encoded in memory (write_common.cpp writes the set atomically).
struct OutFile {
  OutFile(std::string n, std::vector<uint8_t> b, std::shared_ptr<const CubeLevels> v = nullptr, int l = -1, int f = -1)
      : name(std::move(n)), bytes(std::move(b)), values(std::move(v)), level(l), face(f) {}
  std::string name;
  std::vector<uint8_t> bytes;
  // The float values the file encodes (its delivered error is measured against them when the file is
  // decoded, write_common.cpp): a cube file's whole chain, or one face image (`level`, `face`).
  std::shared_ptr<const CubeLevels> values;
  int level = -1, face = -1;
};

struct TargetDef {
  EngineTarget target;
  const char* name;
  // descriptor.cpp: everything the target fixes
  EngineSettings (*settings)();
  // writer.cpp: the file set, named from `name`, of a bake already checked against the settings
  std::vector<OutFile> (*write)(const EngineSettings& s, const EngineBake& bake, const std::string& name,
                                const EngineWriteOptions& o, Metadata& delivered);
  // reader.cpp: the specular chain and the diffuse source the engine samples, from the folder's
  // manifest (`b.folder`, `b.target` set); and, where the engine has one, the Charlie chain of its
  // sheen (nullptr: none) and the DFG table it samples instead of the bake's (nullptr: the bake's).
  void (*read)(const bake_read::Field& manifest, preview::BakeFiles& b);
  void (*read_sheen_chain)(const bake_read::Field& manifest, preview::BakeFiles& b) = nullptr;
  void (*engine_dfg)(preview::BakeFiles& b) = nullptr;
  // splitsum.cpp: the preview's split-sum shading, the engine's shader on those files (splitsum_sampling.hpp)
  const preview::SplitSumShading& (*shading)() = nullptr;
  // what the writer takes: the irradiance SH (every target but khronos-viewer, whose diffuse light is
  // a cube), ASTC HDR chains (the KTX2 targets)
  bool needs_sh = true;
  bool astc = false;
};

// Every target, in the order `engine_target_names()` lists them.
const std::vector<const TargetDef*>& targets();
const TargetDef& target_def(EngineTarget target);

// The face order and orientation every cube file of the targets shares (EngineSettings::orientation).
std::string opengl_faces_text();

// Each target's definition (its folder's descriptor.cpp).
const TargetDef& generic_target();
const TargetDef& filament_target();
const TargetDef& gltf_target();
const TargetDef& babylon_target();
const TargetDef& khronos_viewer_target();

}  // namespace brdfbake::detail::engines
