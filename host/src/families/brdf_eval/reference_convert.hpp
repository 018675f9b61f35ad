// Internal: the public API's BRDF parameters in the scalar reference's own types (the reference
// keeps separate types so that it depends on nothing of the product; see brdfbake/reference/brdf.hpp).
// Used by the reference adapter (families/brdf_eval/reference.cpp) and by tests that evaluate the oracle
// for a public Material.
#pragma once

#include "brdfbake/brdf.hpp"
#include "brdfbake/reference/brdf.hpp"

namespace brdfbake::detail {

reference::BrdfModel to_reference(BrdfModel model);
reference::MicrofacetDistribution to_reference(MicrofacetDistribution distribution);
// Field by field; tests/device/test_brdf_eval.cpp checks that every field reaches the reference.
reference::BrdfMaterial to_reference(const Material& material);

}  // namespace brdfbake::detail
