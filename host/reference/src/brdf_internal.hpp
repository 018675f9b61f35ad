// Internal to the reference: the evaluation of a model from a prepared geometry, shared by
// brdf() and the albedo integrator (which builds the geometry from an exact half vector).
#pragma once

#include "brdfbake/reference/brdf.hpp"

namespace brdfbake::reference {

// What every model needs of a (wi, wo) pair strictly above the horizon.
struct BrdfGeometry {
  Vec3 l, v, h;   // unit light, view and half vectors
  double nl, nv;  // cosines with the normal, floored at kBrdfMinCosine
  double nh;      // n.h
  double lh;      // l.h = v.h, in [0, 1]
};

Rgb brdf_at(BrdfModel model, const BrdfMaterial& m, const BrdfGeometry& g);

}  // namespace brdfbake::reference
