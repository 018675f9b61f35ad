// Internal: an environment as the scalar reference sees it, shared by the environment families'
// reference adapters (families/prefilter/reference.cpp, families/irradiance/reference.cpp).
#pragma once

#include "brdfbake/environment.hpp"
#include "brdfbake/reference/envmap.hpp"

namespace brdfbake::detail {

// `env` as a reference cube of face size `size`: a cube of that size as it is (its floats in
// double); another cube resampled, or an equirect converted, by the reference's brute force
// (reference::cube_resample, reference::equirect_to_cube): every texel the solid-angle-weighted mean
// of the source's bilinear interpolation over its footprint. Rounded to float like a stored level.
reference::EnvCube reference_source_cube(const EnvImage& env, int size);
// The sub-cells per texel side that conversion uses (for the work estimate and the metadata).
int reference_conversion_subdivision(const EnvImage& env, int size);
// A reference cube as level 0 of a CubeLevels (RGBA float, alpha 1), and back.
std::vector<float> to_rgba(const reference::EnvCube& cube);
reference::EnvCube to_reference_cube(const std::vector<float>& rgba, int size);

}  // namespace brdfbake::detail
