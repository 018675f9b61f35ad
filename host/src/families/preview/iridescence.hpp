// Internal: KHR_materials_iridescence in the preview (docs/PREVIEW.md, "The BRDF"; docs/ENGINES.md,
// "KHR_materials_iridescence"): the films the reference integrates for a material, the split-sum
// render's thin-film Fresnel as the engines' shaders evaluate it (fp32), and what each target does
// with the lobe, for the spheres' notes.
#pragma once

#include <string>

#include "brdfbake/engines.hpp"
#include "brdfbake/preview.hpp"

namespace brdfbake::detail::preview {

// The thin-film Fresnel as the glTF-Sample-Viewer's iridescence.glsl evalIridescence (and Babylon.js's
// pbrBRDFFunctions.fx evalIridescence, the same formulation: the KHR_materials_iridescence
// specification's) computes it, in fp32 as a shader: a film of index film_ior and thickness (nm) over
// a base of F0 base_f0, seen from a medium of index outside_ior at incidence cos1.
void eval_iridescence(float outside_ior, float film_ior, float cos1, float thickness, const float base_f0[3],
                      float out[3]);

// The Sample Viewer's Schlick_to_F0(f, f90 = 1, VdotH) (functions.glsl): the F0 whose Schlick Fresnel
// at VdotH is f, with (1 - VdotH)^5 clamped to 0.9999.
float schlick_to_f0(float f, float v_dot_h);

// The split-sum render's film for a material at n.v over the engine's F0 (base_f0): false where the
// material has none (iridescence 0, or a film 0 nm thick: the Sample Viewer zeroes the factor then);
// else the factor and the thin-film Fresnel evalIridescence(1, iridescenceIor, n.v, thickness, F0).
bool split_sum_film(const PreviewMaterial& m, float n_dot_v, const float base_f0[3], float* factor, float fresnel[3]);

// The reference's films (the extension's dielectric_brdf and metal_brdf): the dielectric's over its
// own F0 (preview_dielectric_f0), weighted (1 - metallic) specular, and the metal's over base_color,
// weighted metallic; a weight of 0 has no film.
struct ReferenceFilms {
  double dielectric_weight = 0.0, metal_weight = 0.0;
  Rgb dielectric_f0{0.0, 0.0, 0.0}, metal_f0{0.0, 0.0, 0.0};
};
ReferenceFilms reference_films(const PreviewMaterial& m);

// Whether the target's split-sum render renders the film, and the sphere's note saying what it does.
bool split_sum_renders_iridescence(EngineTarget target);
std::string iridescence_note(EngineTarget target);

}  // namespace brdfbake::detail::preview
