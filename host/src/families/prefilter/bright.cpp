// The bright texels in the filter: how finely each one's footprint is subdivided for a level's lobe,
// and the merged points the strips kernel reads away from a texel's horizon.
#include <algorithm>
#include <cmath>
#include <vector>

#include "families/prefilter/model.hpp"

namespace brdfbake {

// Sub-cells per texel side of the bright texels' footprints (bright_texel_points): enough to resolve
// the lobe (4 texels across its width: 2 alpha for GGX, 1 rad for Charlie's ring), and 4 where the
// kernel's kink at the horizon matters (Charlie; GGX with K'(0) / K(1) = 4 alpha^4 / (1 + alpha^2)^2
// > 1e-3), so that a bright texel at a texel's horizon is cut where the reference cuts it; at most
// kMaxBrightPoints points in all.
namespace {
constexpr int kMaxBrightPoints = 4096;
}  // namespace

// The lobe's part alone: what a bright texel needs away from a texel's horizon (the strips kernel
// takes these "coarse" points there and the full subdivision only near the horizon).
int detail::bright_lobe_subdivision(EnvDistribution dist, double alpha, int source_size) {
  const double width = dist == EnvDistribution::Ggx ? 2.0 * alpha : 1.0;
  return static_cast<int>(std::clamp(std::ceil(4.0 * (2.0 / source_size) / width), 1.0, 4.0));
}
// Whether one point a bright texel resolves the lobe: the tent's whole support (2 texels, 4 / S in
// face coordinates) at most a quarter of the lobe's width.
bool detail::bright_single_point(EnvDistribution dist, double alpha, int source_size) {
  const double width = dist == EnvDistribution::Ggx ? 2.0 * alpha : 1.0;
  return 4.0 * (4.0 / source_size) <= width;
}
// Groups of `per` points (one bright texel's, bright_texel_points' layout with SoA stride `stride`)
// merged into one each: the sum of their values at their weighted mean direction (the weights,
// proportional to the sub-cells' solid angles within a texel, are the values' sums).
std::vector<double> detail::merge_bright_points(const std::vector<double>& pts, size_t stride, size_t per,
                                                size_t texels) {
  const size_t n = std::max<size_t>(texels, 1);
  std::vector<double> out(6 * n, 0.0);
  if (texels == 0) out[2] = 1.0;  // a padding point as bright_texel_points leaves it
  for (size_t t = 0; t < texels; ++t) {
    double d[3] = {0, 0, 0}, v[3] = {0, 0, 0};
    for (size_t k = t * per; k < (t + 1) * per; ++k) {
      const double w = pts[3 * stride + k] + pts[4 * stride + k] + pts[5 * stride + k];
      for (size_t c = 0; c < 3; ++c) {
        d[c] += w * pts[c * stride + k];
        v[c] += pts[(3 + c) * stride + k];
      }
    }
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (size_t c = 0; c < 3; ++c) {
      out[c * n + t] = len > 0.0 ? d[c] / len : pts[c * stride + t * per];
      out[(3 + c) * n + t] = v[c];
    }
  }
  return out;
}

int detail::bright_subdivision(EnvDistribution dist, double alpha, int source_size, size_t bright) {
  double q = bright_lobe_subdivision(dist, alpha, source_size);
  const double a4 = alpha * alpha * alpha * alpha;
  if (dist == EnvDistribution::Charlie || 4.0 * a4 / ((1.0 + alpha * alpha) * (1.0 + alpha * alpha)) > 1e-3) q = 4.0;
  q = std::min(q, std::floor(std::sqrt(double(kMaxBrightPoints) / (4.0 * double(std::max<size_t>(bright, 1))))));
  return static_cast<int>(std::clamp(q, 1.0, 4.0));
}

}  // namespace brdfbake
