// The prefilter's sampling estimator: the lobe samples of a level (Hammersley points through the
// distribution's inverse CDF, with filtered importance sampling's lod) and its default count.
#include <cmath>
#include <vector>

#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/sampling.hpp"
#include "env/cube.hpp"
#include "families/prefilter/lobes.hpp"
#include "families/prefilter/model.hpp"

namespace brdfbake {

using math::kPi;

// The lobe samples of one level in the frame (t, b, R), as the arrays x, y, z, weight, lod_k
// (kernels/prefilter.cl): N Hammersley points, h from D(h) (n.h), l = 2 (n.h) h - n, kept when
// n.l > 0, padded to a multiple of the vector width with weight 0.
std::vector<double> detail::lobe_samples(EnvDistribution dist, double alpha, int n, int source_size, bool fis,
                                         double lod_bias, int* kept) {
  std::vector<double> x, y, z, w, lod;
  const double omega_texel = (2.0 / source_size) * (2.0 / source_size);
  for (int k = 0; k < n; ++k) {
    const math::Point2 u = math::hammersley(static_cast<uint32_t>(k), static_cast<uint32_t>(n));
    const double u1 = u.u, u2 = u.v;
    double cos_h, sin_h;
    if (dist == EnvDistribution::Ggx) {  // Walter et al. 2007, eq. 35: tan^2 = alpha^2 u / (1 - u)
      const double t2 = alpha * alpha * u1 / (1.0 - u1);
      cos_h = 1.0 / std::sqrt(1.0 + t2);
      sin_h = std::sqrt(t2) * cos_h;
    } else {  // Estevez & Kulla 2017: sin = u^(alpha / (2 alpha + 1))
      sin_h = std::pow(u1, alpha / (2.0 * alpha + 1.0));
      cos_h = std::sqrt(std::max(0.0, (1.0 - sin_h) * (1.0 + sin_h)));
    }
    const double phi = 2.0 * kPi * u2;
    const double lz = 2.0 * cos_h * cos_h - 1.0;
    if (lz <= 0.0) continue;
    const double d = env_lobe_d(dist, cos_h, alpha);
    // p(l) = D / 4 (dl = 4 (n.h) dh with v = n); the sample covers 1 / (N p) = 4 / (N D)
    const double omega_sample = 4.0 / (n * d);
    x.push_back(2.0 * cos_h * sin_h * std::cos(phi));
    y.push_back(2.0 * cos_h * sin_h * std::sin(phi));
    z.push_back(lz);
    w.push_back(lz);
    // without filtered importance sampling every sample reads level 0, wherever it lands on the
    // face (a lod far below 0 survives the kernel's texel-size correction and clamps to 0)
    lod.push_back(fis ? 0.5 * std::log2(omega_sample / omega_texel) + lod_bias : -1e3);
  }
  *kept = static_cast<int>(x.size());
  while (x.size() % kEnvVectorWidth != 0 || x.empty()) {
    x.push_back(0.0);
    y.push_back(0.0);
    z.push_back(1.0);
    w.push_back(0.0);
    lod.push_back(0.0);
  }
  std::vector<double> out;
  for (const auto* v : {&x, &y, &z, &w, &lod}) out.insert(out.end(), v->begin(), v->end());
  return out;
}

// The sampling estimator's default lobe samples per texel: its error is the mip blur of filtered
// importance sampling, which falls like 1/N (docs/BENCHMARKS.md: about 1-5% RMS at 1024 on the 256^2
// chain); the quadrature is the default estimator.
int detail::default_prefilter_samples(int level, int levels) {
  (void)level;
  (void)levels;
  return 1024;
}

}  // namespace brdfbake
