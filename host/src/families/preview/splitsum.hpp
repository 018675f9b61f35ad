// Internal: the split-sum render, what a target engine's shader computes from a bake's files
// (docs/ENGINES.md, "What the preview emulates", cites the function each step reproduces): its LOD
// from roughness, trilinear seamless sampling of the stored cube levels (decoded as the GPU sees
// them: bake_files.hpp), the DFG table at its stored size by bilinear lookup (clamp to edge, texel
// centres), its multiple-scattering compensation, and its diffuse term. In fp32, as a shader.
// What the targets share is splitsum_sampling.hpp; each target's shading is its folder's
// host/src/engines/<target>/splitsum.cpp, found through the registry (TargetDef::shading).
#pragma once

#include <string>

#include "brdfbake/preview.hpp"
#include "families/preview/bake_files.hpp"
#include "families/preview/splitsum_sampling.hpp"

namespace brdfbake::detail::preview {

class SplitSum {
 public:
  explicit SplitSum(BakeFiles files, SplitSumOptions options = {});
  // The radiance towards v (unit, from the surface to the viewer) of a surface of normal n.
  // normal_slope2: the squared screen-space derivative of the normal, max(|dn/dx|^2, |dn/dy|^2) per
  // pixel, which Babylon.js's specular anti-aliasing adds to alphaG (the `gltf` target: its loader
  // turns it on); 0 for none.
  Rgb shade(const Vec3& n, const Vec3& v, const PreviewMaterial& m, float normal_slope2 = 0.0f) const;
  // Level 0 of the chain in direction d (the background: the engine's skybox).
  Rgb sky(const Vec3& d) const;
  // What each step does for this target and which shader function it is, for the JSON.
  Metadata steps() const;
  const BakeFiles& files() const { return sampler_.files; }
  // Whether this target's split-sum render renders KHR_materials_sheen from this bake, and what it
  // does (or why not), for the notes of a sheened sphere and the JSON's steps.
  bool renders_sheen() const;
  std::string sheen_note() const;

 private:
  SplitSumSampler sampler_;
  const SplitSumShading* shading_ = nullptr;  // the target's row (engines/registry.hpp)
};

}  // namespace brdfbake::detail::preview
