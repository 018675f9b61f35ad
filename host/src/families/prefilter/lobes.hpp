// Internal: the prefiltered levels' lobes as the engine evaluates them on the host (the sample
// tables and thresholds it ships to kernels/prefilter.cl). The engine's own code, independent of the
// reference's (host/reference/src/envmap.cpp), so that tests/device/test_prefilter.cpp can catch a
// mistake on either side.
#pragma once

#include "brdfbake/environment.hpp"

namespace brdfbake::detail {

// D of the level's distribution at a half vector with cosine n_dot_h (zero below the horizon):
// GGX, Walter et al. 2007 eq. 33, D = alpha^2 / (pi (alpha^2 cos^2 + sin^2)^2); Charlie, Estevez &
// Kulla 2017, D = (2 + 1/alpha) sin^(1/alpha) / (2 pi). alpha floored at math::kMinAlpha.
double env_lobe_d(EnvDistribution distribution, double n_dot_h, double alpha);
// The level's filter kernel with n = v = R (Karis 2013) as a function of c = R.l:
// K = D(h) (n.l)+ with n.h = sqrt((1 + c) / 2), n.l = c.
double env_lobe_kernel(EnvDistribution distribution, double alpha, double cos_rl);
// W = the integral of K over the sphere, in closed form: GGX in the CDF variable of its normals,
// Charlie as a Beta integral (env_lobes.cpp derives both).
double env_lobe_normalization(EnvDistribution distribution, double alpha);

}  // namespace brdfbake::detail
